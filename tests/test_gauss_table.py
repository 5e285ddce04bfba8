"""The batched Gauss maps and convolution on arrays (morph.gauss.gauss_table,
morph.convolve.ConvPieces) against the one-object-per-edge / per-piece path they
replace: the same numbers, to the bit, in the same order.

The reference (:func:`_reference_maps`) is the Edge-list construction: each piece
split by ``split_monotone_many`` (a list per piece), the angles lifted with
numpy's ``_wrap`` loop by loop, an :class:`morph.gauss.Edge` per edge; the edge
tables are compared with the list constructor of ``_EdgeTable``; the convolution
with the pieces of each compatible pair computed alone (``convolve_edges``).
"""

import numpy as np
import pytest

from morph import convolve
from morph import gauss
from morph import parse
from morph import piece as pc
from morph.fonts.brush import ellipse_nib
from morph.stroke import _loops_and_dots_many


def _stroke_loops():
    """Skeleton loops (open paths traced out and back: open cusps at both ends,
    turn-backs, a closed path)."""
    paths = [
        ([pc.line((0, 0), (100, 0)), pc.line((100, 0), (100, 80)),
          pc.line((100, 80), (20, 200))], False),
        ([pc.cubic((0, 0), (40, 90), (120, 90), (160, 0)), pc.line((160, 0), (10, 5))], False),
        ([pc.quadratic((0, 0), (50, 100), (100, 0)), pc.line((100, 0), (0, 0))], True),
        ([pc.line((5, 5), (200, 40))], False),
    ]
    loops, _, _ = _loops_and_dots_many([paths], ellipse_nib(30, 8, 30))
    return list(loops[0])


def _regions():
    g = list(parse.glyph_region("g").region)
    amp = list(parse.glyph_region("ampersand", parse.cubic_test_font_path()).region)
    return {"glyph g": g, "cff ampersand": amp, "stroke": _stroke_loops(),
            "mixed": g + _stroke_loops() + [pc.circle((3.0, -1.0), 2.0)]}


def _np_wrap(a):
    return a - gauss.TWO_PI * np.ceil((a - np.pi) / gauss.TWO_PI)


def _reference_maps(loops, angle_tol=1e-10):
    """The Edge lists as they were built: one list of parts per piece, numpy's
    wrap, an Edge per edge (the turns at the joins from the shared cusp code)."""
    parts = gauss.split_monotone_many([p for loop in loops for p in loop])
    curves, counts, k = [], [], 0
    for loop in loops:
        own = [q for ps in parts[k:k + len(loop)] for q in ps]
        curves += own
        counts.append(len(own))
        k += len(loop)
    counts = np.array(counts)
    first, last = pc.end_tangents_many(curves)
    a0 = np.arctan2(first[:, 1], first[:, 0])
    sweep = _np_wrap(np.arctan2(last[:, 1], last[:, 0]) - a0)
    sweep = np.where(np.abs(sweep) < angle_tol, 0.0, sweep)
    turns = gauss._corner_turns_many(pc.Pieces.of(curves), counts, a0, sweep, last)
    starts, ends = pc.end_points(curves)
    a0, sweep, turns = a0.tolist(), sweep.tolist(), turns.tolist()
    out, lo = [], 0
    for n in counts.tolist():
        edges, theta = [], a0[lo]
        for i in range(lo, lo + n):
            if i > lo:
                theta = theta + _np_wrap(a0[i] - theta)
            edges.append(gauss.Edge("curve", curves[i], starts[i], theta, sweep[i]))
            theta = theta + sweep[i]
            if abs(turns[i]) >= angle_tol:
                edges.append(gauss.Edge("vertex", None, ends[i], theta, turns[i]))
                theta = theta + turns[i]
        out.append(edges)
        lo += n
    return out


def _same_edges(a, b):
    assert len(a) == len(b)
    for ma, mb in zip(a, b):
        assert len(ma) == len(mb)
        for ea, eb in zip(ma, mb):
            assert ea.kind == eb.kind
            assert float(ea.theta) == float(eb.theta) and float(ea.sweep) == float(eb.sweep)
            assert np.asarray(ea.point).tobytes() == np.asarray(eb.point).tobytes()
            if ea.kind == "curve":
                assert np.asarray(ea.piece, float).tobytes() == \
                    np.asarray(eb.piece, float).tobytes()


