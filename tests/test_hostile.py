"""Hostile input through the CLI: one clear error line and exit 2, or a correct result.

Never a traceback, never a wrong picture.  "Correct" is checked against independent
references (shapely / Clipper of the flattened operands, exact areas of polygons).
"""

import pytest

from morph import piece as pc
from morph import moments as mo
from morph.cli import main
from morph.parse import svg_region
from morph.minkowski import minkowski_sum
from tests.oracles import reference as R
from tests.helpers import square_path_data

SVG = '<svg xmlns="http://www.w3.org/2000/svg">%s</svg>'


def _svg(tmp_path, name, d, attrs=""):
    p = tmp_path / name
    p.write_text(SVG % ('<path %s d="%s"/>' % (attrs, d)))
    return str(p)


def error_line(result, code=2):
    """The one error line of a failed command (exit ``code``), no traceback."""
    assert result.exit_code == code, (result.exit_code, result.output, result.exception)
    assert not isinstance(result.exception, Exception) or isinstance(result.exception,
                                                                     SystemExit)
    text = (result.stderr or "") + (result.stdout or "")
    assert "Traceback" not in text
    lines = [l for l in result.stderr.strip().splitlines() if l.strip()]
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("morph: error: ")
    assert "internal error" not in lines[0]
    return lines[0]


def ok(result):
    assert result.exit_code == 0, (result.output, result.exception)
    assert "Traceback" not in result.output
    return result


# ---------------------------------------------------------------------------- fonts

def test_empty_font_path(runner, tmp_path):
    """--font '' must say the font path is empty, not that the current folder is a
    missing file."""
    line = error_line(runner.invoke(main, ["outline", "A", "--font", "",
                                           "-o", str(tmp_path / "a.png")]))
    assert "font" in line
    assert "no such file" not in line, line


def test_nonexistent_font(runner, tmp_path):
    line = error_line(runner.invoke(main, ["outline", "A", "--font",
                                           str(tmp_path / "nope.ttf"),
                                           "-o", str(tmp_path / "a.png")]))
    assert "nope.ttf" in line


def test_font_that_is_not_a_font(runner, tmp_path):
    f = tmp_path / "fake.ttf"
    f.write_text("not a font\n")
    line = error_line(runner.invoke(main, ["outline", "A", "--font", str(f),
                                           "-o", str(tmp_path / "a.png")]))
    assert "fake.ttf" in line


def test_font_that_is_a_folder(runner, tmp_path):
    error_line(runner.invoke(main, ["outline", "A", "--font", str(tmp_path),
                                    "-o", str(tmp_path / "a.png")]))


@pytest.mark.parametrize("ch", ["中", "U+1F600", "nosuchglyphname"])
def test_font_without_the_glyph(runner, tmp_path, ch):
    line = error_line(runner.invoke(main, ["sum", "A", ch, "-o", str(tmp_path / "s.png")]))
    assert "glyph" in line
    assert not (tmp_path / "s.png").exists()


@pytest.mark.parametrize("args", [["outline", " "], ["outline", "space"], ["sum", "A", " "],
                                  ["glyph", " ", "A", "--frames", "3"]])
def test_glyph_without_contours(runner, tmp_path, args):
    line = error_line(runner.invoke(main, args + ["-o", str(tmp_path / "out.png")]))
    assert "empty" in line or "contour" in line


# ---------------------------------------------------------------------------- SVG errors

def test_svg_without_anything(runner, tmp_path):
    p = tmp_path / "none.svg"
    p.write_text(SVG % "")
    line = error_line(runner.invoke(main, ["outline", str(p), "-o", str(tmp_path / "o.png")]))
    assert "none.svg" in line


def test_svg_with_empty_path(runner, tmp_path):
    error_line(runner.invoke(main, ["outline", _svg(tmp_path, "e.svg", ""),
                                    "-o", str(tmp_path / "o.png")]))


