"""The font and shape workflow at its edges: what a new user and real fonts hit
(missing name records, side outputs of two formats, --force on frame folders,
misleading errors, progress, tolerance units)."""

import os

import numpy as np

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


# =========================================================================== 2: UFO subsets

def test_stroked_ufo_subset_compiles(runner, tmp_path):
    """``morph stroke SKELETON -o sub.ufo --glyphs ...`` (the help's own example)
    writes a UFO that ufo2ft compiles as it stands, to CFF and TrueType: the glyphs
    not chosen are left empty (advance kept, skeleton moved to the ``skeleton``
    layer), and stderr says so."""
    import ufo2ft
    import ufoLib2

    from tests import RELIEF_SUBSET

    out = tmp_path / "sub.ufo"
    res = runner.invoke(main, ["stroke", str(RELIEF_SUBSET), "-o", str(out), "--glyphs",
                               "H,o", "--tol", "2e-3"])
    assert res.exit_code == 0, res.output
    assert "not chosen" in res.stderr and "skeleton" in res.stderr
    font = ufoLib2.Font.open(out)
    source = ufoLib2.Font.open(RELIEF_SUBSET)
    assert all(not c.open for g in font for c in g.contours)
    assert not font["A"].contours and font["A"].width == source["A"].width
    assert len(font.layers["skeleton"]["A"].contours) == len(source["A"].contours)
    assert "H" not in font.layers["skeleton"]  # stroked glyphs: their outline only
    otf = ufo2ft.compileOTF(font)
    ttf = ufo2ft.compileTTF(font)
    assert otf["CFF "] and ttf["glyf"]["o"].numberOfContours == 2


# =========================================================================== 3: side outputs

def test_side_outputs_of_two_formats_live_side_by_side(runner, tmp_path):
    """The sample image and specimen are named after the whole output name
    (X.ttf -> X.ttf.png, X.ttf.html), so X.ttf and X.woff2 can be built into one
    folder without --force, and --force rewrites only its own side outputs."""
    ttf, woff2 = tmp_path / "X.ttf", tmp_path / "X.woff2"
    for out in (ttf, woff2):
        res = runner.invoke(main, ["brush", "-o", str(out), "--glyphs", "o"])
        assert res.exit_code == 0, res.output
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["X.ttf", "X.ttf.html", "X.ttf.png", "X.woff2", "X.woff2.html",
                     "X.woff2.png"]
    assert 'url("X.woff2")' in (tmp_path / "X.woff2.html").read_text()
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir() if "woff2" in p.name}
    for p in tmp_path.iterdir():  # mark the woff2 build's files
        if "woff2" in p.name:
            os.utime(p, (1, 1))
    res = runner.invoke(main, ["brush", "-o", str(ttf), "--glyphs", "o", "--nib",
                               "ellipse:40,20,0", "--force"])
    assert res.exit_code == 0, res.output
    for p in tmp_path.iterdir():
        if "woff2" in p.name:
            assert p.stat().st_mtime == 1 and p.read_bytes() == before[p.name]


# =========================================================================== 4: frame folders

def test_force_replaces_morphs_own_frames_only(runner, tmp_path):
    """A second run into a frames folder needs --force (the error says so); with it,
    the frames and animation morph wrote before and does not write again are
    removed, and files morph did not write are kept."""
    out = tmp_path / "d"
    args = ["glyph", "T", "M", "-o", str(out), "--size", "32", "--tol", "2e-3"]
    res = runner.invoke(main, args + ["--frames", "4"])
    assert res.exit_code == 0, res.output
    (out / "notes.txt").write_text("mine")
    (out / "frame-7.png").write_text("not morph's naming")
    res = runner.invoke(main, args + ["--frames", "2"])
    assert res.exit_code == 2 and "--force" in one_error_line(res)
    res = runner.invoke(main, args + ["--frames", "2", "--force", "--animation", "apng"])
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in out.iterdir()) == [
        "frame-000.png", "frame-000.svg", "frame-001.png", "frame-001.svg", "frame-7.png",
        "morph.apng", "notes.txt"]


# =========================================================================== 7: errors

BOX_SVG = ('<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 H 100 V 80 H 0 Z"/>'
           '</svg>')


