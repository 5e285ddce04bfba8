"""C-space obstacles: p is in O ⊕ (ref − R) iff the robot placed at p overlaps O."""

import numpy as np
import pytest
from click.testing import CliRunner
from shapely.geometry import Point

from morph.cli import main
from morph.cspace import cspace_obstacle, place_robot
from morph.parse import glyph_region
from morph.region import point_in_region, region_bbox, region_centroid
from tests.reference import region_polylines, region_to_shapely

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
    from shapely.geometry import LineString, MultiLineString
    bnd = MultiLineString([LineString(np.vstack([p, p[:1]])) for p in cs_lines])
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
    """return_bound: the same region and a bound in (0, tol] (what `morph cspace`
    gives its export the rest of --tol beyond)."""
    obs, rob = glyph_region("o").region, glyph_region("v").region
    plain = cspace_obstacle(obs, rob, TOL)
    loops, bound = cspace_obstacle(obs, rob, TOL, return_bound=True)
    assert [len(loop) for loop in loops] == [len(loop) for loop in plain]
    assert 0.0 < bound <= TOL
