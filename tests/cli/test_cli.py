"""The morph CLI through click's CliRunner: outputs, one-line errors, exit codes."""

import numpy as np
import pytest
from PIL import Image

import morph
from morph import cli
from morph.cli import main

SVG_NS = 'xmlns="http://www.w3.org/2000/svg"'


def one_error_line(result):
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("morph: error: ")
    return lines[0]


def test_version(runner):
    result = runner.invoke(main, ["--version"])
    assert result.exit_code == 0 and morph.__version__ in result.output


def test_help_reads_like_a_manual(runner):
    result = runner.invoke(main, ["outline", "--help"])
    assert result.exit_code == 0
    for word in ("--font", "--tol", "--output", "--force", "--size", "em", "user units",
                 "Examples"):
        assert word in result.output


def test_outline_png(runner, tmp_path):
    out = tmp_path / "g.png"
    result = runner.invoke(main, ["outline", "g", "-o", str(out), "--size", "200"])
    assert result.exit_code == 0, result.output
    img = Image.open(out)
    assert max(img.size) == 200
    values = np.unique(np.asarray(img.convert("L")))
    assert values.min() == 0 and values.max() == 255 and len(values) > 8  # anti-aliased


def test_outline_svg_with_cubic_font(runner, tmp_path):
    out = tmp_path / "B.svg"
    from morph.parse import cubic_test_font_path
    result = runner.invoke(main, ["outline", "B", "--font", cubic_test_font_path(),
                                  "-o", str(out), "--tol", "1e-5"])
    assert result.exit_code == 0, result.output
    text = out.read_text()
    assert "<path" in text and " C" not in text and "C" in text


def test_outline_svg_input(runner, tmp_path, monkeypatch):
    src = tmp_path / "ring.svg"
    src.write_text('<svg %s><path fill-rule="evenodd" d="M -10 0 A 10 10 0 0 1 10 0 '
                   'A 10 10 0 0 1 -10 0 Z M -4 0 A 4 4 0 0 1 4 0 A 4 4 0 0 1 -4 0 Z"/></svg>'
                   % SVG_NS)
    work = tmp_path / "cwd"
    work.mkdir()
    monkeypatch.chdir(work)
    result = runner.invoke(main, ["outline", str(src), "--size", "64"])
    assert result.exit_code == 0, result.output
    img = np.asarray(Image.open("outline-ring.png").convert("L"))
    assert img.shape == (64, 64)
    assert img[32, 32] == 255 and img[32, 10] == 0  # hole in the middle, ring filled


def test_default_output_name_in_cwd(runner, tmp_path, monkeypatch):
    work = tmp_path / "cwd"
    work.mkdir()
    monkeypatch.chdir(work)
    result = runner.invoke(main, ["outline", "g", "--size", "32"])
    assert result.exit_code == 0
    assert Image.open("outline-g.png").size[1] == 32
    result = runner.invoke(main, ["outline", "&", "--size", "32"])
    assert result.exit_code == 0
    assert Image.open("outline-ampersand.png")


def test_missing_glyph_exit_2_one_line(runner, tmp_path):
    result = runner.invoke(main, ["outline", "\u4e00", "-o", str(tmp_path / "x.png")])
    assert result.exit_code == 2
    line = one_error_line(result)
    assert "no glyph" in line
    assert not (tmp_path / "x.png").exists()


def test_existing_output_not_overwritten(runner, tmp_path):
    out = tmp_path / "g.png"
    out.write_bytes(b"keep me")
    result = runner.invoke(main, ["outline", "g", "-o", str(out)])
    assert result.exit_code == 2
    assert "--force" in one_error_line(result)
    assert out.read_bytes() == b"keep me"
    result = runner.invoke(main, ["outline", "g", "-o", str(out), "--force", "--size", "32"])
    assert result.exit_code == 0 and Image.open(out).size[1] == 32


@pytest.mark.parametrize("args, words", [
    (["outline", "g", "-o", "x.jpg"], "suffix"),
    (["outline", "g", "--tol", "0"], "tol"),
    (["outline", "g", "--bogus"], "bogus"),
    (["outline"], "SHAPE"),
    (["nocommand"], "nocommand"),
    (["outline", "g", "--font", "/no/such/font.ttf"], "no such file"),
    (["outline", "missing.svg"], "missing.svg"),
    (["outline", "g", "-o", "/no/such/dir/g.png"], "does not exist"),
])
def test_bad_input_exit_2(runner, tmp_path, monkeypatch, args, words):
    work = tmp_path / "cwd"
    work.mkdir()
    monkeypatch.chdir(work)
    result = runner.invoke(main, args)
    assert result.exit_code == 2, result.output
    assert words in one_error_line(result)