def test_brush_of_a_ufo_points_to_stroke(runner, tmp_path):
    from tests import RELIEF_SUBSET

    res = runner.invoke(main, ["brush", str(RELIEF_SUBSET), "-o", str(tmp_path / "b.ttf")])
    line = one_error_line(res)
    assert res.exit_code == 2 and "morph stroke" in line and "does not exist" not in line


@pytest.mark.parametrize("name", ["picture.png", "sub/picture.png"])
def test_shape_file_that_is_not_svg(runner, tmp_path, monkeypatch, name):
    """A file that is not an SVG document is named as such, not looked up as a
    glyph; a path that does not exist says so."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / name).write_bytes(b"\x89PNG\r\n\x1a\n")
    res = runner.invoke(main, ["outline", name])
    line = one_error_line(res)
    assert res.exit_code == 2 and "not an SVG" in line and "no glyph" not in line
    res = runner.invoke(main, ["outline", "missing/" + name])
    line = one_error_line(res)
    assert res.exit_code == 2 and "no such file" in line


def test_font_given_for_svg_shapes_only(runner, tmp_path):
    from morph.parse import cubic_test_font_path

    box = tmp_path / "box.svg"
    box.write_text(BOX_SVG)
    res = runner.invoke(main, ["svg", str(box), str(box), "--frames", "2", "-o",
                               str(tmp_path / "f"), "--font", cubic_test_font_path()])
    assert res.exit_code == 2 and "--font" in one_error_line(res)
    assert not (tmp_path / "f").exists()


def test_svg_and_glyph_mixed_units_say_so(runner, tmp_path):
    box = tmp_path / "box.svg"
    box.write_text(BOX_SVG)
    res = runner.invoke(main, ["sum", str(box), "o", "-o", str(tmp_path / "s.png"),
                               "--size", "32"])
    assert res.exit_code == 0, res.output
    warning = [s for s in res.stderr.splitlines() if s.startswith("morph: warning:")]
    assert len(warning) == 1 and "user units" in warning[0] and "font units" in warning[0]


# =========================================================================== 12: SVG tolerance

def _ellipse_svg(scale):
    return ('<svg xmlns="http://www.w3.org/2000/svg"><ellipse cx="%g" cy="%g" rx="%g" '
            'ry="%g"/></svg>' % (3 * scale, 2 * scale, 2 * scale, scale))


def _curves(svg):
    """The number of cubic segments (C and S) of a written SVG's path data."""
    import re

    d = re.search(r' d="([^"]*)"', svg.read_text()).group(1)
    return sum(len(re.findall(r"-?[0-9.e]+", part)) // ({"C": 6, "S": 4}[part[0]])
               for part in re.findall(r"[CS][^A-Za-z]*", d))


def test_svg_default_tolerance_is_relative_to_the_drawing(runner, tmp_path):
    """Without --tol an SVG is written within 1e-4 of its size, as a glyph within
    1e-4 em: the same drawing at two scales gives the same curves; an explicit
    --tol is absolute (user units)."""
    counts = []
    for scale in (1.0, 1e4):
        src = tmp_path / ("e%g.svg" % scale)
        src.write_text(_ellipse_svg(scale))
        out = tmp_path / ("o%g.svg" % scale)
        res = runner.invoke(main, ["outline", str(src), "-o", str(out)])
        assert res.exit_code == 0, res.output
        counts.append(_curves(out))
    assert counts[0] == counts[1] > 1
    # explicit --tol: absolute, the larger drawing needs more curves at the same value
    res = runner.invoke(main, ["outline", str(tmp_path / "e10000.svg"), "-o",
                               str(tmp_path / "abs.svg"), "--tol", "1e-4"])
    assert res.exit_code == 0, res.output
    assert _curves(tmp_path / "abs.svg") > counts[1]


def test_tol_help_states_both_defaults(runner):
    res = runner.invoke(main, ["svg", "--help"])
    text = " ".join(res.output.split())
    assert "of the drawing's size" in text and "absolute" in text


# =========================================================================== 5: progress

