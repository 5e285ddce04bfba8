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


def _needle(angle, width, shift):
    """A closed needle: out along one leg, a short tip, back along the other,
    ``width`` apart (the out leg on the right of the back one), rotated and shifted."""
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    pts = [(0.0, 0.0), (-0.1, -width), (89.3, -width), (89.4, 0.0)]
    pts = [tuple(rot @ np.array(p) + shift) for p in pts]
    return [pc.line(pts[i], pts[(i + 1) % 4]) for i in range(4)], rot


def _heights(tg, rot, pieces_of_leg, s):
    """Height across the needle of the rounded polyline along the given pieces, at
    distances s along it (linear between its vertices)."""
    sel = np.isin(tg.piece, pieces_of_leg)
    a, b = tg.to_float(tg.q[sel]), tg.to_float(tg.q[tg.nxt[sel]])
    a, b = a @ rot, b @ rot  # back to the needle's frame
    out = np.full(len(s), np.nan)
    for (x0, y0), (x1, y1) in zip(a, b):
        lo, hi = min(x0, x1), max(x0, x1)
        m = (s >= lo) & (s <= hi) & (hi > lo)
        out[m] = y0 + (s[m] - x0) / (x1 - x0) * (y1 - y0)
    return out


def test_legs_closer_than_the_grid_keep_their_order():
    """Two legs of a needle closer than a grid step, whose ends round independently,
    must not swap sides (the needle's inside would change winding: an open crack in
    a filled region, as in amiri uniFDB3 + uniFCE4): rounded through the same hot
    pixels they coincide or keep their order, at every angle and offset."""
    rng = np.random.default_rng(7)
    grid = 0.014
    s = np.linspace(1.0, 88.0, 400)
    swapped = 0
    for _ in range(60):
        loop, rot = _needle(rng.uniform(0, 2 * np.pi), 10.0 ** rng.uniform(-5, -2.5),
                            rng.uniform(-1, 1, 2))
        tg = tag_loops([loop], 1e-3, grid)
        out, back = _heights(tg, rot, [1], s), _heights(tg, rot, [3], s)
        swapped += np.any(out > back + 1e-9)
        # every vertex still within half a grid diagonal of its own piece
        pts = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
        assert np.abs(tg.to_float(tg.q) - pts).max() <= grid * np.sqrt(2) + 1e-9
    assert swapped == 0


def test_pixel_crossing_test_agrees_with_shapely():
    """The hot-pixel test (segment box overlaps the unit square and the line passes
    closer than |d_x|/2 + |d_y|/2 across) against shapely's segment-square
    intersection, on random segments and pixels (touching cases excluded: measure
    zero)."""
    import shapely

    from morph.trim.flatten import _line_crosses_square

    rng = np.random.default_rng(3)
    a = rng.uniform(-3, 3, (4000, 2))
    b = a + rng.normal(0, 2, (4000, 2)) * rng.choice([0.1, 1.0, 5.0], (4000, 1))
    c = np.rint(rng.uniform(-4, 4, (4000, 2)))
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    boxes = np.all((lo < c + 0.5) & (hi > c - 0.5), axis=1)
    ours = boxes & _line_crosses_square(a, b, c)
    lines = shapely.linestrings(np.stack([a, b], axis=1))
    squares = shapely.box(c[:, 0] - 0.5, c[:, 1] - 0.5, c[:, 0] + 0.5, c[:, 1] + 0.5)
    theirs = shapely.intersects(lines, squares)
    assert 200 < theirs.sum() < 3800  # both outcomes well represented
    assert np.array_equal(ours, theirs)


def test_segment_ranges_end_near_their_next_vertex_with_hot_pixels():
    # loops that meet at joints one grid unit apart (a piece ending beside another's
    # start: hot pixels put vertices on segments at their start, with the start's
    # parameter).  Every segment's range [t0, t1] must map near its two vertices; a
    # vertex sharing its successor's parameter was given t1 = 1 (a whole piece for a
    # one-unit edge: EB Garamond w + i lifted a spike 15 tol long)
    rng = np.random.default_rng(8)
    eps, grid = 1e-3, 1e-2
    checked = 0
    for _ in range(40):
        c = rng.uniform(-1, 1, 2)
        a = rng.uniform(0, 2 * np.pi)
        d = np.array([np.cos(a), np.sin(a)])
        n = np.array([-d[1], d[0]])
        off = rng.uniform(0.3, 1.2) * grid * n   # the second loop's joint one unit away
        p0, p1, p2 = c - 3 * d, c, c + 3 * d + 2 * n
        loops = [[pc.line(p0, p1), pc.quadratic(p1, p1 + 2 * d - n, p2), pc.line(p2, p0)],
                 [pc.line(p1 + off, p1 + off + 3 * n), pc.line(p1 + off + 3 * n, p1 + off - 3 * d),
                  pc.line(p1 + off - 3 * d, p1 + off)]]
        tg = tag_loops(loops, eps, grid)
        x0 = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
        x1 = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t1)])
        reach = eps + grid
        assert np.hypot(*(x0 - tg.to_float(tg.q)).T).max() <= reach
        assert np.hypot(*(x1 - tg.to_float(tg.q[tg.nxt])).T).max() <= reach
        checked += int(np.sum(tg.t0 == tg.t0[tg.nxt]))
    assert checked > 0   # vertices sharing a parameter occurred