@pytest.mark.parametrize("name", ["glyph g", "cff ampersand", "stroke", "mixed"])
def test_gauss_table_is_the_edge_lists(name):
    loops = _regions()[name]
    table = gauss.gauss_table(loops)
    _same_edges(table.maps(), _reference_maps(loops))
    # and each loop alone gives its part of the batch
    _same_edges(table.maps(), [gauss.gauss_map(loop) for loop in loops])


def test_monotone_parts_are_split_monotone_many():
    loops = _regions()["mixed"]
    pieces = [p for loop in loops for p in loop]
    parts, owner = gauss._monotone_parts(pc.Pieces.of(pieces))
    ref = gauss.split_monotone_many(pieces)
    flat = [q for ps in ref for q in ps]
    assert len(parts) == len(flat) > len(pieces)      # some pieces are cut
    assert np.array_equal(owner, np.repeat(np.arange(len(pieces)), [len(ps) for ps in ref]))
    for a, b in zip(parts.rows(), flat):
        assert a.tobytes() == b.tobytes()


def test_moved_is_translate():
    pieces = [p for loop in _regions()["mixed"] for p in loop]
    off = np.random.default_rng(3).normal(scale=100.0, size=(len(pieces), 2))
    moved = gauss._moved(pc.Pieces.of(pieces), off)
    for a, p, o in zip(moved.rows(), pieces, off):
        assert a.tobytes() == pc.translate(p, o).tobytes()


def _table_arrays(t):
    return {k: getattr(t, k) for k in ("loop", "index", "theta", "sweep", "lo", "hi", "sign",
                                       "point", "vertex", "straight", "curved", "deg",
                                       "slot", "h")}


@pytest.mark.parametrize("name", ["glyph g", "stroke", "mixed"])
def test_edge_table_of_gauss_is_the_list_constructor(name):
    g = gauss.gauss_table(_regions()[name])
    fast, ref = convolve._EdgeTable.of_gauss(g), convolve._EdgeTable(g.maps())
    for key, a in _table_arrays(fast).items():
        b = getattr(ref, key)
        assert a.shape == b.shape and a.tobytes() == np.asarray(b, a.dtype).tobytes(), key
    assert sorted(fast.stacks) == sorted(ref.stacks)
    for d in fast.stacks:
        assert fast.stacks[d].tobytes() == ref.stacks[d].tobytes()


@pytest.mark.parametrize("name", ["glyph g", "stroke", "mixed"])
def test_crossing_rows_from_tables_and_from_lists(name):
    a, b = _regions()[name], ellipse_nib(30, 8, 30)
    fast = convolve.with_pair_table(convolve.gauss_pair_of(a, b))
    lists = convolve.GaussPair(fast.maps_a, fast.maps_b, fast.table)
    for reach in (1e-3, 5.0):
        assert np.array_equal(convolve.crossing_rows(fast, reach),
                              convolve.crossing_rows(lists, reach))


def test_stroke_convolution_is_the_pairs_one_by_one():
    """Every piece of a stroke's convolution is the piece of its pair computed
    alone (translations to the bit), in the table's order, with its kind, row, type
    and source."""
    a, b = _regions()["stroke"], ellipse_nib(30, 8, 30)
    pair = convolve.with_pair_table(convolve.gauss_pair_of(a, b))
    conv = convolve.convolution(a, b, 1e-4, gauss_pair=pair)
    ta, tb = pair.edge_tables()
    i, j, lo, hi, k = pair.table
    ref = []
    for r in range(len(i)):
        for c in convolve.convolve_edges(ta.edges[i[r]], tb.edges[j[r]], lo[r], hi[r], k[r],
                                         1e-4):
            ref.append((r, c))
    assert len(conv) == len(ref) > 50
    kinds = set()
    for c, (r, c_ref) in zip(conv, ref):
        assert c.row == r and c.kind == c_ref.kind
        kinds.add(c.kind)
        if c.kind == "translate":   # exact pieces: the same operations
            assert c.bound == c_ref.bound == 0.0
            assert c.piece.tobytes() == np.asarray(c_ref.piece, float).tobytes()
        else:    # Algorithm 4.1 on a batch rounds a level's arrays differently
            assert c.bound == pytest.approx(c_ref.bound, rel=1e-9)
            assert np.allclose(pc.cartesian(c.piece), pc.cartesian(c_ref.piece), atol=1e-9)
        assert c.source == (int(ta.loop[i[r]]), int(ta.index[i[r]]), int(tb.loop[j[r]]),
                            int(tb.index[j[r]]))
        assert c.type == convolve.pair_type(ta.sign[i[r]], tb.sign[j[r]], ta.vertex[i[r]],
                                            tb.vertex[j[r]])


