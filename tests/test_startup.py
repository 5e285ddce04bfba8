"""Start-up cost of the command line: each command loads only the modules it needs.

A fresh interpreter runs one command in-process and reports ``sys.modules``; a
module a command does not use (Pillow for SVG output, the SVG reader and its XML
parser for glyphs, the BLAS thread pool) must not have been loaded, since every
process pays for it again (``morph sum`` as a process against the
polygon script).
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: top-level packages / modules no glyph -> SVG command needs
NOT_FOR_GLYPH_SVG = ("PIL", "svgelements", "xml.etree", "html", "kurbopy",
                     "svgpathtools", "ufoLib2", "ufo2ft", "fontTools.varLib", "numpy.ma")

_PROBE = r"""
import json, os, sys
argv = json.loads(sys.argv[1])
if argv:
    from morph.cli import main
    code = main(argv, standalone_mode=False)
else:
    import morph.cli
    code = 0
print(json.dumps({"code": code, "modules": sorted(sys.modules),
                  "blas": os.environ.get("OPENBLAS_NUM_THREADS")}))
"""


def _modules_after(argv, cwd, env_extra=None):
    env = dict(os.environ)
    env.pop("OPENBLAS_NUM_THREADS", None)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in [env.get("PYTHONPATH")] if p])
    env.update(env_extra or {})
    res = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(argv)], cwd=cwd, env=env,
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout.strip().splitlines()[-1])
    return out["code"], set(out["modules"]), out["blas"]


def _loaded(modules, name):
    return name in modules or any(m.startswith(name + ".") for m in modules)


def test_import_cli_loads_no_reader_or_writer(tmp_path):
    code, mods, blas = _modules_after([], tmp_path)
    for name in NOT_FOR_GLYPH_SVG + ("fontTools", "morph.parse", "morph.render"):
        assert not _loaded(mods, name), name
    assert blas == "1"  # set before numpy loaded


@pytest.mark.parametrize("argv", [["sum", "T", "M", "--tol", "1e-3", "-o", "tm.svg"],
                                  ["outline", "g", "-o", "g.svg"]])
def test_glyph_to_svg_loads_neither_pillow_nor_the_svg_reader(tmp_path, argv):
    code, mods, _ = _modules_after(argv, tmp_path)
    assert code == 0 and (tmp_path / argv[-1]).stat().st_size > 0
    for name in NOT_FOR_GLYPH_SVG:
        assert not _loaded(mods, name), name
    assert _loaded(mods, "fontTools.ttLib")
    assert not _loaded(mods, "morph.paper")   # the paper's methods: only for --method


def test_png_and_svg_input_load_what_they_need(tmp_path):
    """The other side of the laziness: the modules do load when a command needs them."""
    (tmp_path / "box.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg">'
                                      '<rect width="10" height="5"/></svg>')
    code, mods, _ = _modules_after(["outline", "box.svg", "-o", "box.png"], tmp_path)
    assert code == 0 and (tmp_path / "box.png").stat().st_size > 0
    assert _loaded(mods, "PIL") and _loaded(mods, "morph.parse.svg")
    assert not _loaded(mods, "fontTools.ttLib")  # no font opened for an SVG shape


def test_a_blas_thread_count_the_user_set_is_kept(tmp_path):
    _, _, blas = _modules_after([], tmp_path, {"OPENBLAS_NUM_THREADS": "2"})
    assert blas == "2"


# Workers forked for --jobs share what the calling process imported before the fork;
# a module each worker imports itself costs its import once per worker.  The probe
# records, in every worker, the modules its jobs imported.
_WORKER_PROBE = r"""
import json, os, sys
import morph.fonts.jobs as jobs

# two chunks of the two glyphs, two workers: a split from a contour's weight on
jobs.MIN_SPLIT = 1 / 12   # (morph.fonts.stroke.CONTOURS_PER_GLYPH)

call = jobs._queued_call

def recorded(func, k, arg):
    before = set(sys.modules)
    try:
        return call(func, k, arg)
    finally:
        with open(os.path.join(sys.argv[2], "worker-%d-%d.json" % (os.getpid(), k)), "w") as f:
            json.dump(sorted(set(sys.modules) - before), f)

jobs._queued_call = recorded
from morph.cli import main
print(main(json.loads(sys.argv[1]), standalone_mode=False))
"""


@pytest.mark.skipif(sys.platform != "linux", reason="workers are forked on Linux only")
@pytest.mark.parametrize("argv", [
    ["brush", "{font}.ttf", "--glyphs", "a-b", "-o", "b.ttf"],
    ["stroke", str(ROOT / "tests/data/relief/Relief-SingleLine-subset.ufo"), "--glyphs",
     "a-b", "-o", "s.otf"],
    ["stroke", str(ROOT / "tests/data/relief/Relief-SingleLine-subset.ufo"), "--glyphs",
     "a-b", "-o", "s.ttf"]])
def test_font_workers_import_nothing_themselves(tmp_path, argv):
    """brush and stroke import their workers' modules before forking them
    (morph.fonts.jobs.preload_modules): a worker's jobs import no module."""
    font = str(ROOT / "morph/fonts/data/NotoSans-Regular")
    argv = [a.format(font=font) for a in argv] + ["--jobs", "2"]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", _WORKER_PROBE, json.dumps(argv), str(tmp_path)],
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    reports = sorted(tmp_path.glob("worker-*.json"))
    assert len(reports) == 2  # two chunks, in the workers
    for report in reports:
        assert json.loads(report.read_text()) == [], report.name


