"""Image-diff tests of cheap gallery figures (goldens: MORPH_UPDATE_GOLDEN=1)."""

import importlib.util
from pathlib import Path

import pytest

from tests.imagediff import assert_matches_golden

_PATH = Path(__file__).resolve().parent.parent / "gallery" / "make_gallery.py"


@pytest.fixture(scope="module")
def gallery():
    spec = importlib.util.spec_from_file_location("make_gallery", _PATH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("name", ["fig01_convex", "fig02_nonconvex"])
def test_gallery_figure_matches_golden(gallery, name):
    img, shapes, tol = gallery.render(getattr(gallery, name), 240)
    assert_matches_golden(img, "gallery-" + name)


def test_gallery_svg_written(gallery, tmp_path):
    from morph.render import write_svg

    shapes, tol = gallery.fig01_convex()
    out = tmp_path / "f.svg"
    write_svg(str(out), shapes, size=200, tol=tol)
    text = out.read_text()
    assert text.count("<path") == 3