def test_svg_without_path_but_a_rect_is_drawn(runner, tmp_path):
    """No <path>, but a <rect>: a correct result (the rect)."""
    p = tmp_path / "rect.svg"
    p.write_text(SVG % '<rect x="0" y="0" width="5" height="4"/>')
    assert abs(mo.region_area(svg_region(str(p))) - 20.0) < 1e-9
    ok(runner.invoke(main, ["outline", str(p), "-o", str(tmp_path / "o.png")]))


def test_svg_open_path(runner, tmp_path):
    """A filled open path is filled as if closed (SVG implicit close): a triangle."""
    p = _svg(tmp_path, "open.svg", "M0 0 L10 0 L10 10")
    ok(runner.invoke(main, ["outline", p, "-o", str(tmp_path / "o.png")]))
    assert abs(mo.region_area(svg_region(p)) - 50.0) < 1e-9


def test_svg_stroke_only_path(runner, tmp_path):
    """A stroke-only path is a centre line: a region command says so, naming it."""
    p = _svg(tmp_path, "line.svg", "M0 0 L10 0 L10 10", 'id="wire" fill="none" stroke="red"')
    line = error_line(runner.invoke(main, ["outline", p, "-o", str(tmp_path / "o.png")]))
    assert "stroke-only" in line and "wire" in line and "morph stroke" in line


def test_svg_strokes_beside_fills_are_named_in_one_warning(runner, tmp_path):
    """A filled disk inside a stroked ring (ionicons' radio-button-on-outline): the
    region is the fill, and one warning line names the stroked element (the ring
    was left out without a word); the same library call warns with MorphWarning."""
    from morph.errors import MorphWarning

    p = tmp_path / "radio.svg"
    p.write_text(SVG % ('<circle id="dot" cx="0" cy="0" r="4"/>'
                        '<circle id="ring" cx="0" cy="0" r="9" fill="none" stroke="#000"/>'
                        '<path id="wire" d="M0 0 L9 9" fill="none" stroke="#000"/>'))
    res = ok(runner.invoke(main, ["outline", str(p), "-o", str(tmp_path / "o.svg")]))
    lines = [l for l in res.stderr.splitlines() if l.strip()]
    assert len(lines) == 1 and lines[0].startswith("morph: warning: "), res.stderr
    assert "ring" in lines[0] and "1 more" in lines[0] and "morph stroke" in lines[0]
    with pytest.warns(MorphWarning, match="ring"):
        region = svg_region(str(p))
    assert abs(mo.region_area(region) - 16 * 3.141592653589793) < 1e-6


def test_svg_strokes_and_fills_of_no_area(runner, tmp_path):
    """A stroked rect and a filled path of no area (ionicons' laptop-outline): the
    error says that what the file draws is stroke paint, naming an element."""
    p = tmp_path / "laptop.svg"
    p.write_text(SVG % ('<rect id="screen" x="0" y="0" width="9" height="6" fill="none" '
                        'stroke="#000"/><path d="M-1 8h11"/>'))
    line = error_line(runner.invoke(main, ["outline", str(p), "-o", str(tmp_path / "o.png")]))
    assert "fills nothing" in line and "stroke paint" in line and "screen" in line


@pytest.mark.parametrize("d", ["M0 0 L10 0 L NaN 10 Z", "M0 0 L10 0 L nan 10 Z",
                               "M0 0 L10 0 L10 1e999 Z", "M0 0 L10 0 L10 inf Z",
                               "M0 0 C 1 1 NaN 2 10 10 Z"])
def test_svg_nan_and_inf(runner, tmp_path, d):
    error_line(runner.invoke(main, ["outline", _svg(tmp_path, "nan.svg", d),
                                    "-o", str(tmp_path / "o.png")]))
    assert not (tmp_path / "o.png").exists()


@pytest.mark.parametrize("name", ["gone.svg", "gone.svgz", "GONE.SVGZ"])
def test_missing_svg_file(runner, tmp_path, name):
    line = error_line(runner.invoke(main, ["outline", str(tmp_path / name),
                                           "-o", str(tmp_path / "o.png")]))
    assert name in line and "no such file" in line, line