def test_conv_pieces_take_concat_and_chain():
    a, b = _regions()["glyph g"], ellipse_nib(30, 8, 30)
    conv = convolve.convolution(a, b, 0.05)
    objs = list(conv)
    idx = np.arange(len(conv))[::3]
    part = conv.take(idx)
    assert [c.piece.tobytes() for c in part] == [objs[k].piece.tobytes() for k in idx]
    both = convolve.ConvPieces.concat([part, conv.take(~np.isin(np.arange(len(conv)), idx))])
    order = np.concatenate([idx, np.setdiff1d(np.arange(len(conv)), idx)])
    assert [c.piece.tobytes() for c in both] == [objs[k].piece.tobytes() for k in order]
    assert {c.kind for c in objs} >= {"qac", "translate"}
    assert np.array_equal(both.row, conv.row[order])
    # chaining the packed pieces is chaining the list
    packed = convolve.chain(conv.pieces, 1e-6)
    listed = convolve.chain([c.piece for c in objs], 1e-6)
    assert [[p.tobytes() for p in lp] for lp in packed] == \
        [[p.tobytes() for p in lp] for lp in listed]


def test_subdivided_pairs_come_in_travel_order():
    """Pairs split over several levels of Algorithm 4.1 (two ellipses, tight tol):
    each pair's pieces in the order of the pair computed alone, end to start."""
    a, b = [pc.ellipse((0, 0), 5.0, 1.0, 0.3)], [pc.ellipse((0, 0), 3.0, 0.2, -0.7)]
    pair = convolve.with_pair_table(convolve.gauss_pair_of(a, b))
    conv = convolve.convolution(a, b, 1e-6, gauss_pair=pair)
    ta, tb = pair.edge_tables()
    i, j, lo, hi, k = pair.table
    ref = [c for r in range(len(i))
           for c in convolve.convolve_edges(ta.edges[i[r]], tb.edges[j[r]], lo[r], hi[r], k[r],
                                            1e-6)]
    assert len(conv) == len(ref) > len(i)        # pairs cut into several pieces
    for c, c_ref in zip(conv, ref):
        assert np.allclose(pc.cartesian(c.piece), pc.cartesian(c_ref.piece), atol=1e-9)
    starts, ends = pc.end_points(conv.pieces)
    same = conv.row[1:] == conv.row[:-1]           # consecutive pieces of one pair join
    assert same.any() and np.allclose(ends[:-1][same], starts[1:][same], atol=1e-9)


def test_traced_loops_tips_equal_the_winding_test():
    """gauss_table(traced=n): the open cusps of the first n loops (paths traced out
    and back) turn +pi without the probe test; every turn, angle and edge of the
    table equals the full test's, to the bit, on stroke loops (lines, curves, a
    turn-back, a closed path) followed by a loop that is not traced (a circle, and
    a glyph's loops with it); a loop that is not traced keeps the test (a loop
    with a slit cut into it: its open cusp turns -pi, which +pi would not match)."""
    loops = _stroke_loops()
    tail = [pc.circle((3.0, -1.0), 2.0)] + list(parse.glyph_region("g").region)
    full = gauss.gauss_table(loops + tail)
    fast = gauss.gauss_table(loops + tail, traced=len(loops))
    for name in ("loop", "index", "curve", "theta", "sweep", "point", "piece_of"):
        assert np.array_equal(getattr(full, name), getattr(fast, name)), name
    assert (np.isclose(np.abs(full.sweep[~full.curve]), np.pi)).sum() >= 2 * len(loops) - 1
    # a square with a slit cut into it from its right side: the slit's tip is
    # reflex, -pi, found by the test (traced=0), not assumed
    slit = [pc.line((0, 0), (10, 0)), pc.line((10, 0), (10, 4)), pc.line((10, 4), (5, 4)),
            pc.line((5, 4), (10, 4)), pc.line((10, 4), (10, 10)), pc.line((10, 10), (0, 10)),
            pc.line((0, 10), (0, 0))]
    tested = gauss.gauss_table([slit])
    assumed = gauss.gauss_table([slit], traced=1)
    tip = ~tested.curve & np.isclose(np.abs(tested.sweep), np.pi)
    assert np.allclose(tested.sweep[tip], -np.pi)
    assert not np.array_equal(tested.sweep, assumed.sweep)
