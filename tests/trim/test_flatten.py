"""morph.trim.flatten: tagged flattening on the integer grid, against the exact pieces."""

import numpy as np

from morph import piece as pc
from morph.trim.flatten import tag_loops


def test_tags_lie_on_their_pieces():
    loop = list(pc.circle((3.0, -2.0), 5.0)) + []
    eps, grid = 1e-3, 1e-3
    tg = tag_loops([loop], eps, grid)
    pts = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
    assert np.abs(tg.to_float(tg.q) - pts).max() <= grid / np.sqrt(2) + 1e-12
    # every segment's middle is within eps + grid of the circle (flattening bound)
    mid = tg.to_float(0.5 * (tg.q + tg.q[tg.nxt]))
    r = np.hypot(mid[:, 0] - 3.0, mid[:, 1] + 2.0)
    assert np.abs(r - 5.0).max() <= eps + grid
    # segment parameter ranges tile every piece
    for k in range(len(loop)):
        sel = tg.piece == k
        assert tg.t0[sel].min() == 0.0 and tg.t1[sel].max() == 1.0


def test_pieces_shorter_than_the_grid_vanish_but_loops_stay_closed():
    p = [(0, 0), (1, 0), (1, 1e-9), (1, 1), (0, 1)]
    loop = [pc.line(p[i], p[(i + 1) % 5]) for i in range(5)]
    tg = tag_loops([loop], 1e-4, 1e-4)
    assert len(tg.q) == 4 and 1 not in set(tg.piece.tolist())
