"""morph.trim.topology: fill rules, slivers and holes on the integer rings, against
exact areas."""

import numpy as np
import pytest

from morph import piece as pc
from morph.trim.flatten import tag_loops
from morph.polyline import min_segment_distance, winding_number
from morph.trim.topology import drop_slivers, fill_holes, filled_rings, ring_area


def _square(x0, y0, s, ccw=True):
    p = [(x0, y0), (x0 + s, y0), (x0 + s, y0 + s), (x0, y0 + s)]
    if not ccw:
        p = p[::-1]
    return [pc.line(p[i], p[(i + 1) % 4]) for i in range(4)]


@pytest.mark.parametrize("rule, area", [("positive", 7.0), ("nonzero", 7.0), ("evenodd", 6.0)])
def test_fill_rules_on_overlapping_squares(rule, area):
    tg = tag_loops([_square(0, 0, 2), _square(1, 1, 2)], 1e-3, 1e-3)
    rings = filled_rings(tg.paths(), rule)
    got = sum(ring_area(r.q) for r in rings) * tg.grid ** 2
    assert got == pytest.approx(area, rel=1e-6)
    assert all((ring_area(r.q) > 0) != r.hole for r in rings)


def test_positive_ignores_negative_loops():
    tg = tag_loops([_square(0, 0, 2), _square(5, 0, 2, ccw=False)], 1e-3, 1e-3)
    rings = filled_rings(tg.paths(), "positive")
    assert len(rings) == 1 and ring_area(rings[0].q) * tg.grid ** 2 == pytest.approx(4.0)


def test_slivers_dropped_and_holes_filled():
    tg = tag_loops([_square(0, 0, 10), _square(2, 2, 3, ccw=False),
                    _square(12, 12, 1e-3 * 4, ccw=True)], 1e-4, 1e-3)
    rings = filled_rings(tg.paths(), "nonzero")
    assert sorted(r.hole for r in rings) == [False, False, True]
    thin = drop_slivers(rings, 1.5)  # the 4-unit square (mean width 2) is no sliver...
    assert len(thin) == 3
    assert len(drop_slivers(rings, 4.0)) == 2  # ...at a width threshold of 4 units it is
    hole = [i for i, r in enumerate(thin) if r.hole]
    assert len(fill_holes(thin, hole)) == 2


def test_paths_on_one_line_fill_nothing():
    # Clipper refuses a batch whose every path is invalid (collinear after rounding):
    # a stroke with a nib far below tol ended in its ClipperException (exit 1)
    import numpy as np

    flat = [np.array([[0, 0], [5, 5], [9, 9], [5, 5]], np.int64),
            np.array([[0, 3], [4, 3], [8, 3]], np.int64)]
    assert filled_rings(flat, "nonzero") == []
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], np.int64)
    rings = filled_rings(flat + [square], "nonzero")
    assert len(rings) == 1 and ring_area(rings[0].q) == 16


def test_sum_with_a_nib_far_below_tol_is_refused_with_a_suggestion():
    from morph.errors import LimitError
    from morph.stroke import stroke_paths

    path = [pc.line((0, 0), (50, 50)), pc.line((50, 50), (90, 10))]
    tiny = [[pc.line((0, 0), (1e-9, 0)), pc.line((1e-9, 0), (1e-9, 1e-9)),
             pc.line((1e-9, 1e-9), (0, 1e-9)), pc.line((0, 1e-9), (0, 0))]]
    with pytest.raises(LimitError, match="thinner than the tolerance") as err:
        stroke_paths([(path, False)], tiny, 1e-4)
    assert err.value.suggestion < 1e-4


def _one_pass_fill(paths, rule, pts):
    """The reference: which points Clipper's union of the paths in one pass fills
    (even-odd over its output rings, which overlap nowhere)."""
    import pyclipper

    from morph.trim.topology import FILL_TYPES

    clip = pyclipper.Pyclipper()
    clip.AddPaths([p.tolist() for p in paths], pyclipper.PT_SUBJECT, True)
    ft = FILL_TYPES[rule]
    rings = [np.asarray(r, float) for r in clip.Execute(pyclipper.CT_UNION, ft, ft)]
    a = np.concatenate(rings)
    b = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
    return winding_number(pts, rings) % 2 == 1, min_segment_distance(pts, a, b)