def test_bad_svg_file_exit_2(runner, tmp_path):
    src = tmp_path / "neg.svg"
    src.write_text('<svg %s><circle id="c" r="-3"/></svg>' % SVG_NS)
    result = runner.invoke(main, ["outline", str(src), "-o", str(tmp_path / "o.png")])
    assert result.exit_code == 2 and "negative r" in one_error_line(result)


def test_malformed_operand_exit_2_one_line(runner, tmp_path, monkeypatch):
    """An operand that bounds no region (here a clockwise outer loop, as a reader
    that did not orient its loops would give) is bad input: OperandError, exit 2."""
    import morph.parse
    from morph.parse import Shape

    real = morph.parse.load_shape

    def clockwise(arg, font=None, location=None):
        shape = real(arg, font, location)
        if arg != "o":
            return shape
        loops = [[morph.piece.reverse(p) for p in reversed(loop)] for loop in shape.region]
        return Shape(loops, shape.name, shape.source, shape.units_per_em)

    monkeypatch.setattr(morph.parse, "load_shape", clockwise)
    result = runner.invoke(main, ["sum", "o", "x", "-o", str(tmp_path / "s.svg")])
    assert result.exit_code == 2 and "negative signed area" in one_error_line(result)
    assert not (tmp_path / "s.svg").exists()


def test_internal_error_exit_1_and_debug(runner, tmp_path, monkeypatch):
    def boom(*args, **kwargs):
        raise RuntimeError("kaboom")

    monkeypatch.setattr(cli.shapes, "write_image", boom)
    result = runner.invoke(main, ["outline", "g", "-o", str(tmp_path / "g.png")])
    assert result.exit_code == 1
    line = one_error_line(result)
    assert "internal error" in line and "kaboom" in line
    monkeypatch.setenv("MORPH_DEBUG", "1")
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(main, ["outline", "g", "-o", str(tmp_path / "g.png")])
    assert result.exit_code == 1 and "Traceback" in result.stderr
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith("morph: error: internal error in morph outline") and "kaboom" in last
    saved = tmp_path / "morph-debug-outline.json"
    assert str(saved) in last
    import json
    from morph import moments as mo
    from morph.parse import glyph_region
    data = json.loads(saved.read_text())
    loops = [[np.array(p) for p in loop] for loop in data["shapes"][0]["loops"]]
    assert mo.region_area(loops) == mo.region_area(glyph_region("g").region)


@pytest.mark.parametrize("error", ["TopologyError", "ToleranceNotMetError"])
def test_engine_failures_are_internal_exit_1(runner, tmp_path, monkeypatch, error):
    """A failure of the engine is not bad input: exit 1, one line naming the command."""
    import morph.errors

    def fail(*args, **kwargs):
        raise getattr(morph.errors, error)("loops do not close")

    import morph.minkowski

    monkeypatch.setattr(morph.minkowski, "minkowski_sum", fail)
    result = runner.invoke(main, ["sum", "T", "o", "-o", str(tmp_path / "s.png")])
    assert result.exit_code == 1
    line = one_error_line(result)
    assert "internal error in morph sum" in line and error in line


def test_bare_morph_shows_the_manual(runner):
    result = runner.invoke(main, [])
    assert result.exit_code == 0 and "outline" in result.output


def test_console_script_exits_fast_with_its_output_flushed(tmp_path):
    """The console entry (``run``: main, then os._exit without the interpreter's
    teardown) still writes the file, flushes stdout and stderr through a pipe and
    exits with the command's code: 0, 2 for bad input; ``python -m morph`` is the
    same command."""
    import subprocess
    import sys

    out = tmp_path / "om.svg"
    ok = subprocess.run([sys.executable, "-m", "morph.cli", "sum", "O", "M", "-o", str(out)],
                        capture_output=True, text=True, timeout=120)
    assert ok.returncode == 0, ok.stderr
    assert ok.stdout.startswith("wrote %s" % out) and ok.stdout.endswith("\n")
    assert out.read_text().rstrip().endswith("</svg>")
    bad = subprocess.run([sys.executable, "-m", "morph", "sum", "O", "M", "-o", str(out)],
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and "exists" in bad.stderr


def test_written_line_counts_loops_and_pieces(runner, tmp_path):
    """The line after writing names the file and counts, singular where one."""
    out = tmp_path / "om.svg"
    res = runner.invoke(main, ["sum", "O", "M", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert res.output.startswith("wrote %s (1 loop, " % out) and res.output.endswith(" pieces)\n")
    res = runner.invoke(main, ["offset", "o", "--radius", "0.01", "-o", str(tmp_path / "o.svg")])
    assert "(2 loops, " in res.output
