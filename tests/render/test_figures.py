"""morph.render.figures: the C-space figure and animation frames written to a folder."""

import numpy as np
from PIL import Image

from morph import piece as pc
from morph.region import region_bbox
from tests.imagediff import gray


def test_cspace_figure_places_robots_on_the_boundary():
    """cspace_figure: the C-space region, the obstacle, then a robot outline and a dot
    at each of ``samples`` points of the C-space boundary, evenly spread by length."""
    from morph.render import cspace_figure

    obstacle = [pc.circle((0.0, 0.0), 2.0)]
    robot = [pc.circle((0.0, 0.0), 0.5)]
    cspace = [pc.circle((0.0, 0.0), 2.5)]
    shapes = cspace_figure(obstacle, robot, cspace, 1e-3, samples=4)
    assert len(shapes) == 2 + 2 * 4 and shapes[1][0] is obstacle
    dots = [region_bbox(loops) for loops, style in shapes[3::2]]
    centres = np.array([[(b[0] + b[2]) / 2, (b[1] + b[3]) / 2] for b in dots])
    assert np.allclose(np.hypot(*centres.T), 2.5, atol=2e-3)  # on the boundary
    angles = np.sort(np.arctan2(centres[:, 1], centres[:, 0]))
    assert np.allclose(np.diff(angles), np.pi / 2, atol=2e-3)  # evenly spread
    assert len(cspace_figure(obstacle, robot, cspace, 1e-3, samples=0)) == 2


def test_write_frames(tmp_path):
    from morph.render import write_frames

    regions = [[pc.circle((0.0, 0.0), r)] for r in (1.0, 2.0, 3.0)]
    write_frames(tmp_path, regions, size=64, tol=1e-3, duration=50)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["frame-000.png", "frame-000.svg", "frame-001.png", "frame-001.svg",
                     "frame-002.png", "frame-002.svg", "morph.gif"]
    small, large = (gray(Image.open(tmp_path / n)) for n in ("frame-000.png", "frame-002.png"))
    assert small.shape == large.shape and (small < 128).sum() < (large < 128).sum()
