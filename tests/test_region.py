"""Regions: orientation by nesting and fill rule, cleaning, bbox, centroid, point tests."""

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph.region import (Region, clean_loop, loop_bboxes, orient_region, point_in_region,
                          region_bbox, region_centroid, reverse_loop, winding_number,
                          zero_length_mask)


def square(x0, y0, size, ccw=True):
    pts = [(x0, y0), (x0 + size, y0), (x0 + size, y0 + size), (x0, y0 + size)]
    loop = [pc.line(pts[i], pts[(i + 1) % 4]) for i in range(4)]
    return loop if ccw else reverse_loop(loop)


def areas(loops):
    return sorted(round(mo.loop_area(l), 9) for l in loops)


@pytest.mark.parametrize("dirs", [(True, True, True), (False, False, False),
                                  (True, False, True), (False, True, False)])
def test_evenodd_nesting_alternates(dirs):
    loops = [square(0, 0, 10, dirs[0]), square(2, 2, 6, dirs[1]), square(4, 4, 2, dirs[2])]
    out = orient_region(loops, "evenodd")
    assert areas(out) == [-36.0, 4.0, 100.0]
    assert mo.region_area(out) == pytest.approx(68.0)


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_many_nested_loops_against_a_pixel_count_of_the_rule(rule):
    # 20 x 20 cells, each a square with random nesting (0-2 squares inside it) and
    # random directions: the probes of all loops are found at once; the filled area
    # and every loop's role checked against the rule's winding count at cell centres
    rng = np.random.default_rng(3)
    loops, truth = [], 0.0
    for i in range(20):
        for j in range(20):
            depth = int(rng.integers(1, 4))
            dirs = rng.integers(0, 2, depth).astype(bool)
            for d in range(depth):
                loops.append(square(10 * i + d, 10 * j + d, 8 - 2 * d, bool(dirs[d])))
            # windings of the rings between nested squares, outermost first
            w, sides = 0, [8 - 2 * d for d in range(depth)] + [0]
            for d in range(depth):
                w += 1 if dirs[d] else -1
                filled = (w != 0) if rule == "nonzero" else (w % 2 == 1)
                truth += filled * (sides[d] ** 2 - sides[d + 1] ** 2)
    out = orient_region(loops, rule)
    assert mo.region_area(out) == pytest.approx(truth)
    assert all(mo.loop_area(l) != 0 for l in out)


def test_nonzero_opposite_directions_make_a_hole():
    out = orient_region([square(0, 0, 10, False), square(2, 2, 6, True)], "nonzero")
    assert areas(out) == [-36.0, 100.0]


def test_nonzero_same_direction_drops_inner_loop():
    out = orient_region([square(0, 0, 10, False), square(2, 2, 6, False)], "nonzero")
    assert areas(out) == [100.0]
    # and under even-odd the same input has a hole
    assert areas(orient_region([square(0, 0, 10), square(2, 2, 6)], "evenodd")) == [-36.0, 100.0]


def test_disjoint_loops_are_all_outer():
    out = orient_region([square(0, 0, 1, False), square(5, 0, 1, True), square(10, 0, 2, False)])
    assert areas(out) == [1.0, 1.0, 4.0]


def test_circle_hole_in_circle():
    outer = pc.circle((0, 0), 5.0)
    inner = pc.circle((1, 0), 2.0)  # same direction: nonzero keeps no hole
    assert len(orient_region([outer, inner], "nonzero")) == 1
    out = orient_region([outer, reverse_loop(inner)], "nonzero")
    assert mo.region_area(out) == pytest.approx(np.pi * 21, rel=1e-12)


def test_zero_length_pieces_and_zero_area_loops_dropped():
    loop = square(0, 0, 2)
    loop.insert(2, pc.cubic((2, 0), (2, 0), (2, 0), (2, 0)))
    flat = [pc.line((0, 0), (1, 0)), pc.line((1, 0), (0, 0))]
    out = orient_region([loop, flat])
    assert len(out) == 1 and len(out[0]) == 4


