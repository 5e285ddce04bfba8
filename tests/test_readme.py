"""The README's library example runs as written (it is the documentation), and the SVG
it writes holds the sum it computed."""

import re
from pathlib import Path

import numpy as np

from tests.helpers import loop_polygons, shoelace

README = Path(__file__).resolve().parents[1] / "README.md"


def _area_and_perimeter(region, flat):
    polys = loop_polygons(region, flat)
    perimeter = sum(float(np.linalg.norm(np.roll(p, -1, 0) - p, axis=1).sum()) for p in polys)
    return sum(shoelace(p) for p in polys), perimeter


def test_readme_python_example_runs(tmp_path, monkeypatch):
    from morph.parse import load_shape

    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert blocks, "README has no python examples"
    monkeypatch.chdir(tmp_path)  # the example writes images
    scope = {}
    exec(compile("\n".join(blocks), str(README), "exec"), scope)
    assert (tmp_path / "om.png").stat().st_size > 0
    # read back, the SVG encloses the sum's area to within its half of tol along the
    # outline (both flattened within 1e-3 tol, far below what is compared)
    s, tol = scope["s"], scope["tol"]
    back = load_shape(str(tmp_path / "om.svg")).region
    area, perimeter = _area_and_perimeter(s, 1e-3 * tol)
    area_back, _ = _area_and_perimeter(back, 1e-3 * tol)
    assert len(back) == len(s)
    assert abs(area_back - area) <= perimeter * (tol / 2 + 2e-3 * tol)
    assert area > 0