def test_svg_not_xml(runner, tmp_path):
    p = tmp_path / "bad.svg"
    p.write_text("<svg><path d='M0 0 L1 0 L1 1 Z'>")
    error_line(runner.invoke(main, ["outline", str(p), "-o", str(tmp_path / "o.png")]))


# ---------------------------------------------------------------------------- SVG results

def _sum_area_via_cli(runner, tmp_path, a, b, tol):
    out = tmp_path / "s.png"
    ok(runner.invoke(main, ["sum", a, b, "--tol", repr(tol), "-o", str(out)]))
    assert out.exists()
    loops = minkowski_sum(svg_region(a), svg_region(b), tol)
    return mo.region_area(loops), loops


def test_huge_coordinates(runner, tmp_path):
    """A 1e9 square ⊕ a 10-square: (1e9 + 10)^2."""
    a = _svg(tmp_path, "huge.svg", square_path_data(0, 0, 1e9))
    b = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 10))
    area, loops = _sum_area_via_cli(runner, tmp_path, a, b, 1.0)
    assert len(loops) == 1
    assert abs(area - (1e9 + 10) ** 2) <= 1e-9 * (1e9 + 10) ** 2


def test_tiny_coordinates(runner, tmp_path):
    """A 1e-9 square is a square (user units are arbitrary): 1e-9 ⊕ 1e-9 squares =
    a 2e-9 square; outline and sum work."""
    a = _svg(tmp_path, "tiny.svg", square_path_data(0, 0, 1e-9))
    b = _svg(tmp_path, "tiny2.svg", square_path_data(0, 0, 1e-9))
    ok(runner.invoke(main, ["outline", a, "--tol", "1e-13", "-o", str(tmp_path / "o.png")]))
    # the default tolerance is relative to the drawing (1e-4 of its size): it works
    ok(runner.invoke(main, ["outline", a, "-o", str(tmp_path / "o1.png")]))
    # an explicit tolerance is absolute: 1e-4 user units is larger than the shape
    res = runner.invoke(main, ["outline", a, "--tol", "1e-4", "-o", str(tmp_path / "o2.png")])
    assert res.exit_code == 2 and "larger than the shapes" in res.output
    area, loops = _sum_area_via_cli(runner, tmp_path, a, b, 1e-13)
    assert abs(area - 4e-18) < 1e-3 * 4e-18


@pytest.mark.parametrize("radius", ["-0.5", "-1e-4"])
def test_inset_of_a_shape_below_tol_erodes_it(runner, tmp_path, radius):
    """A 1e-7 square inset by more than its size (at the default tol 1e-4): all of
    it erodes, one line; the hole test's predicate met loops that round to one
    grid point (a ClipperException, exit 1)."""
    a = _svg(tmp_path, "tinyrect.svg", square_path_data(0, 0, 1e-7))
    line = error_line(runner.invoke(main, ["offset", a, "--radius=" + radius,
                                           "-o", str(tmp_path / "o.svg")]))
    assert "erodes all" in line and "tinyrect" in line


def test_duplicated_points(runner, tmp_path):
    a = _svg(tmp_path, "dup.svg", "M0 0 L0 0 L10 0 L10 0 L10 10 L0 10 L0 10 L0 0 Z")
    b = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 10))
    area, loops = _sum_area_via_cli(runner, tmp_path, a, b, 1e-4)
    assert len(loops) == 1 and abs(area - 400.0) < 1e-6


def test_zero_length_curves(runner, tmp_path):
    a = _svg(tmp_path, "zl.svg", "M0 0 C0 0 0 0 0 0 L10 0 C10 0 10 0 10 0 Q10 10 10 10 "
                                 "L10 10 Q10 10 10 10 L0 10 Z")
    b = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 10))
    area, loops = _sum_area_via_cli(runner, tmp_path, a, b, 1e-4)
    assert len(loops) == 1 and abs(area - 400.0) < 1e-6