def test_clean_loop_snaps_joins_exactly():
    loop = [pc.line((0, 0), (1, 0)), pc.line((1 + 1e-12, 0), (0, 1)),
            pc.line((0, 1), (0, 1e-12))]
    out = clean_loop(loop)
    for a, b in zip(out, out[1:] + out[:1]):
        assert np.array_equal(pc.end(a), pc.start(b))
    with pytest.raises(ValueError):
        clean_loop([pc.line((0, 0), (1, 0)), pc.line((1, 0.5), (0, 0))], tol=1e-6)


def test_zero_length_pieces_found_among_mixed_degrees_and_dropped():
    """zero_length_mask flags exactly the pieces whose control points coincide (a
    point repeated, up to 1e-12 of the coordinates' size, weights of any value),
    whatever the degrees around them; clean_loop drops them and closes the rest."""
    dot = pc.from_points([(5.0, 5.0)] * 3, [1.0, 3.0, 1.0])
    almost = pc.line((1e6, 0.0), (1e6 + 1e-7, 0.0))  # 1e-13 of its coordinates
    short = pc.line((0.0, 0.0), (1e-9, 0.0))           # 1e-9 of the unit scale: kept
    pieces = [pc.line((0, 0), (5, 5)), dot, pc.cubic((5, 5), (6, 7), (8, 7), (9, 5)), almost,
              short, pc.from_points([(2.0, 2.0)] * 4)]
    assert zero_length_mask(pieces).tolist() == [False, True, False, True, False, True]
    assert zero_length_mask([]).tolist() == []
    loop = [pc.line((0, 0), (4, 0)), pc.line((4, 0), (4, 0)), pc.line((4, 0), (0, 3)),
            pc.from_points([(0, 3)] * 3), pc.line((0, 3), (0, 0))]
    out = clean_loop(loop)
    assert len(out) == 3 and abs(mo.loop_area(out) - 6.0) < 1e-12


def test_unknown_fill_rule():
    with pytest.raises(ValueError):
        orient_region([square(0, 0, 1)], "odd")


def test_region_bbox_is_tight():
    box = region_bbox([pc.circle((1.0, 2.0), 3.0)])
    assert np.allclose(box, [-2.0, -1.0, 4.0, 5.0], atol=1e-12)
    c = pc.cubic((0, 0), (1, 2), (2, 2), (3, 0))  # max y = 1.5 at t = 0.5
    assert np.allclose(region_bbox([[c, pc.line((3, 0), (0, 0))]]), [0, 0, 3, 1.5])


@pytest.mark.parametrize("seed", range(6))
def test_region_bbox_of_random_pieces_matches_dense_sampling(seed):
    """Mixed degrees 1-5, polynomial and rational (weights 0.2-5), with a repeated
    control point (a zero of the tangent at an end) in some: every sampled point
    lies in the box and each side is reached by the samples within their spacing's
    error (extremes are stationary points: O(h^2))."""
    rng = np.random.default_rng(seed)
    pieces = []
    for k in range(12):
        n = int(rng.integers(1, 6))
        pts = rng.normal(size=(n + 1, 2)) * 10 ** rng.uniform(-1, 2)
        if k % 4 == 1 and n >= 2:
            pts[1] = pts[0]
        w = np.ones(n + 1) if k % 2 else rng.uniform(0.2, 5.0, n + 1)
        pieces.append(pc.from_points(pts, w))
    box = region_bbox([pieces])
    t = np.linspace(0.0, 1.0, 20001)
    dense = np.vstack([pc.evaluate(p, t) for p in pieces])
    size = np.ptp(dense, axis=0).max()
    lo, hi = dense.min(axis=0), dense.max(axis=0)
    assert np.all(box[:2] <= lo + 1e-12 * size) and np.all(box[2:] >= hi - 1e-12 * size)
    assert np.allclose(box, np.concatenate([lo, hi]), rtol=0, atol=1e-6 * size)
    # per loop (pieces dealt to 3 loops, one left empty), the same against its samples
    loops = [pieces[0::3], [], pieces[1::3], pieces[2::3]]
    boxes = loop_bboxes(loops)
    assert boxes.shape == (3, 4)
    for b, loop in zip(boxes, [loops[0], loops[2], loops[3]]):
        d = np.vstack([pc.evaluate(p, t) for p in loop])
        assert np.allclose(b, np.r_[d.min(axis=0), d.max(axis=0)], rtol=0, atol=1e-6 * size)


