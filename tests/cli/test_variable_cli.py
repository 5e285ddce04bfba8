"""``morph stroke --vary-nib``: the variable font, its side outputs, bad input."""

import pytest

from morph.cli import main
from tests import RELIEF_SUBSET

NIBS = ["--nib", "ellipse:40,10,30", "--vary-nib", "ellipse:120,30,30"]


def test_variable_stroke_writes_font_designspace_and_masters(runner, tmp_path):
    out = tmp_path / "Nib.ttf"
    args = ["stroke", str(RELIEF_SUBSET), "-o", str(out), *NIBS, "--glyphs", "s,o",
            "--jobs", "1"]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "variable, axes NIBW Nib width 40..120" in result.output
    masters = tmp_path / "Nib-masters"
    for p in (out, tmp_path / "Nib.designspace", masters, tmp_path / "Nib.ttf.png",
              tmp_path / "Nib.ttf.html"):
        assert p.exists(), p
    assert len(list(masters.glob("*.ufo"))) == 2
    again = runner.invoke(main, args)
    assert again.exit_code == 2 and "use --force" in again.output
    stale = masters / "Old.ufo"
    stale.mkdir()
    forced = runner.invoke(main, args + ["--force"])
    assert forced.exit_code == 0, forced.output
    assert not stale.exists()                   # --force leaves nothing stale


@pytest.mark.parametrize("extra,output,message", [
    (NIBS, "Nib.ufo", "must end in .ttf"),
    (["--nib", "ellipse:40,10,30", "--vary-nib", "ellipse:40,10,30"], "Nib.ttf",
     "is the --nib nib"),
    (["--vary-nib", "ellipse:0,10,30"], "Nib.ttf", "--vary-nib width and height"),
    (["--vary-nib", "ellipse:80,20,30", "--nib-svg", "nib.svg"], "Nib.ttf", "not --nib-svg"),
])
def test_variable_stroke_bad_input(runner, tmp_path, extra, output, message):
    result = runner.invoke(main, ["stroke", str(RELIEF_SUBSET), "-o", str(tmp_path / output),
                                  *extra])
    assert result.exit_code == 2, result.output
    assert message in result.output and len(result.output.strip().splitlines()) == 1
    assert "Traceback" not in result.output


def test_variable_stroke_of_svg_is_refused(runner, tmp_path):
    svg = tmp_path / "a.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 L10 10" '
                   'stroke="black"/></svg>')
    result = runner.invoke(main, ["stroke", str(svg), "-o", str(tmp_path / "x.svg"),
                                  "--vary-nib", "ellipse:8,2,30"])
    assert result.exit_code == 2 and "needs a UFO skeleton" in result.output


def test_stroke_help_says_which_outputs_overlap(runner):
    text = runner.invoke(main, ["stroke", "--help"]).output
    assert "--vary-nib" in text and "overlapping" in text and "trimmed" in text