@pytest.mark.parametrize("rule", ["positive", "nonzero", "evenodd"])
@pytest.mark.parametrize("seed", range(4))
def test_two_pass_rings_fill_and_nest_as_clipper(rule, seed):
    """filled_rings (a flat union, then the tree of its rings) on random overlapping
    integer polygons and nested squares of both directions (holes, islands in
    holes, a triangle touching a square's corner): its rings fill what Clipper's
    one-pass union fills (at 10,000 points off the lattice, those farther than 2
    units from its rings: each pass rounds its crossings to the lattice), each ring's hole flag
    is its orientation, and each ring lies inside its parent (a box inside its box,
    of the other kind, larger), outer rings at the top."""
    rng = np.random.default_rng(seed)
    paths = [rng.integers(0, 60, (int(rng.integers(3, 9)), 2)) for _ in range(8)]
    for k, s in enumerate((50, 40, 30, 20, 10)):
        sq = np.array([[0, 0], [s, 0], [s, s], [0, s]]) + 70 + (50 - s) // 2
        paths.append(sq if k % 2 == 0 else sq[::-1])
    paths.append(np.array([[70, 70], [60, 60], [60, 70]]))
    rings = filled_rings(paths, rule)
    pts = np.c_[rng.uniform(-1, 121, 10000), rng.uniform(-1, 121, 10000)]
    got = winding_number(pts, [r.q.astype(float) for r in rings])
    ref, gap = _one_pass_fill(paths, rule, pts)
    assert set(np.unique(got[gap > 2])) <= {0, 1}
    assert np.array_equal((got == 1)[gap > 2], ref[gap > 2]) and (gap > 2).sum() > 5000
    for r in rings:
        assert (ring_area(r.q) < 0) == r.hole
        if r.parent < 0:
            assert not r.hole
            continue
        parent = rings[r.parent]
        assert parent.hole != r.hole and abs(ring_area(parent.q)) > abs(ring_area(r.q))
        assert (r.q.min(axis=0) >= parent.q.min(axis=0)).all()
        assert (r.q.max(axis=0) <= parent.q.max(axis=0)).all()
    assert sum(r.hole for r in rings) >= 1 and len(rings) >= 4