def test_zero_length_arc(runner, tmp_path):
    """SVG spec (F.6.2): an arc whose endpoints coincide is omitted (svgpathtools,
    the former parser, asserted on it); morph must not report 'cannot parse SVG ...: AssertionError'."""
    a = _svg(tmp_path, "zla.svg", "M0 0 L10 0 L10 10 A 3 3 0 0 1 10 10 L0 10 Z")
    b = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 10))
    area, loops = _sum_area_via_cli(runner, tmp_path, a, b, 1e-4)
    assert len(loops) == 1 and abs(area - 400.0) < 1e-6


def test_nonconvex_nib(runner, tmp_path):
    """A non-convex 'nib' is just a shape: correct sum (Clipper reference)."""
    a = _svg(tmp_path, "c.svg", "M0 0 L10 0 L10 10 L5 3 L0 10 Z")
    b = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 4))
    area, loops = _sum_area_via_cli(runner, tmp_path, a, b, 1e-4)
    ref = R.polygon_minkowski_sum(svg_region(a), svg_region(b), 1e-3)
    assert abs(area - ref.area) < 1e-3 * ref.area
    assert R.count_outer_and_holes(ref) == (1, 0) and len(loops) == 1


def _self_intersecting_check(runner, tmp_path, d, attrs=""):
    """Either a clear error (exit 2) or the correct sum with a 2-square under the
    path's fill rule (reference: shapely/Clipper of the polygon, rule applied)."""
    pytest.importorskip("shapely")
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    a = _svg(tmp_path, "x.svg", d, attrs)
    b = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 2))
    out = tmp_path / "s.png"
    res = runner.invoke(main, ["sum", a, b, "-o", str(out)])
    if res.exit_code != 0:
        error_line(res)
        return
    loops = minkowski_sum(svg_region(a), svg_region(b), 1e-4)
    # the filled shape under the fill rule, from shapely's own polygonization
    pts = [tuple(map(float, s.split())) for s in d.strip("MZ ").replace("L", ",").split(",")]
    ring = [(x, -y) for x, y in pts]
    if "evenodd" in attrs:
        pytest.importorskip("shapely")
        import shapely
        filled = shapely.make_valid(Polygon(ring))  # GEOS linework: even-odd faces
    else:
        filled = R.region_to_shapely([[pc.line(ring[i], ring[(i + 1) % len(ring)])
                                       for i in range(len(ring))]], 1e-6)
    poly_b = Polygon([(0, 0), (2, 0), (2, -2), (0, -2)])
    parts = getattr(filled, "geoms", [filled])
    ref = unary_union([R.polyline_minkowski_sum(p, poly_b, 1e4) for p in parts])
    area = mo.region_area(loops)
    assert abs(area - ref.area) < 1e-3 * ref.area, (area, ref.area)
    assert (sum(mo.loop_area(l) > 0 for l in loops),
            sum(mo.loop_area(l) < 0 for l in loops)) == R.count_outer_and_holes(ref, 1e-6)


def test_self_intersecting_bow_tie(runner, tmp_path):
    """A bow tie (nonzero fill: two triangles of area 25 each)."""
    _self_intersecting_check(runner, tmp_path, "M0 0 L10 10 L10 0 L0 10 Z")


def test_self_intersecting_figure_eight(runner, tmp_path):
    """Unequal lobes of opposite orientation: nonzero fill fills both lobes."""
    _self_intersecting_check(runner, tmp_path, "M0 0 L20 20 L20 0 L0 10 Z")


def test_self_intersecting_pentagram_nonzero(runner, tmp_path):
    _self_intersecting_check(runner, tmp_path, "M50 0 L79 90 L2 35 L98 35 L21 90 Z")


def test_self_intersecting_pentagram_evenodd(runner, tmp_path):
    """Even-odd: the centre pentagon is a hole (inradius ~14 > the 2-square)."""
    _self_intersecting_check(runner, tmp_path, "M50 0 L79 90 L2 35 L98 35 L21 90 Z",
                             'fill-rule="evenodd"')


# ---------------------------------------------------------------------------- usage

