"""morph.stroke.stroke_paths (open path ⊕ nib) against Clipper's polygon Minkowski sum
of the finely flattened path and nib (an independent computation), with shapely for
areas and Hausdorff distances."""

import numpy as np
import pyclipper
import pytest
pytest.importorskip("shapely")
import shapely
from shapely.geometry import Polygon

from morph import piece as pc
from morph import moments as mo
from morph import polyline as pl
from morph.fonts.brush import ellipse_nib
from morph.stroke import stroke_paths
from tests.helpers import pencil_path

FLAT = 5e-3  # reference flattening (both operands), in path units
SCALE = 1e4  # Clipper integer scale of the reference


def _reference(paths, nib):
    """Union of MinkowskiSum(nib polygon, path polyline) in Clipper (open paths)."""
    nib_poly = pyclipper.scale_to_clipper(pl.flatten_loop(nib[0], FLAT), SCALE)
    parts = []
    for pieces, closed in paths:
        pts = np.concatenate([pl.flatten(p, FLAT)[0] for p in pieces])
        parts += pyclipper.MinkowskiSum(nib_poly, pyclipper.scale_to_clipper(pts, SCALE), closed)
    clip = pyclipper.Pyclipper()
    clip.AddPaths(parts, pyclipper.PT_SUBJECT, True)
    tree = clip.Execute2(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    polys, stack = [], list(tree.Childs)
    while stack:  # outer contours with their holes; islands in holes are outers again
        node = stack.pop()
        holes = [np.array(h.Contour) / SCALE for h in node.Childs]
        polys.append(Polygon(np.array(node.Contour) / SCALE, holes))
        stack.extend(g for h in node.Childs for g in h.Childs)
    return shapely.unary_union(polys)


def _ours(loops, tol):
    outer = [Polygon(pl.flatten_loop(l, tol / 4)) for l in loops if mo.loop_area(l) > 0]
    holes = [Polygon(pl.flatten_loop(l, tol / 4)) for l in loops if mo.loop_area(l) < 0]
    return shapely.unary_union(outer).difference(shapely.unary_union(holes))


def _check(paths, nib, tol):
    loops = stroke_paths(paths, nib, tol)
    ours, ref = _ours(loops, tol), _reference(paths, nib)
    # boundary distance: our curves within tol of the reference boundary, plus the
    # reference's own flattening and our drawing's tol / 4
    h = ours.boundary.hausdorff_distance(ref.boundary)
    assert h <= tol + 2 * FLAT + tol / 4, h
    assert abs(ours.area - ref.area) <= (tol + 2 * FLAT) * ref.boundary.length
    return loops


@pytest.mark.parametrize("seed", range(4))
def test_random_cubic_and_ellipse_nib_at_random_angles(seed):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0, 100, size=(4, 2))
    angle = rng.uniform(0, 180)
    print("seed", seed, "angle", angle)
    nib = ellipse_nib(rng.uniform(10, 30), rng.uniform(2, 10), angle)
    _check([([pc.cubic(*pts)], False)], nib, 0.05)


def test_polyline_with_sharp_corners_and_a_disk():
    p = [(0, 0), (50, 0), (10, 30), (60, 40)]
    pieces = [pc.line(p[i], p[i + 1]) for i in range(3)]
    nib = [list(pc.circle((0.0, 0.0), 6.0))]
    loops = _check([(pieces, False)], nib, 0.02)
    assert len(loops) >= 1


def test_closed_path_keeps_its_counter():
    circle = list(pc.circle((0.0, 0.0), 40.0))
    loops = _check([(circle, True)], ellipse_nib(20, 6, 30), 0.05)
    assert sorted(np.sign(mo.loop_area(l)) for l in loops) == [-1, 1]


def test_paths_are_united_and_dots_are_the_nib():
    nib = ellipse_nib(12, 4, 30)
    cross = [([pc.line((0, 0), (50, 50))], False), ([pc.line((0, 50), (50, 0))], False)]
    loops = _check(cross, nib, 0.05)
    assert len(loops) == 1
    dot = stroke_paths([([pc.line((7.0, 3.0), (7.0, 3.0))], False)], nib, 0.05)
    assert mo.region_area(dot) == pytest.approx(np.pi * 6 * 2, rel=1e-9)


def test_stroke_many_each_result_against_its_own_reference():
    """Several path sets stroked together (the font commands' packed call): random
    cubics, a closed path with its counter, crossing lines, a dot beside a line (an
    i), and a set of a dot alone; each result against the Clipper reference of its
    own paths, the empty set gives an empty region."""
    from morph.stroke import stroke_many

    rng = np.random.default_rng(11)
    nib, tol = ellipse_nib(14, 4, 30), 0.05
    sets = [[([pc.cubic(*rng.uniform(0, 100, size=(4, 2)))], False)] for _ in range(3)]
    sets.append([(list(pc.circle((0.0, 0.0), 40.0)), True)])
    sets.append([([pc.line((0, 0), (50, 50))], False), ([pc.line((0, 50), (50, 0))], False)])
    sets.append([([pc.line((0, 0), (0, 60))], False), ([pc.line((0, 80), (0, 80))], False)])
    sets.append([([pc.line((7.0, 3.0), (7.0, 3.0))], False)])
    sets.append([])
    out = stroke_many(sets, nib, tol)
    assert len(out) == len(sets) and out[-1] == []
    for paths, loops in zip(sets[:5], out[:5]):   # the reference has no dots
        ours, ref = _ours(loops, tol), _reference(paths, nib)
        assert ours.boundary.hausdorff_distance(ref.boundary) <= tol + 2 * FLAT + tol / 4
        assert abs(ours.area - ref.area) <= (tol + 2 * FLAT) * ref.boundary.length
    assert sorted(np.sign(mo.loop_area(l)) for l in out[3]) == [-1, 1]
    # the i: the stem against its reference, the dot the nib at (0, 80)
    stem = [l for l in out[5] if pc.bbox(l[0])[3] < 70]
    dot = [l for l in out[5] if pc.bbox(l[0])[1] > 70]
    assert len(stem) == 1 and len(dot) == 1
    ref = _reference(sets[5][:1], nib)
    assert _ours(stem, tol).boundary.hausdorff_distance(ref.boundary) <= tol + 2 * FLAT + tol / 4
    assert mo.region_area(dot) == pytest.approx(np.pi * 7 * 2, rel=1e-9)
    assert mo.region_area(out[6]) == pytest.approx(np.pi * 7 * 2, rel=1e-9)


