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
                     "svgpathtools", "ufoLib2", "ufo2ft", "fontTools.varLib", "numpy.ma",
                     "morph.cli.fonts", "morph.cli.apps")  # other commands' modules

_PROBE = r"""
import json, os, sys
argv = json.loads(sys.argv[1])
if argv:
    from morph.cli import main
    code = main(argv, standalone_mode=False)
else:
    import morph.cli
    code = 0
# a module deferred by morph.fonts.deferred and never used has not run: not loaded
print(json.dumps({"code": code, "modules": sorted(m for m, v in sys.modules.items()
                                                  if type(v).__name__ != "_Deferred"),
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


def test_every_command_is_named_with_its_module():
    """morph.cli.group.COMMAND_MODULES names every command with the module that
    defines it (a command missing there would be loaded only with all of them)."""
    from morph.cli import COMMAND_MODULES, load_commands, main

    load_commands()
    assert {name: cmd.callback.__module__ for name, cmd in main.commands.items()
            if name != "freeze-probe"} == \
        {name: "morph.cli." + module for name, module in COMMAND_MODULES.items()}


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
#: (morph.fonts.specimen.save_png writes the sample), its EXIF and TIFF tags and its
#: file formats' base (deferred: morph.fonts.deferred.pillow), the html package (the
#: specimen escapes its text itself), the SVG reader and its XML parser (--nib-svg
#: only), numpy.ma, strptime's locale tables (morph.fonts.fontinfo reads the head
#: table's dates itself); the shape commands' modules (morph.cli.group.COMMAND_MODULES)
NOT_FOR_FONT_COMMANDS = ("numpy.polynomial", "PIL.PngImagePlugin", "PIL.ExifTags",
                         "PIL.TiffTags", "html", "xml.etree", "morph.parse.svg", "numpy.ma",
                         "_strptime", "PIL.ImageFile",
                         "morph.cli.shapes", "morph.cli.apps")

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


def test_brush_of_a_font_without_anchors_loads_no_layout_classes(tmp_path):
    """``morph brush`` of the bundled TrueType font (GPOS of kerning only, GDEF
    without ligature carets) leaves GPOS and GDEF as stored and reads and writes its
    name table from its records: fontTools' OpenType layout classes and HarfBuzz's
    bindings are not loaded."""
    code, mods, _ = _modules_after(["brush", "--glyphs", "A", "-o", "b.ttf", "--jobs", "1"],
                                   tmp_path)
    assert code == 0 and (tmp_path / "b.ttf").stat().st_size > 0
    for name in ("fontTools.ttLib.tables.otTables", "fontTools.ttLib.tables._n_a_m_e",
                 "uharfbuzz"):
        assert not _loaded(mods, name), name


#: what ``morph stroke`` never needs for a static font of a skeleton without kerning,
#: anchors or components (morph.fonts.tables_static): ufo2ft, ufoLib2 and the UFO
#: library, the variable-font stack, fontTools' CFF library and its OpenType layout
#: classes, feaLib (no feature file), the charstring decomposer (no composite); its
#: .glif files in ufoLib's plain markup are read without an XML parser
#: (morph.parse.glif_xml.plain_tree): neither xml.etree nor lxml nor fontTools.misc.etree
#: (the plists are read by plistlib's expat parser)
NOT_FOR_PLAIN_STROKE = NOT_FOR_STATIC_BRUSH + (
    "fontTools.cffLib", "fontTools.ttLib.tables.otTables", "fontTools.feaLib",
    "morph.fonts.brush", "morph.parse.charstrings", "lxml", "fontTools.misc.etree")


def _plain_skeleton(folder):
    from tests.fontfixtures import hershey_like

    hershey_like().save(folder / "h.ufo")
    return "h.ufo"


@pytest.mark.parametrize("out", ["s.otf", "s.ttf"])
def test_static_stroke_of_a_plain_skeleton_loads_no_ufo_compiler(tmp_path, out):
    """``morph stroke`` of a skeleton that needs no feature writer reads the UFO and
    writes the font's tables itself; the subroutinizer (cffsubr's ``tx``) runs for
    a CFF font only, as an executable found without importing the cffsubr package
    (morph.fonts.subrs.tx_runner); the sample loads Pillow."""
    from fontTools.ttLib import TTFont

    argv = ["stroke", _plain_skeleton(tmp_path), "-o", out, "--jobs", "1"]
    code, mods, _ = _modules_after(argv, tmp_path)
    assert code == 0 and (tmp_path / out).stat().st_size > 0
    for name in NOT_FOR_PLAIN_STROKE:
        assert not _loaded(mods, name), name
    assert _loaded(mods, "PIL") and _loaded(mods, "fontTools.ttLib")
    if out.endswith(".otf"):   # tx ran: the charstrings call its subroutines
        cff = TTFont(str(tmp_path / out))["CFF "].cff
        private = cff.topDictIndex[0].Private
        assert len(cff.GlobalSubrs) + len(getattr(private, "Subrs", ())) > 0


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


#: what a CFF 1 font without layout tables never needs: the HarfBuzz bindings that
#: fontTools.cffLib loads through otBase (morph.fonts.deferred defers them)
NOT_FOR_PLAIN_CFF_BRUSH = ("uharfbuzz._harfbuzz",)


def test_cff_brush_defers_harfbuzz(tmp_path):
    """``morph brush`` of the bundled CFF font (no GSUB/GPOS) reads its CFF table
    with fontTools' layout modules deferred: HarfBuzz's bindings are not loaded."""
    font = str(ROOT / "morph/fonts/data/NotoSans-Regular.otf")
    code, mods, _ = _modules_after(["brush", font, "--glyphs", "A", "-o", "b.otf", "--jobs", "1"],
                                   tmp_path)
    assert code == 0 and (tmp_path / "b.otf").stat().st_size > 0
    for name in NOT_FOR_PLAIN_CFF_BRUSH:
        assert not _loaded(mods, name), name
    assert _loaded(mods, "fontTools.cffLib")


_MARKED_CFF = r"""
import sys
from fontTools.feaLib.builder import addOpenTypeFeaturesFromString
from fontTools.ttLib import TTFont

