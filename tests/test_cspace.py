"""C-space obstacles: p is in O ⊕ (ref − R) iff the robot placed at p overlaps O."""

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely
from click.testing import CliRunner
from shapely.geometry import Point

from morph.cli import main
from morph.cspace import cspace_obstacle, place_robot
from morph.parse import glyph_region
from morph.region import point_in_region, region_bbox, region_centroid
from tests.oracles.reference import region_polylines, region_to_shapely

TOL = 0.5


@pytest.mark.parametrize("obstacle,robot,use_centroid", [("o", "v", True), ("e", "y", False)])
def test_random_placements_agree_with_polygon_overlap(obstacle, robot, use_centroid):
    obs = glyph_region(obstacle).region
    rob = glyph_region(robot).region
    ref = region_centroid(rob) if use_centroid else np.zeros(2)
    cs = cspace_obstacle(obs, rob, TOL, reference=ref)
    flat = TOL / 4
    obs_poly = region_to_shapely(obs, flat)
    rob_poly = region_to_shapely(rob, flat)
    cs_lines = region_polylines(cs, flat)
    box = region_bbox(cs)
    rng = np.random.default_rng(7)
    pad = 0.1 * (box[2] - box[0])
    pts = rng.uniform([box[0] - pad, box[1] - pad], [box[2] + pad, box[3] + pad], (1000, 2))
    inside = point_in_region(pts, cs, flat)
    # distance to the C-space boundary: skip near-boundary points
    pytest.importorskip("shapely")
    from shapely.geometry import LineString, MultiLineString
    bnd = MultiLineString([LineString(np.vstack([p, p[:1]])) for p in cs_lines])
    pytest.importorskip("shapely")
    from shapely import affinity
    mismatches, checked = 0, 0
    for p, ins in zip(pts, inside):
        if bnd.distance(Point(p)) < 2 * TOL + flat:
            continue
        placed = affinity.translate(rob_poly, p[0] - ref[0], p[1] - ref[1])
        checked += 1
        if placed.intersects(obs_poly) != bool(ins):
            mismatches += 1
    assert checked > 900
    assert inside.sum() > 100 and (~inside).sum() > 100
    assert mismatches == 0


def test_place_robot_moves_reference_point():
    rob = glyph_region("v").region
    ref = region_centroid(rob)
    moved = place_robot(rob, (10.0, 20.0), ref)
    assert np.allclose(region_centroid(moved), (10.0, 20.0))


def test_cli_cspace(tmp_path):
    out = tmp_path / "c.png"
    r = CliRunner().invoke(main, ["cspace", "O", "v", "-o", str(out), "--size", "96"])
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 0


def test_cspace_obstacle_reports_the_error_it_achieved():
    """The result's bound is in (0, tol] (what `morph cspace`
    gives its export the rest of --tol beyond)."""
    obs, rob = glyph_region("o").region, glyph_region("v").region
    plain = cspace_obstacle(obs, rob, TOL)
    loops = cspace_obstacle(obs, rob, TOL)
    bound = loops.bound
    assert [len(loop) for loop in loops] == [len(loop) for loop in plain]
    assert 0.0 < bound <= TOL


ROOM = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">'
        '<path d="M10 10 H190 V190 H120 V80 H80 V190 H10 Z"/>'
        '<path d="M150 40 h20 v20 h-20 Z"/></svg>')        # a U-shaped room, a pillar
ROBOT = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 40 40">'
         '<path d="M0 0 L30 0 L0 20 Z"/><circle cx="10" cy="25" r="8"/></svg>')


def _placements_agree(free, room, robot, ref, tol, seed):
    """Random positions p away from the free space's boundary (2 tol + flattening):
    p is in the free space iff the robot placed at p lies inside the room (shapely
    polygons of both, flattened within tol / 4).  Boundary samples of the free space:
    the placed robot touches a wall (inside the room grown by that margin, not inside
    the room shrunk by it).  Returns the counts inside and outside."""
    pytest.importorskip("shapely")
    from shapely import affinity
    from shapely.geometry import LineString, MultiLineString

    flat = tol / 4
    room_poly, rob_poly = region_to_shapely(room, flat), region_to_shapely(robot, flat)
    margin = 2 * tol + flat
    bnd = MultiLineString([LineString(np.vstack([p, p[:1]]))
                           for p in region_polylines(free, flat)])
    box = region_bbox(room)
    rng = np.random.default_rng(seed)
    pts = rng.uniform(box[:2], box[2:], (1500, 2))
    inside = point_in_region(pts, free, flat)
    counts = [0, 0]
    far = shapely.distance(shapely.points(pts), bnd) >= margin
    for p, ins in zip(pts[far], inside[far]):
        placed = affinity.translate(rob_poly, p[0] - ref[0], p[1] - ref[1])
        assert placed.within(room_poly) == bool(ins), p
        counts[bool(ins)] += 1
    grown, shrunk = room_poly.buffer(margin), room_poly.buffer(-margin)
    for loop in free:
        for p in loop:
            for q in (from_h(p, t) for t in (0.0, 0.3, 0.7)):
                placed = affinity.translate(rob_poly, q[0] - ref[0], q[1] - ref[1])
                assert placed.within(grown) and not placed.within(shrunk), q
    return counts


def from_h(piece, t):
    from morph import piece as pc

    return pc.evaluate(piece, np.array([t]))[0]


@pytest.mark.parametrize("angle", [0.0, 0.7, 2.9])
def test_free_space_inside_a_room_agrees_with_polygon_containment(angle):
    """free_space = room ⊖ (robot − ref) for an asymmetric robot (a triangle and a
    disk: the erosion must reflect it) in a room with a pillar, the robot turned by
    a few angles; the room's convex corners stay sharp, the pillar's get rounded."""
    from morph.cspace import free_space
    from morph.parse import svg_region
    from morph.region import transform_region

    room = svg_region(ROOM)
    c, s = np.cos(angle), np.sin(angle)
    robot = transform_region(svg_region(ROBOT), [[c, -s, 0.0], [s, c, 0.0]])
    ref = region_centroid(robot)
    free = free_space(room, robot, 0.01, reference=ref)
    bound = free.bound
    assert 0.0 < bound <= 0.01
    inside, outside = _placements_agree(free, room, robot, ref, 0.01, seed=int(10 * angle))
    assert inside > 200 and outside > 200


def test_free_space_is_empty_where_the_robot_fits_nowhere(tmp_path):
    from morph.cspace import free_space

    assert len(free_space(glyph_region("O").region, glyph_region("period").region, TOL)) == 0
    (tmp_path / "room.svg").write_text(ROOM)
    (tmp_path / "robot.svg").write_text(ROBOT)
    r = CliRunner().invoke(main, ["cspace", "O", "period", "--inside", "-o",
                                  str(tmp_path / "x.png")])
    assert r.exit_code == 2 and "fits nowhere inside glyph 'O'" in r.output
    assert not (tmp_path / "x.png").exists()
    out = tmp_path / "free.svg"
    r = CliRunner().invoke(main, ["cspace", str(tmp_path / "room.svg"),
                                  str(tmp_path / "robot.svg"), "--inside", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert out.read_text().count("<path") >= 3      # free space, room, robots