def test_progress_off_a_terminal_prints_status_lines(runner, tmp_path, monkeypatch):
    """A run whose stderr is not a terminal prints a status line every few seconds
    (here every 10 ms): the glyphs done of all, and the time."""
    from morph.cli import options

    monkeypatch.setattr(options, "STATUS_SECONDS", 0.01)
    res = runner.invoke(main, ["brush", "-o", str(tmp_path / "p.ttf"), "--glyphs", "o,T",
                               "--jobs", "1"])
    assert res.exit_code == 0, res.output
    status = [s for s in res.stderr.splitlines() if s.startswith("morph brush: ")]
    assert status and "/2 glyphs" in status[0] and status[-1].startswith("morph brush: 2/2")


def test_progress_piped_stroke_counts_rise_to_the_total(runner, tmp_path, monkeypatch):
    """A piped stroke of a small font with two workers: the status lines' counts
    never go back, reach the total, and move inside the chunks (the workers report
    their work as they go, not only when a chunk is done)."""
    import re

    from morph.cli import options
    from morph.fonts import jobs
    from morph.fonts.stroke import CONTOURS_PER_GLYPH
    from tests import RELIEF_SUBSET

    monkeypatch.setattr(options, "STATUS_SECONDS", 0.01)
    # two chunks, two workers: a split from two contours' weight on
    monkeypatch.setattr(jobs, "MIN_SPLIT", 1 / CONTOURS_PER_GLYPH)
    chunks = []     # the stroke's chunks (the glyphs with contours to stroke)
    split = jobs.glyph_chunks
    monkeypatch.setattr(jobs, "glyph_chunks",
                        lambda *a, **k: _spied(chunks, split(*a, **k), k))
    res = runner.invoke(main, ["stroke", str(RELIEF_SUBSET), "-o", str(tmp_path / "s.ufo"),
                               "--jobs", "2"])
    assert res.exit_code == 0, res.output
    lines = re.findall(r"^morph stroke: (\d+)/(\d+) glyphs", res.stderr, re.M)
    # the total: the glyphs with contours to stroke, once planned (the whole font before)
    counts, total = [int(c) for c, _ in lines], int(lines[-1][1])
    assert counts == sorted(counts) and counts[-1] == total == sum(map(len, chunks))
    assert len(chunks) == 2     # the counts a chunk's arrival alone can give, either first:
    assert set(counts) - ({0, total} | {len(c) for c in chunks})


def test_progress_frames_count_the_free_first_frame_with_the_next(runner, tmp_path, monkeypatch):
    """The first frame is operand A itself and costs nothing: a piped run's status
    lines never show it alone (a time left measured on it promised ~30x the run),
    and the counts rise to the total."""
    import re

    from morph.cli import options

    monkeypatch.setattr(options, "STATUS_SECONDS", 0.005)
    res = runner.invoke(main, ["glyph", "T", "M", "--frames", "4", "-o", str(tmp_path / "f")])
    assert res.exit_code == 0, res.output
    counts = [int(c) for c in re.findall(r"^morph glyph: (\d+)/4 frames", res.stderr, re.M)]
    assert counts and counts == sorted(counts) and counts[-1] == 4
    assert 1 not in counts


def test_progress_eta_from_work_done():
    """The time left is the time per item done so far times the items left, shown
    once something is done; items reported in bursts (a batch of glyphs finishing
    together) count each."""
    import io
    import time

    from morph.cli.options import Progress

    out = io.StringIO()
    with Progress(100, "glyphs", "morph brush", stream=out, tty=False, interval=60) as bar:
        t0 = time.monotonic()
        assert "left" not in bar.status()
        bar.update(25)
        elapsed = time.monotonic() - t0
        text = bar.status()
    assert "25/100 glyphs (25 %)" in text
    left = float(text.split("about ")[1].split(" s left")[0])
    assert left <= 3 * elapsed + 0.5
    assert out.getvalue() == ""  # nothing shown in under a minute off a terminal


def test_progress_on_a_terminal_redraws_at_most_every_interval():
    """On a terminal a glyph done is not a redraw: 30,000 glyphs done within the
    interval draw the line once as they start and once at the end (a redraw per
    glyph would write 30,001 lines)."""
    import io

    from morph.cli.options import Progress

    out = io.StringIO()
    with Progress(30000, "glyphs", "morph stroke", stream=out, tty=True, interval=60) as bar:
        for _ in range(30000):
            bar.update(1)
            bar.partial(0.5)
            bar.partial(-0.5)
    lines = out.getvalue().split("\r\033[K")[1:]
    assert len(lines) == 2, len(lines)
    assert lines[-1].startswith("morph stroke: 30000/30000 glyphs (100 %)")
    assert lines[-1].endswith("\n")


