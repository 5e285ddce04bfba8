"""morph.render's API: the shapes the writers accept (normalize_shapes)."""

import pytest
from PIL import Image

from morph import piece as pc
from morph.region import Region
from morph.render import normalize_shapes, write_png


def test_region_object_and_list_of_regions_accepted(tmp_path):
    r = Region([pc.circle((0, 0), 1.0)])
    assert len(normalize_shapes(r)) == 1
    assert len(normalize_shapes([r, list(r)])) == 2
    with pytest.raises(ValueError):
        normalize_shapes([])
    with pytest.raises(ValueError):
        normalize_shapes([[1, 2, 3]])
    write_png(tmp_path / "r.png", r, size=32)
    assert Image.open(tmp_path / "r.png").size == (32, 32)