def test_centroid_exact():
    ring = [square(0, 0, 4), reverse_loop(square(0, 0, 2))]  # L shape
    assert np.allclose(region_centroid(ring), [(16 * 2 - 4 * 1) / 12] * 2, atol=1e-14)
    assert np.allclose(region_centroid([pc.ellipse((3.0, -1.0), 2.0, 1.0, 0.5)]), [3.0, -1.0],
                       atol=1e-12)
    # half disk: centroid at 4r / (3 pi)
    half = pc.ellipse_arc((0, 0), 1.0, 1.0, 0.0, 0.0, np.pi) + [pc.line((-1, 0), (1, 0))]
    assert np.allclose(region_centroid([half]), [0, 4 / (3 * np.pi)], atol=1e-13)


def test_winding_number_and_point_in_region():
    ring = [square(0, 0, 10), reverse_loop(square(3, 3, 4))]
    pts = np.array([[1, 1], [5, 5], [20, 5], [9.5, 5], [2.5, 5]])
    assert list(point_in_region(pts, ring, 1e-3)) == [True, False, False, True, True]
    two = [np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)] * 2
    assert list(winding_number(np.array([[1.0, 1.0], [3.0, 1.0]]), two)) == [2, 0]
    cw = [np.array([[0, 0], [0, 2], [2, 2], [2, 0]], float)]
    assert list(winding_number(np.array([[1.0, 1.0]]), cw)) == [-1]


def test_region_is_immutable_and_knows_what_it_is():
    """A Region is a sequence of loops; it cannot be edited in place, so its mark
    (validated) and bound cannot go stale: an edit makes a new, unvalidated region."""
    r = orient_region([square(0, 0, 2, False), square(0.5, 0.5, 1, False)], "evenodd")
    assert isinstance(r, Region) and r.validated and r.bound is None
    assert len(r) == 2 and r.area == pytest.approx(3.0)
    assert np.allclose(r.bbox, [0, 0, 2, 2])
    m = r.translated((1, 1)).scaled(2)
    assert m.validated and m.area == pytest.approx(12.0)
    assert np.allclose(m.bbox, [2, 2, 6, 6])
    mirrored = r.transformed([[-1, 0, 0], [0, 1, 0]])  # orientation kept
    assert mirrored.validated and mirrored.area == pytest.approx(3.0)
    assert [len(l) for l in r] == [4, 4]
    assert "Region(2 loops, 8 pieces, validated" in repr(r)
    with pytest.raises(AttributeError):
        r.append(r[0])
    with pytest.raises(AttributeError):
        r.validated = False
    with pytest.raises(TypeError):
        r[0][0] = r[0][1]
    with pytest.raises(ValueError):   # read-only arrays
        r[0][0][0, 0] = 5.0
    edited = Region(list(r) + [square(5, 5, 1, True)])
    assert not edited.validated and len(edited) == 3
    # the caller's arrays are not frozen by wrapping them
    piece = np.array([[0, 0, 1], [1, 0, 1]], float)
    Region([[piece]])
    piece[0, 0] = 1.0
    # bounds scale with the map; a singular map drops the mark
    b = Region._make(r, True, 0.5)
    assert b.scaled(3).bound == pytest.approx(1.5) and b.translated((1, 0)).bound == 0.5
    assert not b.transformed([[1, 0, 0], [0, 0, 0]]).validated
    import pickle

    back = pickle.loads(pickle.dumps(b))
    assert back.validated and back.bound == 0.5 and len(back) == 2