# =========================================================================== 6: --location

def test_location_draws_the_glyph_without_instancing_the_font(tmp_path, monkeypatch):
    """A glyph at a location is drawn from the variable font directly (the glyph set
    at that location), not by instancing the whole font: the same outline and
    advance as the instance, and the instancer is not called."""
    from morph import parse
    from morph.parse import glyphs, instantiate_font, load_font
    from tests.fontfixtures import build_variable_font

    path = build_variable_font(tmp_path)
    instance = instantiate_font(load_font(str(path)), {"wght": 550})
    want = parse.read_glyph(instance, "o")

    def refuse(*args, **kwargs):
        raise AssertionError("the whole font was instanced for one glyph")

    monkeypatch.setattr(glyphs, "instantiate_font", refuse)
    got = parse.glyph_region("o", str(path), "wght=550")
    assert got.advance_width == want.advance_width
    assert len(got.region) == len(want.region)
    for a, b in zip(got.region, want.region):
        assert np.allclose(np.concatenate(a), np.concatenate(b))
    with pytest.raises(parse.glyphs.ParseError, match="axes"):
        parse.glyph_region("o", str(path), "wght=900")


# =========================================================================== 8: tolerance units

def test_tolerance_units_helper_and_where_both_are_documented(runner):
    """The library's tol is in the shapes' own units, --tol in em for glyphs: one
    helper converts (em_to_units: em x units per em; SVG user units as they are),
    named where both are documented."""
    import morph.minkowski
    from morph.parse import em_to_units, glyph_region, svg_shape

    g = glyph_region("o")
    assert em_to_units(1e-4, 1000) == g.em_to_units(1e-4) == pytest.approx(0.1)
    assert svg_shape("M0 0H10V10H0Z").em_to_units(1e-4) == 1e-4
    assert em_to_units(1e-4, None) == 1e-4
    assert "em_to_units" in morph.minkowski.minkowski_sum.__doc__
    text = " ".join(runner.invoke(main, ["sum", "--help"]).output.split())
    assert "units per em" in text and "library" in text


@pytest.mark.parametrize("command", [
    ["stroke", "RELIEF", "-o", "s.otf"],
    ["stroke", "RELIEF", "-o", "v.ttf", "--vary-nib", "ellipse:120,30,30"],
    ["brush", "-o", "b.ttf"],
    ["brush", "-o", "w.ttf", "--vary-nib", "ellipse:120,30,30"]])
def test_a_tolerance_as_coarse_as_the_nib_is_refused_before_any_glyph(runner, tmp_path,
                                                                     command):
    """--tol no finer than the nib (its control box's larger side, ~88 units for the
    stroke's default nib at 1000 units per em, ~84 for the brush's) is one error line
    naming --tol, exit 2, nothing written, before any glyph is computed (every stroked
    glyph would come out empty, a polygon fallback each); a --tol just below the nib
    passes this check."""
    from tests import RELIEF_SUBSET

    args = [str(RELIEF_SUBSET) if a == "RELIEF" else
            str(tmp_path / a) if a.endswith(("otf", "ttf")) else a for a in command]
    res = runner.invoke(main, args + ["--glyphs", "H", "--tol", "0.09", "--jobs", "1"])
    line = one_error_line(res)
    assert res.exit_code == 2 and "--tol 0.09 em" in line and "nib" in line
    assert "use --tol 0.0088 em or less" in line or "use --tol 0.0084 em or less" in line
    assert not list(tmp_path.iterdir())
    res = runner.invoke(main, args + ["--glyphs", "H", "--tol", "0.08", "--jobs", "1"])
    assert res.exit_code != 2, res.stderr


def test_glyphs_that_fell_back_for_one_reason_share_it(capsys):
    """The fallback line names each reason once, after the glyphs it concerns."""
    from morph.cli.fonts import _fallback_status

    why = ValueError("tolerance too coarse")
    assert _fallback_status([("C", why), ("D", ValueError(str(why))), ("E", "other")],
                            " to a polygon stroke") == 1
    err = capsys.readouterr().err.strip()
    assert err == ("morph: error: font written, but 3 glyph(s) fell back to a polygon "
                   "stroke: C, D (tolerance too coarse); E (other)")
    assert _fallback_status([], "") == 0