font = TTFont(sys.argv[1])
addOpenTypeFeaturesFromString(font, '''
markClass acute <anchor 280 500> @TOP;
feature mark { pos base [A a] <anchor 300 720> mark @TOP; } mark;
''')
font.save(sys.argv[2])
"""

_BRUSH_PROBE = r"""
import sys
if sys.argv[3] == "plain":   # the layout modules imported before the CFF table is read
    import fontTools.ttLib.tables.otTables, uharfbuzz  # noqa: F401 - imported for their effect
from morph.fonts.brush import brush_font, ellipse_nib
brush_font(sys.argv[1], sys.argv[2], ellipse_nib(80, 30, 30), ["A", "a"], tol=0.5)
print(sorted(m for m in sys.modules if m.startswith("uharfbuzz")))
"""


def test_deferred_layout_modules_load_where_used(tmp_path):
    """A CFF font with GPOS: the deferred modules load where the anchors are moved and
    the table compiled (HarfBuzz's packer), and the font is byte for byte the one of
    a process that imported them first (head's dates aside)."""
    from fontTools.ttLib import TTFont

    env = dict(os.environ, PYTHONPATH=str(ROOT))
    src = tmp_path / "marked.otf"
    subprocess.run([sys.executable, "-c", _MARKED_CFF, str(ROOT / "morph/fonts/data/"
                                                               "NotoSans-Regular.otf"),
                    str(src)], check=True, env=env, timeout=120)
    outs = []
    for mode in ("deferred", "plain"):
        out = tmp_path / ("%s.otf" % mode)
        res = subprocess.run([sys.executable, "-c", _BRUSH_PROBE, str(src), str(out), mode],
                             env=env, capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr
        assert "uharfbuzz._harfbuzz" in res.stdout   # GPOS compiled with HarfBuzz's packer
        outs.append(TTFont(str(out)))
    a, b = outs
    assert sorted(a.reader.keys()) == sorted(b.reader.keys()) and "GPOS" in a
    for tag in a.reader.keys():
        if tag != "head":
            assert a.reader[tag] == b.reader[tag], tag
    assert a["GPOS"].table.LookupList.Lookup[0].SubTable  # the anchors are there


def test_deferred_module_runs_at_first_use(tmp_path, monkeypatch):
    """morph.fonts.deferred: importing a deferred module by name binds it without
    running it; its first attribute runs it; one that raises as it runs raises there
    and is left out of sys.modules, as a failed import is; a name not found is
    left to a plain import."""
    from morph.fonts.deferred import deferred_imports

    (tmp_path / "morph_probe_ok.py").write_text("import sys\nsys.morph_probe_ran = True\nX = 3\n")
    (tmp_path / "morph_probe_broken.py").write_text("raise ImportError('broken on purpose')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    names = ["morph_probe_ok", "morph_probe_broken", "morph_probe_absent"]
    try:
        assert deferred_imports(names) == names[:2]
        import morph_probe_ok  # noqa: E402 - imported here, after its deferral
        assert not hasattr(sys, "morph_probe_ran")
        assert morph_probe_ok.X == 3 and sys.morph_probe_ran
        import morph_probe_broken  # noqa: E402 - as above
        with pytest.raises(ImportError, match="on purpose"):
            morph_probe_broken.X
        assert "morph_probe_broken" not in sys.modules
    finally:
        for name in names:
            sys.modules.pop(name, None)
        if hasattr(sys, "morph_probe_ran"):
            del sys.morph_probe_ran


_AGL_PROBE = r"""
import sys
from fontTools.ttLib import TTFont
from morph.fonts.deferred import glyph_list
from morph.parse import default_font_path
glyph_list()
order = TTFont(default_font_path()).getGlyphOrder()    # post format 3: names from cmap
agl = sys.modules["fontTools.agl"]
ran = type(agl).__name__ != "_Deferred"
names = dict(agl.UV2AGL)
print(repr((order, ran, names, agl.AGL2UV["A"], type(agl).__name__)))
"""


def test_glyph_names_without_adobes_full_list():
    """morph.fonts.deferred.glyph_list: the bundled font's glyph names made from its
    character map are those fontTools makes with its own Adobe Glyph List, without
    running fontTools.agl; its list for new fonts is morph's copy; another name of
    the module runs it."""
    import ast

    from fontTools import agl
    from fontTools.ttLib import TTFont

    from morph.parse import default_font_path

    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", _AGL_PROBE], env=env, capture_output=True,
                         text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    order, ran, names, a, kind = ast.literal_eval(res.stdout.strip().splitlines()[-1])
    assert order == TTFont(default_font_path()).getGlyphOrder() and "A" in order
    assert not ran and names == agl.UV2AGL
    assert a == 0x41 and kind == "module"


_EXIF_PROBE = r"""
import sys
from morph.fonts.deferred import pillow
Image, = pillow("Image")
ran = type(sys.modules["PIL.ExifTags"]).__name__ != "_Deferred"
exif = Image.new("RGB", (1, 1)).getexif()
exif[0x0131] = "morph"                      # Software
data = exif.tobytes()
back = Image.Exif()
back.load(data)
print(ran, back[0x0131], back.get_ifd(0x8825), type(sys.modules["PIL.ExifTags"]).__name__)
"""


def test_pillow_runs_its_exif_tags_where_used():
    """morph.fonts.deferred.pillow: Pillow's EXIF tags stay unrun as Pillow loads and
    run when an image's EXIF data needs them, which then reads as with a plain
    import."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", _EXIF_PROBE], env=env, capture_output=True,
                         text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["False", "morph", "{}", "module"]


_IMAGEFILE_PROBE = r"""
import hashlib, io, sys
if sys.argv[1] == "deferred":
    from morph.fonts.deferred import pillow
    Image, ImageDraw = pillow("Image", "ImageDraw")
else:
    from PIL import Image, ImageDraw
img = Image.new("RGB", (700, 90), "white")
ImageDraw.Draw(img).ellipse((3, 4, 650, 85), fill=(10, 20, 30), outline=(200, 0, 0))
data = img.tobytes()
ran = type(sys.modules["PIL.ImageFile"]).__name__ != "_Deferred"
buf = io.BytesIO()
img.save(buf, "PNG")                      # Pillow's PNG plugin: runs ImageFile
back = Image.open(io.BytesIO(buf.getvalue())).tobytes()
print(ran, hashlib.sha1(data).hexdigest(), back == data,
      type(sys.modules["PIL.ImageFile"]).__name__)
"""


def test_pillow_image_file_runs_only_where_used():
    """morph.fonts.deferred.pillow: ``Image.tobytes`` reads the deferred
    ``PIL.ImageFile``'s chunk size without running it and gives the bytes it gives
    with a plain import of Pillow; saving and opening a PNG with Pillow runs it."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = []
    for how in ("deferred", "plain"):
        res = subprocess.run([sys.executable, "-c", _IMAGEFILE_PROBE, how], env=env,
                             capture_output=True, text=True, timeout=120)
        assert res.returncode == 0, res.stderr
        out.append(res.stdout.split())
    assert out[0][0] == "False" and out[1][0] == "True"
    assert out[0][1] == out[1][1] and out[0][2:] == out[1][2:] == ["True", "module"]


def test_a_command_runs_with_what_was_imported_frozen():
    """The group freezes the collector's objects for a command's run (what was
    imported before it is left out of the full passes) and unfreezes them after."""
    import gc

    import click

    from morph.cli import main

    seen = []

    @click.command("freeze-probe")
    def probe():
        seen.append(gc.get_freeze_count())

    before = gc.get_freeze_count()
    main.add_command(probe)
    try:
        assert main(["freeze-probe"], standalone_mode=False) == 0
    finally:
        main.commands.pop("freeze-probe")
    assert seen[0] > before and gc.get_freeze_count() == before