def _tree_rings(flat):
    """(vertex set, hole, parent's vertex set) of each ring of Clipper's PolyTree
    of flat rings: the tree pass that _nested_rings stands in for."""
    import pyclipper

    clip = pyclipper.Pyclipper()
    clip.AddPaths(flat, pyclipper.PT_SUBJECT, True)
    tree = clip.Execute2(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    out, stack = set(), [(child, None) for child in tree.Childs]
    while stack:
        node, parent = stack.pop()
        key = frozenset(map(tuple, node.Contour))
        out.add((key, bool(node.IsHole), parent))
        stack.extend((child, key) for child in node.Childs)
    return out


@pytest.mark.parametrize("seed", range(6))
def test_nested_rings_as_the_tree_pass(seed):
    """_nested_rings (the nesting of Clipper's flat rings from exact winding numbers)
    gives the rings, hole flags and parents of Clipper's PolyTree pass, parents
    before children, on random overlapping polygons with nested squares of both
    directions; it gives up (None) where a ring visits a grid point twice (two
    squares meeting at a corner), and filled_rings then gives the tree pass's."""
    import pyclipper

    from morph.trim.topology import _nested_rings

    rng = np.random.default_rng(seed)
    # simple star-shaped polygons overlapping on a fine lattice (crossings rarely
    # round onto one grid point), rings around holes among them
    paths = []
    for _ in range(10):
        ang = np.sort(rng.uniform(0, 2 * np.pi, 12))
        r = rng.uniform(4000, 20000, 12)
        c = rng.uniform(10000, 50000, 2)
        paths.append(np.rint(c + r[:, None] * np.c_[np.cos(ang), np.sin(ang)]).astype(int).tolist())
    for k, s in enumerate((50, 40, 30, 20, 10)):
        sq = (np.array([[0, 0], [s, 0], [s, s], [0, s]]) + 70 + (50 - s) // 2) * 1000
        paths.append((sq if k % 2 == 0 else sq[::-1]).tolist())
    clip = pyclipper.Pyclipper()
    clip.AddPaths(paths, pyclipper.PT_SUBJECT, True)
    flat = clip.Execute(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    rings = _nested_rings(flat)
    assert rings is not None and len(rings) == len(flat)
    rings = rings.to_list()
    keys = [frozenset(map(tuple, r.q.tolist())) for r in rings]
    assert all(r.parent < k for k, r in enumerate(rings))
    assert {(keys[k], r.hole, keys[r.parent] if r.parent >= 0 else None)
            for k, r in enumerate(rings)} == _tree_rings(flat)
    assert sum(r.hole for r in rings) >= 2 and any(
        r.parent >= 0 and rings[r.parent].parent >= 0 for r in rings)
    # a ring inside another's box, not inside it: both at the top
    ell = [[0, 0], [100, 0], [100, 10], [10, 10], [10, 100], [0, 100]]
    box = [[50, 50], [60, 50], [60, 60], [50, 60]]
    got = _nested_rings([ell, box]).to_list()
    assert [r.parent for r in got] == [-1, -1] and not any(r.hole for r in got)
    # a ring through one grid point twice: the tree pass decides
    bow = [[0, 0], [10, 0], [10, 10], [20, 10], [20, 20], [10, 20], [10, 10], [0, 10]]
    assert _nested_rings([bow]) is None
    got = filled_rings([np.array(bow)], "nonzero")
    keys = [frozenset(map(tuple, r.q.tolist())) for r in got]
    assert {(keys[k], r.hole, keys[r.parent] if r.parent >= 0 else None)
            for k, r in enumerate(got)} == _tree_rings([bow])


def _comb(x0, y0, teeth):
    """An integer comb: a base 10 high with ``teeth`` teeth 1 wide and 80 long (12
    teeth: mean width 1.29 units, a thin ring with a fat base)."""
    pts = [(x0, y0), (x0 + 10 + 2 * teeth, y0), (x0 + 10 + 2 * teeth, y0 + 10)]
    for k in range(teeth - 1, -1, -1):
        x = x0 + 10 + 2 * k
        pts += [(x + 1, y0 + 10), (x + 1, y0 + 90), (x, y0 + 90), (x, y0 + 10)]
    return np.array(pts + [(x0, y0 + 10)], np.int64)


@pytest.mark.parametrize("rule", ["positive", "nonzero", "evenodd"])
@pytest.mark.parametrize("seed", range(4))
def test_slivers_left_out_before_the_tree_change_only_thin_rings(rule, seed):
    """filled_rings(paths, rule, thin) leaves out thin rings holding no other ring
    before the tree pass; with drop_slivers after, it fills what Clipper's flat
    union fills except inside its thin rings (mean width <= 1.5 units), at 10,000
    points more than 2 units from either's rings, as drop_slivers on the full tree
    does.  Inputs: random polygons with thin triangles (lone slivers, some crossing
    others), a thin comb holding a hole and an island (they go with it), and a
    hole that is a sliver (it closes)."""
    rng = np.random.default_rng(seed)
    paths = [rng.integers(0, 60, (int(rng.integers(3, 9)), 2)) for _ in range(6)]
    for _ in range(12):
        a = rng.integers(0, 60, 2)
        d = rng.integers(-40, 40, 2)
        paths.append(np.array([a, a + d, a + d // 2 + rng.integers(0, 2, 2)], np.int64))
    comb = _comb(110, 0, 12)  # beyond the random polygons' reach (x < 100)
    paths += [comb, np.array([[113, 3], [113, 7], [117, 7], [117, 3]], np.int64),
              np.array([[114, 4], [116, 4], [116, 6], [114, 6]], np.int64)]
    big = np.array([[110, 100], [150, 100], [150, 140], [110, 140]], np.int64)
    paths += [big, np.array([[115, 110], [115, 111], [145, 110]], np.int64)[::-1]]
    assert _is_thin_ring(comb) and not _is_thin_ring(big)
    flat = [np.asarray(f, float) for f in pyclipper_union(paths, rule)]
    thin_flat = [f for f in flat if _is_thin_ring(f)]
    pts = np.c_[rng.uniform(-41, 151, 10000), rng.uniform(-41, 141, 10000)]
    union = winding_number(pts, flat) == 1
    in_thin = np.zeros(len(pts), bool)
    for f in thin_flat:
        in_thin |= winding_number(pts, [f]) != 0
    probes = np.array([[111.5, 1.5], [113.5, 3.5], [115.0, 5.0], [130.0, 110.2], [130.0, 130.0]])
    for rings in (drop_slivers(filled_rings(paths, rule, 1.5), 1.5),
                  drop_slivers(filled_rings(paths, rule), 1.5)):
        q = [r.q.astype(float) for r in rings]
        got = winding_number(pts, q)
        far = (min_segment_distance(pts, *_edges(flat)) > 2) & (
            min_segment_distance(pts, *_edges(q)) > 2)
        assert far.sum() > 5000 and set(np.unique(got[far])) <= {0, 1}
        assert np.array_equal((got == 1)[far & ~in_thin], union[far & ~in_thin])
        assert not any(_is_thin_ring(x) for x in q)
        # the comb's base, its hole and the island in it go with the comb; the
        # big square's sliver hole closes
        assert winding_number(probes, q).tolist() == [0, 0, 0, 1, 1]


def pyclipper_union(paths, rule):
    import pyclipper

    from morph.trim.topology import FILL_TYPES

    clip = pyclipper.Pyclipper()
    clip.AddPaths([p.tolist() for p in paths], pyclipper.PT_SUBJECT, True)
    return clip.Execute(pyclipper.CT_UNION, FILL_TYPES[rule], FILL_TYPES[rule])


def _is_thin_ring(q):
    d = np.diff(np.vstack([q, q[:1]]), axis=0)
    return 2 * abs(ring_area(q)) <= 1.5 * np.hypot(d[:, 0], d[:, 1]).sum()


def _edges(rings):
    return np.concatenate(rings), np.concatenate([np.roll(x, -1, axis=0) for x in rings])


def test_near_coincident_copies_fill_in_seconds():
    """Three copies of a blob 1e-7 of its size apart, in both directions (Clipper's
    one-pass tree took minutes on the slivers between them, and remove_folds went
    through the spikes one rescan at a time): the region is the blob, found in a
    subprocess within 60 s."""
    import subprocess
    import sys

    pts = [(20, 50), (20, 20), (45, 12), (60, 15), (85, 20), (90, 40), (85, 60), (80, 85),
           (50, 92), (35, 80), (20, 70), (20, 60), (20, 50)]

    def path(dx, backwards):
        p = pts[::-1] if backwards else pts
        xy = ["%.5f %g" % (x + dx, y) for x, y in p]
        return "M" + xy[0] + " " + " ".join("C" + " ".join(xy[k:k + 3]) for k in range(1, 13, 3))

    # one path element: the parser fills its three subpaths together (winding +1 -1 -1)
    svg = ('<svg xmlns="http://www.w3.org/2000/svg"><path d="%s %s %s"/></svg>'
           % (path(0, False), path(1e-5, True), path(-1e-5, True)))
    script = ("import sys\nfrom morph.parse import svg_region\nfrom morph import moments as mo\n"
              "r = svg_region(sys.argv[1])\nprint(len(r), mo.region_area(r))\n")
    out = subprocess.run([sys.executable, "-c", script, svg], capture_output=True, text=True,
                         timeout=60, check=True).stdout.split()
    assert int(out[0]) == 1  # the slivers between the copies are dropped
    assert abs(float(out[1]) - 3824.5) < 0.01  # the blob's area, within the slivers'


@pytest.mark.parametrize("rule", ["positive", "nonzero", "evenodd"])
def test_groups_apart_united_alone_fill_as_one_union(rule):
    """filled_rings unites each group of paths apart from the others on its own,
    moved to the origin (topology._union): on a 5 x 5 grid of cells of random
    overlapping polygons (a chunk of glyphs), with two cells 3 units apart (within
    APART_GAP: one group) and two just farther (two groups), it fills what
    Clipper's one-pass union of all paths fills (at 20,000 points more than 2 units
    from either's rings), the groups' boxes are more than the gap apart, and the
    flat rings come from the highest top down."""
    from morph.trim.topology import APART_GAP, FILL_TYPES, _apart_groups, _union

    rng = np.random.default_rng(21)
    paths = []
    for cx in range(5):
        for cy in range(5):
            base = np.array([cx * 3000, cy * 2000])
            for _ in range(3):
                paths.append(base + rng.integers(0, 900, (int(rng.integers(3, 9)), 2)))
    near = np.array([[20000, 0], [20300, 0], [20300, 300], [20000, 300]])
    paths += [near, near + [303, 0]]                         # 3 units apart: one group
    paths += [near + [0, 1000], near + [300 + APART_GAP + 1, 1000]]  # apart
    rings = filled_rings(paths, rule)
    pts = np.c_[rng.uniform(-100, 21000, 20000), rng.uniform(-100, 10000, 20000)]
    got = winding_number(pts, [r.q.astype(float) for r in rings])
    ref, gap = _one_pass_fill(paths, rule, pts)
    q = [r.q.astype(float) for r in rings]
    far = (gap > 2) & (min_segment_distance(pts, *_edges(q)) > 2)
    assert far.sum() > 15000 and set(np.unique(got[far])) <= {0, 1}
    assert np.array_equal((got == 1)[far], ref[far])
    # probes inside the four squares: filled, the first two in one ring
    probes = np.array([[20150, 150], [20453, 150], [20150, 1150], [20458, 1150]], float)
    assert np.all(winding_number(probes, q) == 1)
    # the groups: 25 cells (some may join inside a cell), the near pair one group
    lo = np.array([p.min(axis=0) for p in paths])
    hi = np.array([p.max(axis=0) for p in paths])
    group = _apart_groups(lo, hi, APART_GAP)
    assert group[-4] == group[-3] and group[-2] != group[-1]
    for g in range(group.max() + 1):
        for h in range(g + 1, group.max() + 1):
            a, b = group == g, group == h
            sep = np.maximum(lo[b].min(axis=0) - hi[a].max(axis=0),
                             lo[a].min(axis=0) - hi[b].max(axis=0))
            assert sep.max() > APART_GAP
    # the flat rings from the highest top down, ties from the left
    sizes = np.array([len(p) for p in paths])
    f_sizes, f_q, _ = _union(sizes, np.concatenate(paths).astype(np.int64), FILL_TYPES[rule])
    rows = np.split(f_q, np.cumsum(f_sizes)[:-1])
    tops = [(-r[:, 1].max(), r[r[:, 1] == r[:, 1].max(), 0].min()) for r in rows]
    assert tops == sorted(tops) and len(tops) > 20


def test_tree_pass_only_for_the_groups_that_need_it():
    """packed_filled_rings on two groups of paths apart: one whose flat ring visits
    a grid point twice (two squares meeting at a corner, one with a hole: Clipper's
    tree pass decides it), one of nested squares (nested in numpy).  The rings, hole flags
    and parents are those of Clipper's tree pass on each group's paths, the second
    group's rings keep their group number, and parents come first."""
    from morph.trim.topology import packed_filled_rings

    def square(x, y, s, ccw=True):
        p = np.array([[x, y], [x + s, y], [x + s, y + s], [x, y + s]], np.int64)
        return p if ccw else p[::-1]

    bow = [square(0, 0, 10), square(10, 10, 10), square(2, 2, 4, ccw=False)]
    nest = [square(1000, 0, 60), square(1010, 10, 40, ccw=False), square(1020, 20, 20)]
    paths = bow + nest
    got = packed_filled_rings(np.array([len(p) for p in paths]), np.concatenate(paths),
                              "nonzero")
    rings = got.to_list()
    keys = [frozenset(map(tuple, r.q.tolist())) for r in rings]
    assert all(r.parent < k for k, r in enumerate(rings))
    want = _tree_rings([p.tolist() for p in bow]) | _tree_rings([p.tolist() for p in nest])
    assert {(keys[k], r.hole, keys[r.parent] if r.parent >= 0 else None)
            for k, r in enumerate(rings)} == want
    nested = [r for r in rings if r.q[:, 0].min() >= 1000]
    assert len(nested) == 3 and len({r.group for r in nested}) == 1 and nested[0].group >= 0
    assert [r.group for r in rings if r.q[:, 0].max() <= 20] == [-1] * (len(rings) - 3)
    assert any(r.hole and r.parent >= 0 for r in rings if r.q[:, 0].max() <= 20)