@pytest.mark.parametrize("cmd", ["glyph", "svg"])
@pytest.mark.parametrize("frames", ["0", "-3", "1", "x"])
def test_bad_frames(runner, tmp_path, cmd, frames):
    if cmd == "glyph":
        a, b = "A", "B"
    else:
        a = _svg(tmp_path, "a.svg", square_path_data(0, 0, 10))
        b = _svg(tmp_path, "b.svg", square_path_data(0, 0, 5))
    out = tmp_path / "frames"
    line = error_line(runner.invoke(main, [cmd, a, b, "--frames", frames, "-o", str(out)]))
    assert "frames" in line
    assert not out.exists()


def test_output_under_a_regular_file(runner, tmp_path):
    f = tmp_path / "afile"
    f.write_text("x")
    error_line(runner.invoke(main, ["sum", "A", "B", "-o", str(f / "x.png")]))
    error_line(runner.invoke(main, ["outline", "A", "-o", str(f / "sub" / "x.svg")]))
    error_line(runner.invoke(main, ["glyph", "A", "B", "--frames", "2", "-o", str(f / "dir")]))
    assert f.read_text() == "x"


def test_output_folder_is_a_file(runner, tmp_path):
    f = tmp_path / "afile"
    f.write_text("x")
    error_line(runner.invoke(main, ["glyph", "A", "B", "--frames", "2", "-o", str(f)]))
    assert f.read_text() == "x"


def test_output_bad_suffix_and_missing_folder(runner, tmp_path):
    error_line(runner.invoke(main, ["sum", "A", "B", "-o", str(tmp_path / "x.jpg")]))
    error_line(runner.invoke(main, ["sum", "A", "B", "-o", str(tmp_path / "no" / "x.png")]))


@pytest.mark.parametrize("tol", ["0", "-1", "nan", "abc"])
def test_bad_tolerance(runner, tmp_path, tol):
    error_line(runner.invoke(main, ["sum", "A", "B", "--tol", tol,
                                    "-o", str(tmp_path / "x.png")]))
    assert not (tmp_path / "x.png").exists()


# ---------------------------------------------------------------------------- size and budgets

def _run_limited(args, tmp_path, timeout=30, memory=3 * 2 ** 30):
    """Run `python -m morph.cli ARGS` in a subprocess with a time and memory limit
    (a regression must fail the test, not hang or exhaust the machine)."""
    import resource
    import subprocess
    import sys

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))

    res = subprocess.run([sys.executable, "-m", "morph.cli"] + args, cwd=tmp_path,
                         capture_output=True, text=True, timeout=timeout, preexec_fn=limit)
    return res


def _limit_line(res, *words):
    assert res.returncode == 2, (res.returncode, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("morph: error: "), res.stderr
    assert "Warning" not in res.stderr and "Traceback" not in res.stderr
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


@pytest.mark.parametrize("case", ["coords-1e9", "radius-1e9", "drawing-1e6", "tol-1e-9",
                                  "tol-larger", "tol-inf", "tol-nan", "coords-1e308"])
def test_size_and_tolerance_guards(tmp_path, case):
    """Each case ran > 60 s with up to 15 GB before: now one line within seconds, and
    the line names a tolerance that works (or the bad value)."""
    import time

    big = _svg(tmp_path, "big.svg", "M0 0 C 3e8 -1e8 7e8 1e8 1e9 0 L1e9 1e9 "
                                    "C 7e8 8e8 3e8 1.1e9 0 1e9 Z")
    mid = _svg(tmp_path, "mid.svg", "M0 0 C 3e5 -1e5 7e5 1e5 1e6 0 L1e6 1e6 "
                                    "C 7e5 8e5 3e5 1.1e6 0 1e6 Z")
    sq = _svg(tmp_path, "sq.svg", square_path_data(0, 0, 10))
    huge = _svg(tmp_path, "huge.svg", square_path_data(0, 0, 1e308))
    out = str(tmp_path / "o.png")
    args, words = {
        # an explicit --tol is absolute in user units (the default is relative to the drawing)
        "coords-1e9": (["sum", big, sq, "--tol", "1e-4", "-o", out],
                       ["use a tolerance of at least"]),
        "radius-1e9": (["offset", "O", "--radius", "1e9", "-o", out], ["at least"]),
        "drawing-1e6": (["offset", mid, "--radius", "10", "--tol", "1e-4", "-o", out],
                        ["budget", "at least"]),
        "tol-1e-9": (["sum", "O", "M", "--tol", "1e-9", "-o", out], ["at least"]),
        "tol-larger": (["sum", "O", "M", "--tol", "10", "-o", out], ["larger than"]),
        "tol-inf": (["sum", "O", "M", "--tol", "inf", "-o", out], ["finite"]),
        "tol-nan": (["sum", "O", "M", "--tol", "nan", "-o", out], ["finite"]),
        "coords-1e308": (["outline", huge, "-o", out], ["coordinate"]),
    }[case]
    t0 = time.perf_counter()
    res = _run_limited(args, tmp_path)
    assert time.perf_counter() - t0 < 5
    _limit_line(res, *words)
    assert not (tmp_path / "o.png").exists()


# ------------------------------------------------------- broken UFO and font files

def _relief_copy(tmp_path):
    import shutil

    from tests import RELIEF_SUBSET

    dst = tmp_path / "Broken.ufo"
    shutil.copytree(RELIEF_SUBSET, dst)
    return dst


def _edit(path, old, new):
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))


