"""The font and shape workflow at its edges: what a new user and real fonts hit
(missing name records, side outputs of two formats, --force on frame folders,
misleading errors, progress, tolerance units)."""

import os

import pytest
from fontTools.ttLib import TTFont

from morph.cli import main
from morph.parse import cubic_test_font_path


def one_error_line(result):
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("morph: error: ")
    return lines[0]


@pytest.fixture(scope="module")
def font_without_full_name(tmp_path_factory):
    """The bundled CFF font, which has no name ID 4 (full name) or 6, as some real
    fonts have not (removed again in case a later version adds them)."""
    font = TTFont(cubic_test_font_path())
    font["name"].removeNames(nameID=4)
    path = tmp_path_factory.mktemp("nameless") / "NoFullName.otf"
    font.save(str(path))
    return path


def test_brush_font_without_full_name(runner, tmp_path, monkeypatch, font_without_full_name):
    """A missing name record is normal: the font, sample and specimen are written,
    exit 0, and no debug file appears in the working folder."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("MORPH_DEBUG", raising=False)
    out = tmp_path / "BrushCFF.otf"
    res = runner.invoke(main, ["brush", str(font_without_full_name), "-o", str(out),
                               "--glyphs", "o"])
    assert res.exit_code == 0, res.output
    assert out.is_file()
    pages = [p for p in tmp_path.iterdir() if p.suffix == ".html"]
    assert len(pages) == 1
    text = pages[0].read_text()
    assert "Noto Sans" in text  # the source named by its family and style
    assert not [p for p in os.listdir(tmp_path) if p.startswith("morph-debug")]


def test_display_name_falls_back_on_family_and_style(font_without_full_name):
    from morph.parse import font_display_name

    font = TTFont(str(font_without_full_name))
    assert font_display_name(font) == "Noto Sans CFF Regular"
    for nid in (1, 2, 16, 17):
        font["name"].removeNames(nameID=nid)
    font["name"].setName("NotoSansCFF-Regular", 6, 3, 1, 0x409)
    assert font_display_name(font) == "NotoSansCFF-Regular"  # the PostScript name
    font["name"].removeNames(nameID=6)
    assert font_display_name(font, "x.otf") == "x.otf"
