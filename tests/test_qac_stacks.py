"""The pieces of accepted QAC nodes built on arrays (morph.qac.piece_stacks, the
driver's stacked mode) against the same pieces built row by row.

The nodes are those Algorithm 4.1 accepts on real convolutions (Relief skeleton
glyphs with the broad and the round nib: polynomial cubics with rational conics,
both roles), with the kinds of some rows changed to corners and chords (the
constructions are defined for any pair) and one row whose tangent numerator
vanishes at an end (its own, lower-degree group).  The reference is the one-row
code: ``_corner_piece``, ``chord_piece``, ``convolve_qac_piece`` (None where a
weight is <= 0), reversed where C1 = cb runs against ca.
"""

from pathlib import Path

import numpy as np
import pytest

from morph import convolve, qac
from morph import piece as pc
from morph.budget import plan
from morph.nib import ellipse_nib
from morph.parse.ufo import decomposed_paths, load_ufo
from morph.stroke import stroke_many

RELIEF = Path(__file__).parent / "data" / "relief" / "Relief-SingleLine-subset.ufo"


def _row_piece(nodes, r):
    """The piece of node r as the one-row functions make it (None: rejected)."""
    ca, cb, sa, sb = nodes["ca"][r], nodes["cb"][r], nodes["sa"][r], nodes["sb"][r]
    kind, swap = nodes["kind"][r], bool(nodes["swap"][r])
    if kind == qac.CORNER:
        return qac._corner_piece(ca, cb, sa, sb, swap)
    if kind == qac.CHORD:
        return qac.chord_piece(ca, cb, sa, sb)[0]
    piece = qac.convolve_qac_piece(cb if swap else ca, None, nodes["q2"][r])
    if not np.all(piece[:, 2] > 0):
        return None
    return pc.reverse(piece) if (swap and sa != sb) else piece


@pytest.fixture(scope="module")
def accepted():
    """The accepted node batches of the convolutions of a few Relief glyphs with
    the broad and the round nib (every batch the driver returned)."""
    font = load_ufo(RELIEF, lazy=False)
    sets = [decomposed_paths(font, n) for n in ("a", "S", "g", "eight")]
    batches = []
    real = convolve.subdivide_nodes
    try:
        def keep(*args, **kwargs):
            out = real(*args, **kwargs)
            batches.append(out[0])
            return out

        convolve.subdivide_nodes = keep
        for nib in (ellipse_nib(45.0, 10.0, 30.0), ellipse_nib(30.0, 30.0, 0.0)):
            stroke_many(sets, nib, plan(0.5)[0])
    finally:
        convolve.subdivide_nodes = real
    return batches


def _varied(nodes, seed):
    """The nodes with a third of the rows made corners, a sixth chords, roles
    mixed on those, and one QAC row's C1 given a zero end tangent."""
    rng = np.random.default_rng(seed)
    out = {k: np.array(v) for k, v in nodes.items()}
    pick = rng.random(len(out["kind"]))
    out["kind"] = np.where(pick < 1 / 3, qac.CORNER, np.where(pick < 0.5, qac.CHORD, qac.QAC))
    other = out["kind"] != qac.QAC
    out["swap"] = np.where(other, rng.random(len(pick)) < 0.5, out["swap"])
    r = np.flatnonzero((out["kind"] == qac.QAC) & ~out["swap"])[0]
    out["ca"][r, 1] = out["ca"][r, 0]   # a cubic whose tangent numerator vanishes at t = 0
    return out


def _same(a, b):
    if a is None or b is None:
        return a is None and b is None
    return a.shape == b.shape and np.allclose(pc.cartesian(a), pc.cartesian(b), atol=1e-9) \
        and np.allclose(a[:, 2] / a[0, 2], b[:, 2] / b[0, 2], rtol=1e-9)


def test_piece_stacks_match_rows(accepted):
    kinds = set()
    for k, nodes in enumerate(accepted):
        for case in (nodes, _varied(nodes, k)):
            ok, groups = qac.piece_stacks(case)
            got = [None] * len(ok)
            for rows, stack in groups:
                assert stack.ndim == 3 and len(rows) == len(stack)
                for r, piece in zip(rows.tolist(), stack):
                    assert got[r] is None      # each node in one group
                    got[r] = piece
            for r in range(len(ok)):
                want = _row_piece(case, r)
                assert _same(got[r], want), (k, r, case["kind"][r], case["swap"][r])
                assert ok[r] == (want is not None)
                kinds.add((int(case["kind"][r]), bool(case["swap"][r]),
                           pc.is_polynomial(case["cb" if case["swap"][r] else "ca"][r])))
            assert qac.piece_nodes(case)[0] is got[0] or _same(qac.piece_nodes(case)[0],
                                                                 got[0])
    # corners and QAC pieces in both roles, polynomial and rational C1
    assert {(qac.CORNER, False), (qac.CORNER, True), (qac.CHORD, False),
            (qac.QAC, False), (qac.QAC, True)} <= {(k, s) for k, s, _ in kinds}
    assert {True, False} <= {p for k, _, p in kinds if k == qac.QAC}


def test_piece_stacks_detect_a_wrong_role(accepted):
    """The comparison can fail: corners built with the other role differ."""
    nodes = _varied(accepted[0], 0)
    wrong = dict(nodes, swap=~nodes["swap"])
    ok, groups = qac.piece_stacks(wrong)
    rows = np.flatnonzero(nodes["kind"] == qac.CORNER)
    got = {}
    for rs, stack in groups:
        got.update(zip(rs.tolist(), stack))
    assert sum(not _same(got.get(r), _row_piece(nodes, r)) for r in rows) > len(rows) // 2


def test_driver_stacked_matches_lists(accepted):
    """subdivide_nodes with the stacked pieces gives the nodes, errors and pieces
    (in order) of its list mode."""
    from morph.subdivide import subdivide_nodes

    roots = {k: v for k, v in accepted[0].items() if k not in ("kind", "swap", "q2", "depth")}
    roots["tol"] = np.full(len(roots["ca"]), 1e-3)   # finer: more levels
    args = (qac.bound_nodes, qac.split_nodes, 1e-3, 24)
    d1, p1, e1 = subdivide_nodes(roots, qac.piece_nodes, *args)
    d2, p2, e2 = subdivide_nodes(roots, qac.piece_stacks, *args, stacked=True)
    assert len(p1) == len(p2) == len(d1["lo"]) > len(roots["lo"])
    assert np.array_equal(e1, e2) and np.array_equal(d1["lo"], d2["lo"])
    assert all(np.array_equal(a, b) for a, b in zip(p1, p2))