# =========================================================================== 13: sample text

def test_sample_text_the_font_covers(runner, tmp_path):
    """A font that does not draw the sample text (here a stroked subset: only H and o
    have outlines) gets a sample of its own characters in cmap order, and says so;
    the specimen uses the same text."""
    from tests import RELIEF_SUBSET

    out = tmp_path / "S.otf"
    res = runner.invoke(main, ["stroke", str(RELIEF_SUBSET), "-o", str(out), "--glyphs", "H,o",
                               "--tol", "2e-3"])
    assert res.exit_code == 0, res.output
    note = [s for s in res.stderr.splitlines() if "sample" in s]
    assert len(note) == 1 and "Hamburgefonstiv" in note[0] and "'Ho'" in note[0]
    assert '<p id="sample">Ho</p>' in (tmp_path / "S.otf.html").read_text()


def test_sample_text_kept_when_covered():
    from morph.fonts.specimen import sample_text
    from morph.parse import load_font

    font = load_font()
    assert sample_text(font, "Hamburgefonstiv") == ("Hamburgefonstiv", False)
    text, changed = sample_text(font, "Hamburg 一二")
    assert changed and "一" not in text and text.startswith("!")  # its own, cmap order


def test_sample_text_of_private_use_glyphs_after_the_others():
    """A font of private use characters only (an icon font, Plane 15 glyphs) is
    sampled with them, not with nothing; where there are others they come first."""
    from morph.fonts.specimen import sample_text

    pua = {0xF0000 + k: "u%05X" % (0xF0000 + k) for k in range(40)}
    text, changed = sample_text(None, "Hamburg", ink=(pua, lambda name: True))
    assert changed and text == "".join(chr(0xF0000 + k) for k in range(15))
    mixed = {**pua, **{ord(c): c for c in "abc"}}
    text, _ = sample_text(None, "Hamburg", ink=(mixed, lambda name: True))
    assert text == "abc" + "".join(chr(0xF0000 + k) for k in range(12))


def test_debug_file_goes_where_morph_debug_says(runner, tmp_path, monkeypatch):
    """MORPH_DEBUG naming a folder puts the debug file there, not in the working
    folder (MORPH_DEBUG=1: the working folder, as documented)."""
    import morph.minkowski

    def boom(*args, **kwargs):
        raise RuntimeError("kaboom")

    monkeypatch.setattr(morph.minkowski, "minkowski_sum", boom)
    work, dumps = tmp_path / "work", tmp_path / "dumps"
    work.mkdir()
    dumps.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setenv("MORPH_DEBUG", str(dumps))
    res = runner.invoke(main, ["sum", "o", "x", "-o", str(tmp_path / "s.png")])
    assert res.exit_code == 1 and str(dumps) in res.stderr
    assert [p.name for p in dumps.iterdir()] == ["morph-debug-sum.json"]
    assert not list(work.iterdir())


# =========================================================================== 14: test summary

def test_the_readme_test_command_prints_its_summary():
    """The README's test command, with pyproject's addopts, ends with the "N passed"
    line (two -q together hide it): run here on one small test file, without -n."""
    import re
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    cmd = re.search(r"python -m pytest([^\n`]*)", (root / "README.md").read_text())
    flags = cmd.group(1).split()
    for k in range(len(flags) - 1, -1, -1):  # the workers (-n N): one file needs none
        if flags[k] == "-n":
            del flags[k:k + 2]
    res = subprocess.run([sys.executable, "-m", "pytest", *flags, "-p", "no:randomly",
                          "-p", "no:cacheprovider", "tests/test_init.py"], cwd=root,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    assert re.search(r"^\d+ passed", res.stdout, re.M), res.stdout


def _spied(seen, chunks, kwargs):
    """``chunks`` (of :func:`morph.fonts.jobs.glyph_chunks`), added to ``seen`` when
    weighted: the stroke's chunks of the glyphs with contours to stroke."""
    if kwargs.get("weights") is not None:
        seen.extend(chunks)
    return chunks