#: what the font commands never need, each a few ms of every process: numpy's
#: polynomial classes (morph.quadrature tabulates the rules), Pillow's PNG plugin
#: (morph.fonts.specimen.save_png writes the sample), the html package (the specimen
#: escapes its text itself), the SVG reader and its XML parser (--nib-svg only),
#: numpy.ma
NOT_FOR_FONT_COMMANDS = ("numpy.polynomial", "PIL.PngImagePlugin", "html", "xml.etree",
                         "morph.parse.svg", "numpy.ma")

#: what a static brush never needs: ufo2ft and its variable-font stack, ufoLib2
NOT_FOR_STATIC_BRUSH = ("ufo2ft", "ufoLib2", "fontTools.varLib", "fontTools.designspaceLib",
                        "fontTools.ufoLib", "cffsubr") + NOT_FOR_FONT_COMMANDS


@pytest.mark.parametrize("out", ["b.ttf", "b.otf"])
def test_static_brush_loads_no_ufo_compiler(tmp_path, out):
    """``morph brush`` writes the source font's tables itself: ufo2ft (whose import
    brings fontTools.varLib and its variable compilers), ufoLib2 and the
    subroutinizer stay unloaded for a static font, and so does what no font command
    needs (NOT_FOR_FONT_COMMANDS); the sample and specimen load Pillow."""
    code, mods, _ = _modules_after(["brush", "--glyphs", "A", "-o", out, "--jobs", "1"],
                                   tmp_path)
    assert code == 0 and (tmp_path / out).stat().st_size > 0
    for name in NOT_FOR_STATIC_BRUSH:
        assert not _loaded(mods, name), name
    assert _loaded(mods, "PIL") and _loaded(mods, "fontTools.ttLib")


#: what ``morph stroke`` never needs for a static font of a skeleton without kerning,
#: anchors or components (morph.fonts.tables_static): ufo2ft, ufoLib2 and the UFO
#: library, the variable-font stack, fontTools' CFF library and its OpenType layout
#: classes, feaLib (no feature file)
NOT_FOR_PLAIN_STROKE = tuple(m for m in NOT_FOR_STATIC_BRUSH if m != "cffsubr") + (
    "fontTools.cffLib", "fontTools.ttLib.tables.otTables", "fontTools.feaLib",
    "morph.fonts.brush")


def _plain_skeleton(folder):
    from tests.fontfixtures import hershey_like

    hershey_like().save(folder / "h.ufo")
    return "h.ufo"


@pytest.mark.parametrize("out", ["s.otf", "s.ttf"])
def test_static_stroke_of_a_plain_skeleton_loads_no_ufo_compiler(tmp_path, out):
    """``morph stroke`` of a skeleton that needs no feature writer reads the UFO and
    writes the font's tables itself; the subroutinizer (cffsubr's ``tx``) runs for
    a CFF font only; the sample loads Pillow."""
    argv = ["stroke", _plain_skeleton(tmp_path), "-o", out, "--jobs", "1"]
    code, mods, _ = _modules_after(argv, tmp_path)
    assert code == 0 and (tmp_path / out).stat().st_size > 0
    for name in NOT_FOR_PLAIN_STROKE:
        assert not _loaded(mods, name), name
    assert _loaded(mods, "cffsubr") == out.endswith(".otf")
    assert _loaded(mods, "PIL") and _loaded(mods, "fontTools.ttLib")


def test_stroke_of_a_skeleton_ufo2ft_must_compile_uses_ufo2ft(tmp_path):
    """The other side: a skeleton whose anchors ufo2ft's mark writer would put in
    the abvm / blwm features (a combining mark of Devanagari's script extensions
    and no languagesystem to cut them) is compiled by ufo2ft."""
    from tests.fontfixtures import hershey_like

    font = hershey_like()
    font["A"].appendAnchor({"name": "top", "x": 378, "y": 700})
    font["gravecomb"].appendAnchor({"name": "_top", "x": -110, "y": 600})
    font.save(tmp_path / "m.ufo")
    argv = ["stroke", "m.ufo", "-o", "s.otf", "--jobs", "1"]
    code, mods, _ = _modules_after(argv, tmp_path)
    assert code == 0 and _loaded(mods, "ufo2ft") and _loaded(mods, "ufoLib2")


@pytest.mark.skipif(sys.platform != "linux", reason="workers are forked on Linux only")
@pytest.mark.parametrize("out", ["s.otf", "s.ttf"])
def test_plain_stroke_workers_import_nothing_themselves(tmp_path, out):
    """The workers of a plain skeleton's stroke read its .glif files without
    ufoLib2, with what the calling process imported before forking them."""
    argv = ["stroke", _plain_skeleton(tmp_path), "-o", out, "--jobs", "2"]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", _WORKER_PROBE, json.dumps(argv), str(tmp_path)],
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    reports = sorted(tmp_path.glob("worker-*.json"))
    assert len(reports) == 2
    for report in reports:
        assert json.loads(report.read_text()) == [], report.name