@pytest.mark.parametrize("seed", range(3))
def test_stroke_far_from_the_origin_is_the_stroke_moved(seed):
    """Short paths traced back on themselves (Relief's i: a 2-unit serif line) turn
    the same way at their ends wherever they lie: the stroke of the paths moved by
    a few thousand units is the stroke moved (it lost a cap, 47 units^2, at 10 of
    41 random offsets when the cusp's side was decided on absolute coordinates)."""
    rng = np.random.default_rng(seed)
    nib, tol = ellipse_nib(90, 20, 30), 0.25
    paths = [([pc.line((140, 0), (140, 555))], False), ([pc.line((141, 555), (139, 555))], False),
             ([pc.line((140, 678), (140, 785))], False), ([pc.line((141, 785), (139, 785))], False)]
    base = stroke_paths(paths, nib, tol)
    for _ in range(8):
        off = rng.uniform(-5000, 5000, 2)
        moved = [([pc.translate(p, off) for p in pieces], cl) for pieces, cl in paths]
        got = stroke_paths(moved, nib, tol)
        assert len(got) == len(base)
        assert mo.region_area(got) == pytest.approx(mo.region_area(base), abs=1e-3), off


@pytest.mark.parametrize("points", [[(0, 0), (60, 0), (30, 0)],
                                    [(0, 0), (60, 0), (30, 0), (30, 40)],
                                    [(0, 0), (60, 0), (15, 0), (45, 0), (20, 10)]])
def test_a_path_running_back_over_itself_is_stroked_exactly(points):
    """A centre line that turns back over its own trace (a pen retracing a stroke)
    is cut at its reversals and stroked part by part: the union is the path's
    stroke (Clipper reference).  Traced forward and back whole, its loop would turn
    twice and be refused (it was stroked with a cap missing before)."""
    nib, tol = ellipse_nib(14, 4, 30), 0.05
    pieces = [pc.line(points[i], points[i + 1]) for i in range(len(points) - 1)]
    loops = stroke_paths([(pieces, False)], nib, tol)
    ours, ref = _ours(loops, tol), _reference([(pieces, False)], nib)
    assert ours.boundary.hausdorff_distance(ref.boundary) <= tol + 2 * FLAT + tol / 4
    assert abs(ours.area - ref.area) <= (tol + 2 * FLAT) * ref.boundary.length


def test_loop_stacks_hold_the_loops_pieces_in_order():
    """The stacks _loops_and_dots_many hands to minkowski_sums are the pieces of
    its loops, set by set, loop by loop, to the bit (what the sum would gather
    from the loops); sets of lines, curves, a path turning back on itself, a dot
    and an empty set."""
    from morph.stroke import _loops_and_dots_many

    rng = np.random.default_rng(5)

    def path(n, closed=False):
        pts = rng.uniform(0, 500, (n + 1, 2))
        pieces = [pc.from_points(pts[i:i + 2]) if rng.random() < 0.6 else
                  pc.from_points(np.array([pts[i], pts[i] + rng.uniform(-50, 50, 2),
                                           pts[i + 1]]))
                  for i in range(n)]
        return pieces, closed

    back = [pc.line((0, 0), (100, 0)), pc.line((100, 0), (10, 0))]     # turns back
    dot = [pc.line((5, 5), (5, 5))]
    sets = [[path(4), path(1)], [], [(back, False)], [(dot, False)], [path(6, True)]]
    loops, dots, stacked = _loops_and_dots_many(sets, ellipse_nib(30, 8, 30))
    pieces = [p for k in range(len(sets)) for loop in loops[k] for p in loop]
    assert len(stacked) == len(pieces) and dots[3] and not loops[1]
    want = pc.Pieces.of(pieces)
    assert [(ks.tolist(), h.tobytes()) for ks, h in stacked.groups] == \
        [(ks.tolist(), h.tobytes()) for ks, h in want.groups]
    assert all(np.array_equal(a, b) for a, b in zip(stacked, pieces))


@pytest.mark.parametrize("seed", range(6))
def test_a_closed_path_through_its_own_start_stroked_alone(seed):
    """A closed path that runs on smoothly through its start, stroked alone (one
    region: not packed with others) at a random angle and scale: its loop traced out
    and back has both tips at that point, where the trace goes on through them; the
    tips are known to turn +pi (the stroke's paths are traced), not judged by a probe
    beyond them, which would probe the trace itself (it read one tip as -pi and
    refused the loop as crossing itself: feather's edit-2 icon, every nib angle).
    Against the Clipper reference, with its counter."""
    rng = np.random.default_rng(seed)
    scale = float(np.exp(rng.uniform(np.log(0.5), np.log(20.0))))
    path = pencil_path(rng.uniform(0, 360), scale)
    nib = ellipse_nib(2.0 * scale, rng.uniform(0.3, 1.5) * scale, rng.uniform(0, 180))
    loops = _check([(path, True)], nib, 0.01 * scale)
    assert sorted(np.sign(mo.loop_area(l)) for l in loops) == [-1, 1]