@pytest.mark.parametrize("damage,says", [
    ("xml", "GLIF contains invalid XML"),
    ("missing", "does not exist"),
    ("huge", "coordinate of 1e+308"),
    ("upm", "unitsPerEm 0"),
    ("cycle", "uses itself through its components: l => l"),
])
def test_broken_ufo_is_bad_input(runner, tmp_path, damage, says):
    # each was an internal error (exit 1: GlifLibError, OverflowError, ufo2ft's
    # division by zero or cyclical component) or a numpy warning before the line
    ufo = _relief_copy(tmp_path)
    glif = ufo / "glyphs" / "l.glif"
    if damage == "xml":
        _edit(glif, "</glyph>", "")
    elif damage == "missing":
        glif.unlink()
    elif damage == "huge":
        _edit(glif, '<point x="252" y="4" type="move"/>', '<point x="1e308" y="4" type="move"/>')
    elif damage == "upm":
        _edit(ufo / "fontinfo.plist", "<integer>1000</integer>", "<integer>0</integer>")
    else:
        _edit(glif, "  </outline>", '    <component base="l"/>\n  </outline>')
    out = tmp_path / "out.otf"
    line = error_line(runner.invoke(main, ["stroke", str(ufo), "-o", str(out), "--glyphs", "l"]))
    assert says in line
    assert not out.exists()