def test_loops_with_equal_boxes_and_areas_but_other_curves_do_not_cancel():
    """A square notched at the top and the same square notched at the bottom (same
    bounding box, same area), in opposite directions: not coincident, so under
    nonzero they fill their symmetric difference (shapely), not nothing."""
    pytest.importorskip("shapely")
    from shapely.geometry import Polygon

    from morph.trim import fill_region

    top = [(0, 0), (10, 0), (10, 10), (6, 10), (6, 9), (4, 9), (4, 10), (0, 10)]
    bottom = [(0, 0), (4, 0), (4, 1), (6, 1), (6, 0), (10, 0), (10, 10), (0, 10)]

    def loop(pts):
        return [pc.line(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]

    a, b = loop(top), reverse_loop(loop(bottom))
    assert mo.loop_area(a) == -mo.loop_area(b) == 98.0
    got = orient_region([a, b], "nonzero", on_crossing=fill_region)
    ref = Polygon(top).symmetric_difference(Polygon(bottom))
    assert abs(mo.region_area(got) - ref.area) < 1e-9 and ref.area == 4.0


def _same_region(a, b):
    """Two regions equal to the bit: loops, pieces, their shapes and every float."""
    return (len(a) == len(b) and a.validated == b.validated and a.bound == b.bound
            and all(len(la) == len(lb) and all(p.shape == q.shape and np.array_equal(p, q)
                                                 and (p.tobytes() == np.ascontiguousarray(q).tobytes())
                                                 for p, q in zip(la, lb))
                    for la, lb in zip(a, b)))


def _cases():
    """Regions for orient_regions: glyphs (lines, quadratics, cubics), nested squares
    of random directions, circles (rational pieces), and the ones orient_region
    handles alone: crossing loops, coincident loops, a loop of no area, nothing."""
    from morph.parse import cubic_test_font_path, default_font_path, glyph_name, load_font
    from morph.parse.glyphs import _glyph_loops

    out = []
    for path in (default_font_path(), cubic_test_font_path()):
        font = load_font(path)
        glyphs = font.getGlyphSet()
        for name in ["a", "B", "O", "percent", "g", "eight", "ampersand", "i", "Q", "period"]:
            out.append(_glyph_loops(glyphs, glyph_name(font, name), name, "test"))
    rng = np.random.default_rng(5)
    for _ in range(12):
        depth = int(rng.integers(1, 4))
        out.append([square(d, d, 8 - 2 * d, bool(rng.integers(0, 2))) for d in range(depth)])
    out.append([list(pc.circle((0, 0), 5)), reverse_loop(list(pc.circle((0, 0), 2)))])
    out.append([square(0, 0, 4), square(10, 0, 4)])   # equal areas, apart: no coincidence
    fast = len(out)
    out.append([square(0, 0, 4), square(2, 2, 4)])                 # crossing
    out.append([square(0, 0, 4), square(0, 0, 4), square(10, 0, 1)])  # coincident
    flat = [pc.line((0, 0), (4, 0)), pc.line((4, 0), (0, 0))]
    out.append([square(0, 0, 4), flat])                             # a loop of no area
    out.append([])
    out.append([[pc.line((1, 1), (1, 1))]])                          # only zero-length
    return out, fast


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_orient_regions_is_orient_region_of_each_to_the_bit(rule):
    from morph.region import _LoopBatch, orient_regions
    from morph.trim import fill_region

    regions, fast = _cases()
    got = orient_regions(regions, rule, on_crossing=fill_region)
    for k, region in enumerate(regions):
        assert _same_region(got[k], orient_region(region, rule, on_crossing=fill_region)), k
    batch = _LoopBatch(regions)
    assert set(batch.fast) == set(range(fast))  # the common cases took the batched way
    assert set(batch.slow) == {fast, fast + 1, fast + 2}
    # and a region put wrong is seen: a hole turned the other way is not the same
    hole = got[0][1] if len(got[0]) > 1 else None
    if hole is not None:
        wrong = Region._make([got[0][0], reverse_loop(hole)] + list(got[0][2:]), True)
        assert not _same_region(wrong, got[0])


def test_orient_regions_of_nested_squares_against_a_pixel_count():
    """The batched way alone (all regions take it), against the rule's count."""
    from morph.region import _LoopBatch, orient_regions

    rng = np.random.default_rng(11)
    regions, truth = [], []
    for _ in range(40):
        depth = int(rng.integers(1, 4))
        dirs = rng.integers(0, 2, depth).astype(bool)
        regions.append([square(d, d, 8 - 2 * d, bool(dirs[d])) for d in range(depth)])
        w, sides, filled = 0, [8 - 2 * d for d in range(depth)] + [0], 0.0
        for d in range(depth):
            w += 1 if dirs[d] else -1
            filled += (w != 0) * (sides[d] ** 2 - sides[d + 1] ** 2)
        truth.append(filled)
    assert _LoopBatch(regions).fast == list(range(40))
    for region, area in zip(orient_regions(regions), truth):
        assert mo.region_area(region) == pytest.approx(area)
        assert region.validated