def test_truncated_font_is_bad_input(runner, tmp_path):
    # the glyf table is read lazily, after the font opened: its TTLibError was exit 1
    from morph.parse import default_font_path

    data = open(default_font_path(), "rb").read()
    from fontTools.ttLib import TTFont

    font = TTFont(default_font_path())
    glyf = font.reader.tables["glyf"]
    cut = tmp_path / "cut.ttf"
    cut.write_bytes(data[:glyf.offset + glyf.length // 4])
    line = error_line(runner.invoke(main, ["brush", str(cut), "-o", str(tmp_path / "b.ttf"),
                                           "--glyphs", "o"]))
    assert "cannot read the font" in line and "glyf" in line


def test_numpy_warnings_do_not_add_lines(tmp_path):
    # numpy's RuntimeWarnings (an input that overflowed, e.g. a coordinate of 1e308
    # in a UFO before it was refused) were printed before the error line.  A reader
    # that warns and then fails, in a process of its own (pytest captures warnings
    # raised in-process)
    import os
    import subprocess
    import sys

    script = ("import sys, numpy as np, morph.parse as P\n"
              "from morph.errors import ParseError\n"
              "def bad(*a, **k):\n"
              "    np.array([1e308]) * np.array([1e308])\n"
              "    raise ParseError('shape x is bad', 'x')\n"
              "P.load_shape = bad\n"
              "from morph.cli import run\n"
              "sys.argv = ['morph', 'outline', 'g', '-o', sys.argv[1]]\n"
              "run()\n")
    env = {k: v for k, v in os.environ.items() if k not in ("MORPH_DEBUG", "PYTHONWARNINGS")}
    r = subprocess.run([sys.executable, "-c", script, str(tmp_path / "o.svg")],
                       capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines() == ["morph: error: shape x is bad"], r.stderr


def test_nib_option_must_be_positive_and_finite(runner, tmp_path):
    p = tmp_path / "line.svg"
    p.write_text(SVG % '<path d="M0 0 L10 0" fill="none" stroke="black"/>')
    for nib in ("ellipse:inf,2,0", "ellipse:0,2,0", "ellipse:3,-2,0", "ellipse:3,2,nan",
                "ellipse:1e9,1,0"):  # the last was "the nib is not convex"
        line = error_line(runner.invoke(main, ["stroke", str(p), "-o", str(tmp_path / "s.svg"),
                                               "--nib", nib]))
        assert "--nib" in line


def test_svg_path_without_data_draws_nothing(runner, tmp_path):
    # a <path/> without d is not rendered; it was "object of type 'NoneType' has no len()"
    p = tmp_path / "nod.svg"
    p.write_text(SVG % '<path/>')
    assert "no path or shape that is drawn" in error_line(
        runner.invoke(main, ["outline", str(p), "-o", str(tmp_path / "a.png")]))
    p.write_text(SVG % '<path/><rect width="10" height="20"/>')
    assert abs(mo.region_area(svg_region(str(p))) - 200) < 1e-9


def test_svg_argument_that_is_a_folder_or_self_referencing(runner, tmp_path):
    folder = tmp_path / "dir.svg"
    folder.mkdir()
    assert "it is a folder" in error_line(
        runner.invoke(main, ["outline", str(folder), "-o", str(tmp_path / "a.png")]))
    loop = tmp_path / "loop.svg"
    loop.write_text('<svg xmlns="http://www.w3.org/2000/svg" '
                    'xmlns:xlink="http://www.w3.org/1999/xlink"><g id="g">'
                    '<rect width="5" height="5"/><use xlink:href="#g"/></g></svg>')
    line = error_line(runner.invoke(main, ["outline", str(loop), "-o", str(tmp_path / "b.png")]))
    assert "nest too deeply" in line or "refer" in line


def test_svgz_and_svg_without_suffix_are_read_as_svg(runner, tmp_path):
    # both were taken for glyph names ("font ... has no glyph for 'x.svgz'")
    import gzip

    doc = SVG % '<rect x="0" y="0" width="30" height="20"/>'
    (tmp_path / "r.svgz").write_bytes(gzip.compress(doc.encode()))
    (tmp_path / "drawing").write_text(doc)
    (tmp_path / "bad.svgz").write_bytes(gzip.compress(doc.encode())[:20])
    for name in ("r.svgz", "drawing"):
        out = tmp_path / (name + ".svg")
        ok(runner.invoke(main, ["outline", str(tmp_path / name), "-o", str(out)]))
        assert abs(mo.region_area(svg_region(str(out))) - 600) < 1e-6
    line = error_line(runner.invoke(main, ["outline", str(tmp_path / "bad.svgz"), "-o",
                                           str(tmp_path / "bad.png")]))
    assert "cannot read SVG" in line


def test_font_collection_reads_its_first_font(runner, tmp_path):
    # a .ttc was refused with fontTools' "specify a font number" (no option gives one)
    from fontTools.ttLib import TTCollection, TTFont

    from morph.parse import cubic_test_font_path, default_font_path, glyph_region

    col = TTCollection()
    col.fonts = [TTFont(default_font_path()), TTFont(cubic_test_font_path())]
    path = tmp_path / "pair.ttc"
    col.save(str(path))
    got = glyph_region("g", str(path)).region
    assert mo.region_area(got) == pytest.approx(mo.region_area(glyph_region("g").region))
    ok(runner.invoke(main, ["outline", "g", "--font", str(path), "-o", str(tmp_path / "g.png")]))
