"""Brush fonts: written glyph = glyph ⊕ nib (Hausdorff <= 1 font unit vs Clipper).

A-Z, a-z of both bundled fonts are checked the same way by ``python -m bench.brush``
(bench/brush.md); here a few glyphs, kept cheap.
"""

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from fontTools.pens.areaPen import AreaPen
from fontTools.pens.recordingPen import DecomposingRecordingPen
from fontTools.ttLib import TTFont
from PIL import Image, ImageDraw, ImageFont

from morph import piece as pc
from morph.cli import main
from morph.errors import MorphError, TopologyError
from morph.fonts import jobs as jobs_mod
from morph.fonts.tables import outline_glyphs
from tests.fontfixtures import WIDE, bounds, build_mark_font, build_variable_font
from morph.fonts.brush import (brush_font, check_convex_nib, composite_plan, ellipse_nib,
                               parse_glyph_spec, region_extent)
from morph.parse import cubic_test_font_path, default_font_path, glyph_region
from morph.region import translate_region
from tests.oracles.reference import hausdorff, polygon_minkowski_sum, region_to_shapely

NIB = (80.0, 30.0, 30.0)
CHARS = "oTgSWe"


@pytest.fixture(scope="module", params=["ttf", "otf"])
def brushed(request, tmp_path_factory):
    src = default_font_path() if request.param == "ttf" else cubic_test_font_path()
    out = tmp_path_factory.mktemp("brush") / ("b." + request.param)
    seen = []
    stats = brush_font(src, out, ellipse_nib(*NIB), list(CHARS) + [" "], tol=0.5,
                       family_name="Test Brush", progress=seen.append)
    assert len(seen) == len(CHARS) + 1 and stats["glyphs"] == len(CHARS) + 1
    return src, out


def _shifted_nib():
    nib = ellipse_nib(*NIB)
    shift = -region_extent(nib)[0]
    return translate_region(nib, (shift, 0.0))


def _assert_sum(src, out, ch_or_name):
    got = glyph_region(ch_or_name, font=str(out)).region
    ref = polygon_minkowski_sum(glyph_region(ch_or_name, font=src).region, _shifted_nib(),
                                0.25)
    assert hausdorff(region_to_shapely(got, 0.05), ref, 0.5) <= 1.0, ch_or_name


def test_outlines_equal_glyph_plus_nib(brushed):
    src, out = brushed
    for ch in CHARS:
        _assert_sum(src, out, ch)


def _bounds(font, name):
    from fontTools.pens.boundsPen import BoundsPen

    pen = BoundsPen(font.getGlyphSet())
    font.getGlyphSet()[name].draw(pen)
    return pen.bounds


def _control_xmin(font, name):
    """xMin of the glyph's control points (glyf's xMin, which hmtx's lsb is)."""
    from fontTools.pens.boundsPen import ControlBoundsPen

    pen = ControlBoundsPen(font.getGlyphSet())
    font.getGlyphSet()[name].draw(pen)
    return pen.bounds[0]


def test_composites_follow_swept_components(brushed):
    """TrueType oacute = o + acute: o swept, oacute grows like o, acute stays centred.

    CFF has no composites (the bundled .otf has no seac either): its accented letters
    are plain outlines and stay as they are when their base letter is swept.
    """
    src, out = brushed
    a, b = TTFont(str(src)), TTFont(str(out))
    if "glyf" not in a:
        for name in ("oacute", "eacute"):
            assert b["hmtx"][name] == a["hmtx"][name]
            assert _bounds(b, name) == _bounds(a, name)
        return
    x0, _, x1, _ = region_extent(ellipse_nib(*NIB))
    assert composite_plan(a, ["o"]) == (["ograve", "oacute", "ocircumflex", "otilde",
                                          "odieresis"], [])
    for name in ("ograve", "oacute", "ocircumflex", "otilde", "odieresis"):
        g = b["glyf"][name]
        assert g.isComposite()
        assert b["hmtx"][name][0] == b["hmtx"]["o"][0] == round(a["hmtx"][name][0] + x1 - x0)
        # the lsb is the control box's xMin (an off-curve point may reach past the ink)
        assert b["hmtx"][name][1] == _control_xmin(b, name)
        assert _control_xmin(b, name) <= _bounds(b, name)[0] < _control_xmin(b, name) + 1
        mark = [c for c in g.components if c.glyphName != "o"][0]
        old = [c for c in a["glyf"][name].components if c.glyphName == mark.glyphName][0]
        assert (mark.x - old.x, mark.y - old.y) == (round((x1 - x0) / 2), 0)
        # the mark keeps its place over the (widened) o: centres agree as before
        (ox0, _, ox1, _), (px0, _, px1, _) = _bounds(a, "o"), _bounds(b, "o")
        assert abs((px0 + px1) / 2 - (ox0 + ox1) / 2 - mark.x + old.x) <= 1
        assert _bounds(b, name)[2] <= b["hmtx"][name][0]  # ink inside the advance
    # unrelated composites and the accents themselves are untouched
    for name in ("Eacute", "acute"):
        assert b["hmtx"][name] == a["hmtx"][name]
    # Pillow: "oó" in the new font, no ink clipped at the right edge of the advance
    fnt = ImageFont.truetype(str(out), 100)
    adv = fnt.getlength("ó")
    img = Image.new("L", (int(adv) + 40, 160), 255)
    ImageDraw.Draw(img).text((20, 20), "ó", font=fnt, fill=0)
    ink = np.nonzero(np.asarray(img).min(axis=0) < 128)[0]
    assert ink[0] >= 20 and ink[-1] <= 20 + adv


def test_chosen_composite_is_decomposed_and_swept(tmp_path):
    """A chosen composite becomes glyph ⊕ nib of its decomposed outline (accent too)."""
    src, out = default_font_path(), tmp_path / "c.ttf"
    stats = brush_font(src, out, ellipse_nib(*NIB), ["eacute", "Y"], tol=0.5,
                       composites="sweep")
    assert (stats["glyphs"], stats["followed"], stats["decomposed"]) == (2, 0, 1)
    b = TTFont(str(out))
    for name in ("eacute", "Yacute"):  # chosen / decomposed because Y was swept
        assert not b["glyf"][name].isComposite()
        _assert_sum(src, out, name)
    with pytest.raises(ValueError, match="composites"):  # a bad argument
        brush_font(src, "unused.ttf", ellipse_nib(*NIB), ["Y"], composites="keep")


def test_metrics_names_and_directions(brushed):
    src, out = brushed
    a, b = TTFont(str(src)), TTFont(str(out))
    nib_w = region_extent(ellipse_nib(*NIB))
    nib_w = nib_w[2] - nib_w[0]
    cmap = a.getBestCmap()
    for ch in CHARS + " ":
        name = cmap[ord(ch)]
        assert b["hmtx"][name][0] == round(a["hmtx"][name][0] + nib_w)
        if ch != " ":  # left side bearing kept (outline shifted by the nib's left extent):
            # the curves' left edge within tol (0.5) + rounding (0.71) of the source's; the
            # hmtx value is the control box's, which an off-curve point may widen
            assert abs(_bounds(b, name)[0] - a["hmtx"][name][1]) <= 0.5 + 0.71
    assert b["name"].getDebugName(1) == "Test Brush"
    assert b["name"].getDebugName(6).startswith("TestBrush")
    # contour direction of the format: TrueType outer clockwise (AreaPen < 0),
    # CFF outer counter-clockwise (> 0); the bundled test .otf keeps TrueType directions
    want = -1.0 if "glyf" in b else 1.0
    for ch in CHARS:
        name = cmap[ord(ch)]
        pa, pb = AreaPen(a.getGlyphSet()), AreaPen(b.getGlyphSet())
        a.getGlyphSet()[name].draw(pa)
        b.getGlyphSet()[name].draw(pb)
        assert np.sign(pb.value) == want
        assert abs(pb.value) > abs(pa.value)
    # untouched glyph stays
    assert b["hmtx"]["A"] == a["hmtx"]["A"]


def test_pillow_renders(brushed):
    _, out = brushed
    fnt = ImageFont.truetype(str(out), 48)
    img = Image.new("L", (200, 70), 255)
    ImageDraw.Draw(img).text((5, 5), "oTg", font=fnt, fill=0)
    assert np.asarray(img).min() == 0


def test_nonconvex_nib_rejected():
    star = [[pc.line(a, b) for a, b in zip(pts, np.roll(pts, -1, axis=0))]
            for pts in [np.array([[0, 0], [10, 0], [5, 2], [10, 10], [0, 10]], float)]]
    with pytest.raises(MorphError, match="not convex"):
        check_convex_nib(star)
    check_convex_nib(ellipse_nib(10, 5, 20))


def test_nib_errors_keep_the_nib():
    """A bad nib is a bad argument (ValueError) and a MorphError, and keeps the nib."""
    from morph.errors import NibError

    with pytest.raises(NibError) as info:
        ellipse_nib(0, 5, 10)
    assert isinstance(info.value, ValueError) and info.value.nib == (0, 5, 10)
    two = ellipse_nib(10, 5) + ellipse_nib(4, 4)
    with pytest.raises(NibError, match="one closed convex shape") as info:
        check_convex_nib(two)
    assert info.value.nib is two


def test_parse_glyph_spec():
    assert parse_glyph_spec("a-c,X,ampersand") == ["a", "b", "c", "X", "ampersand"]


def test_cli_brush(tmp_path):
    out = tmp_path / "f.ttf"
    r = CliRunner().invoke(main, ["brush", "-o", str(out), "--glyphs", "T,o",
                                  "--nib", "ellipse:60,20,45", "--sample", "ToT"])
    assert r.exit_code == 0, r.output
    assert TTFont(str(out))["name"].getDebugName(1).endswith("Brush")
    assert (tmp_path / "f.ttf.png").stat().st_size > 0
    nib = tmp_path / "nib.svg"
    nib.write_text('<svg xmlns="http://www.w3.org/2000/svg"><path '
                   'd="M0 0 L20 0 L10 5 L20 20 L0 20 Z"/></svg>')
    r = CliRunner().invoke(main, ["brush", "-o", str(tmp_path / "g.ttf"), "--glyphs", "T",
                                  "--nib-svg", str(nib)])
    assert r.exit_code == 2
    assert "not convex" in r.output


def test_cli_brush_composites(tmp_path):
    """--composites sweep decomposes eacute and sweeps it (a simple glyph in the
    output); follow keeps it a composite (TrueType)."""
    for mode, composite in (("follow", True), ("sweep", False)):
        out = tmp_path / (mode + ".ttf")
        r = CliRunner().invoke(main, ["brush", "-o", str(out), "--glyphs", "e",
                                      "--composites", mode, "--sample", "e"])
        assert r.exit_code == 0, r.output
        f = TTFont(str(out))
        name = f.getBestCmap()[ord("é")]
        assert f["glyf"][name].isComposite() == composite, mode
    r = CliRunner().invoke(main, ["brush", "-o", str(tmp_path / "x.ttf"), "--composites", "no"])
    assert r.exit_code == 2


# ========================================================== outlines of the written font



def assert_ots(path):
    import ots  # a test extra: missing, the test fails rather than skips
    r = ots.sanitize(str(path), capture_output=True)
    assert r.returncode == 0, (r.stdout + r.stderr).decode(errors="replace")


def contour_points(font, name):
    """Every contour of a glyph as its list of points in order (on- and off-curve),
    closing point not repeated, drawn through the glyph set (components decomposed)."""
    pen = DecomposingRecordingPen(font.getGlyphSet())
    font.getGlyphSet()[name].draw(pen)
    contours, cur = [], None
    for op, args in pen.value:
        if op == "moveTo":
            cur = [args[0]]
        elif op in ("lineTo", "qCurveTo", "curveTo"):
            cur.extend(a for a in args if a is not None)
        elif op in ("closePath", "endPath"):
            if len(cur) > 1 and cur[-1] == cur[0]:
                cur.pop()
            contours.append(cur)
    return contours


def assert_clean_outlines(font, names):
    """No zero-length segment and no repeated point in any contour; no two segments
    of a glyph between the same two on-curve points (fontbakery's check)."""
    for name in names:
        for pts in contour_points(font, name):
            for a, b in zip(pts, pts[1:] + pts[:1]):
                assert a != b, (name, a)


@pytest.fixture(scope="module")
def mark_font(tmp_path_factory):
    return build_mark_font(tmp_path_factory.mktemp("marks") / "Marks.ttf")


def _shape(path, text):
    """(glyph name, x, y) of each glyph of ``text`` shaped by HarfBuzz (pen positions)."""
    hb = pytest.importorskip("uharfbuzz")
    font = TTFont(str(path))
    order = font.getGlyphOrder()
    hbf = hb.Font(hb.Face(hb.Blob.from_file_path(str(path))))
    buf = hb.Buffer()
    buf.add_str(text)
    buf.guess_segment_properties()
    hb.shape(hbf, buf)
    out, x = [], 0
    for info, pos in zip(buf.glyph_infos, buf.glyph_positions):
        out.append((order[info.codepoint], x + pos.x_offset, pos.y_offset))
        x += pos.x_advance
    return font, out


def _centres(path, text):
    font, shaped = _shape(path, text)
    cs = []
    for name, x, y in shaped:
        x0, y0, x1, y1 = bounds(font, name)
        cs.append((x + (x0 + x1) / 2.0, y + (y0 + y1) / 2.0))
    return np.array(cs), [s[0] for s in shaped]


@pytest.mark.parametrize("glyphs", [["e", "o", "m", "acutecomb", "gravecomb"], ["e", "o", "m"]],
                         ids=["marks-swept", "marks-not-swept"])
def test_gpos_marks_stay_centred(mark_font, tmp_path, glyphs):
    """é = e + U+0301 (+ U+0300 stacked by mkmk) shaped by HarfBuzz on the written font:
    each mark keeps its offset from the base's centre within 2 units (the anchors
    moved with the sweep), whether the marks were swept or not.  A swept mark on a
    base without an anchor (m + U+0301: the mark hangs from the end of m's advance)
    keeps its offset too."""
    out = tmp_path / "m.ttf"
    stats = brush_font(str(mark_font), out, ellipse_nib(*NIB), glyphs, tol=0.5)
    assert stats["anchors"] > 0 and not stats["fallback"]
    text = "e\u0301\u0300"
    before, names = _centres(mark_font, text)
    after, names_after = _centres(out, text)
    assert names == names_after == ["e", "acutecomb", "gravecomb"]
    for k in (1, 2):
        shift = (after[k] - after[0]) - (before[k] - before[0])
        assert np.abs(shift).max() <= 2.0, (k, before, after)
    assert abs(after[1][0] - after[0][0]) <= 2.0  # the acute was centred: it still is
    if "acutecomb" in glyphs:
        (b0, b1), (a0, a1) = _centres(mark_font, "m\u0301")[0], _centres(out, "m\u0301")[0]
        assert np.abs((a1 - a0) - (b1 - b0)).max() <= 2.0, (b1 - b0, a1 - a0)
    b = TTFont(str(out))
    assert b["hmtx"]["acutecomb"][0] == 0  # zero-width marks stay zero-width
    assert_ots(out)


def test_fallback_keeps_the_font(tmp_path, monkeypatch):
    """A glyph whose sum raises is written by the polygon fallback (within 1 unit of
    glyph ⊕ nib), named in the result; if that fails too it is left as in the source;
    the CLI writes the font and exits 1 naming it."""
    import morph.minkowski

    real, real_many = morph.minkowski.minkowski_sum, morph.minkowski.minkowski_sums

    def flaky(a, b, tol, *args, **kw):
        if len(a) == 2:  # 'o' (two loops) fails, 'T' (one loop) works
            raise TopologyError("no closed loop (test)")
        return real(a, b, tol, *args, **kw)

    def flaky_many(regions, b, tol, *args, **kw):  # a chunk's sums, as one: 'o' fails it
        if any(len(a) == 2 for a in regions):
            raise TopologyError("no closed loop (test)")
        return real_many(regions, b, tol, *args, **kw)

    monkeypatch.setattr(morph.minkowski, "minkowski_sum", flaky)
    monkeypatch.setattr(morph.minkowski, "minkowski_sums", flaky_many)
    src, out = default_font_path(), tmp_path / "f.ttf"
    stats = brush_font(src, out, ellipse_nib(*NIB), ["o", "T"], tol=0.5)
    assert list(stats["fallback"]) == ["o"]
    kind, error = stats["fallback"]["o"]
    assert kind == "polygon" and "TopologyError" in error
    _assert_sum(src, out, "o")
    _assert_sum(src, out, "T")
    assert_clean_outlines(TTFont(str(out)), ["o", "T"])

    r = CliRunner().invoke(main, ["brush", "-o", str(tmp_path / "c.ttf"), "--glyphs", "o,T",
                                  "--jobs", "1", "--sample", "oT"])
    assert r.exit_code == 1, r.output
    assert (tmp_path / "c.ttf").stat().st_size > 0 and (tmp_path / "c.ttf.html").exists()
    line = [s for s in r.output.splitlines() if s.startswith("morph: error:")]
    assert len(line) == 1 and "o (polygon sum" in line[0] and "T (" not in line[0]

    def broken(*args, **kw):  # a MorphError: the ladder's last rung fails too
        raise MorphError("no polygon either (test)")

    monkeypatch.setattr(jobs_mod, "polygon_sum", broken)
    stats = brush_font(src, tmp_path / "g.ttf", ellipse_nib(*NIB), ["o"], tol=0.5)
    assert stats["fallback"]["o"][0] == "source"
    a, b = TTFont(src), TTFont(str(tmp_path / "g.ttf"))
    assert b["hmtx"]["o"] == a["hmtx"]["o"] and bounds(b, "o") == bounds(a, "o")


def test_fallback_retry_at_finer_tolerance(tmp_path, monkeypatch):
    """A sum that raises at the geometry share of tol but not at RETRY_SHARE of it keeps
    its curves (kind "retry"); one that raises for the nib as given is computed with
    the nib turned (within tol)."""
    import morph.minkowski
    from morph.budget import RETRY_SHARE, plan

    geometry = plan(0.5).geometry

    real = morph.minkowski.minkowski_sum

    def coarse_fails(a, b, tol, *args, **kw):
        if tol > RETRY_SHARE * geometry:
            raise TopologyError("fails at %g (test)" % tol)
        return real(a, b, tol, *args, **kw)

    monkeypatch.setattr(morph.minkowski, "minkowski_sum", coarse_fails)
    src, out = default_font_path(), tmp_path / "r.ttf"
    stats = brush_font(src, out, ellipse_nib(*NIB), ["o"], tol=0.5)
    assert stats["fallback"]["o"][0] == "retry" and "fails at %g" % geometry in stats["fallback"]["o"][1]
    _assert_sum(src, out, "o")
    g = TTFont(str(out))["glyf"]["o"]
    assert g.numberOfContours == 2 and not all(g.flags[k] & 1 for k in range(len(g.flags)))

    nib = ellipse_nib(*NIB)
    real_many = morph.minkowski.minkowski_sums

    def given(b):   # the nib as given (brush_font sums it as a validated Region, a copy)
        return len(b) == len(nib) and all(
            len(lb) == len(ln) and all(np.array_equal(p, q) for p, q in zip(lb, ln))
            for lb, ln in zip(b, nib))

    def only_turned(a, b, tol, *args, **kw):  # fails for the nib as given, at any tolerance
        if given(b):
            raise TopologyError("tangent nib (test)")
        return real(a, b, tol, *args, **kw)

    def only_turned_many(regions, b, tol, *args, **kw):   # a chunk's sums, as one
        if given(b):
            raise TopologyError("tangent nib (test)")
        return real_many(regions, b, tol, *args, **kw)

    monkeypatch.setattr(morph.minkowski, "minkowski_sum", only_turned)
    monkeypatch.setattr(morph.minkowski, "minkowski_sums", only_turned_many)
    out = tmp_path / "turned.ttf"  # a new path: glyph_region caches fonts by path
    stats = brush_font(src, out, nib, ["o", "T"], tol=0.5)
    assert {n: k for n, (k, _) in stats["fallback"].items()} == {"o": "rotated", "T": "rotated"}
    _assert_sum(src, out, "o")
    _assert_sum(src, out, "T")


def test_jobs_give_the_same_font(tmp_path, monkeypatch):
    """--jobs 2 (a process pool) writes the same outlines, metrics and anchors as 1."""
    monkeypatch.setattr("morph.fonts.jobs.MIN_SPLIT", 1)   # two chunks: workers for jobs=2
    outs = []
    for jobs in (1, 2):
        out = tmp_path / ("j%d.ttf" % jobs)
        brush_font(default_font_path(), out, ellipse_nib(*NIB), list("oTgSWe"), tol=0.5,
                   jobs=jobs)
        outs.append(TTFont(str(out)))
    a, b = outs
    for tag in ("glyf", "hmtx", "OS/2", "hhea", "name", "GPOS"):
        assert a.getTableData(tag) == b.getTableData(tag) or \
            a[tag].compile(a) == b[tag].compile(b), tag


def test_tables_after_brush(brushed):
    """xAvgCharWidth recomputed, vertical metrics grown by the nib, coherent names,
    clean contours, and OTS accepts the font."""
    src, out = brushed
    a, b = TTFont(str(src)), TTFont(str(out))
    widths = [w for w, _ in b["hmtx"].metrics.values() if w > 0]
    assert b["OS/2"].xAvgCharWidth == round(sum(widths) / len(widths))
    _, y0, _, y1 = region_extent(ellipse_nib(*NIB))
    up, down = int(np.ceil(y1)), int(np.ceil(-y0))
    assert b["hhea"].ascent == a["hhea"].ascent + up
    assert b["hhea"].descent == a["hhea"].descent - down
    assert b["OS/2"].sTypoAscender == a["OS/2"].sTypoAscender + up
    assert b["OS/2"].usWinDescent == a["OS/2"].usWinDescent + down
    for name in CHARS:
        gy0, gy1 = bounds(b, b.getBestCmap()[ord(name)])[1::2]
        assert gy1 <= b["OS/2"].usWinAscent and -gy0 <= b["OS/2"].usWinDescent
    n = b["name"]
    assert (n.getDebugName(1), n.getDebugName(2), n.getDebugName(4), n.getDebugName(6)) == \
        ("Test Brush", "Regular", "Test Brush Regular", "TestBrush-Regular")
    assert n.getDebugName(16) is None and n.getDebugName(17) is None
    if a["name"].getDebugName(25):  # variations PostScript prefix: follows the family
        assert n.getDebugName(25) == "TestBrush"
    assert_clean_outlines(b, [b.getBestCmap()[ord(c)] for c in CHARS])
    assert_ots(out)


def test_clean_contours_m(tmp_path):
    """The brushed 'm' had a zero-length segment (three equal points)."""
    out = tmp_path / "m.ttf"
    brush_font(default_font_path(), out, ellipse_nib(*NIB), ["m", "n", "h"], tol=0.5)
    assert_clean_outlines(TTFont(str(out)), ["m", "n", "h"])


def test_woff2_output(tmp_path):
    out = tmp_path / "w.woff2"
    brush_font(default_font_path(), out, ellipse_nib(*NIB), ["T"], tol=0.5)
    f = TTFont(str(out))
    assert f.flavor == "woff2" and f["hmtx"]["T"][0] > TTFont(default_font_path())["hmtx"]["T"][0]
    assert_ots(out)


def test_base_not_chosen_is_swept(tmp_path):
    """ï = dotlessi + dieresis: with only 'i' chosen, dotlessi is swept too so that ï
    (and ì í î) follow; they are named in the result."""
    src, out = default_font_path(), tmp_path / "i.ttf"
    a = TTFont(src)
    cmap = a.getBestCmap()
    base = a["glyf"][cmap[ord("ï")]].components[0].glyphName
    stats = brush_font(src, out, ellipse_nib(*NIB), ["i"], tol=0.5)
    assert set(stats["base_not_chosen"]) == {base}
    assert cmap[ord("ï")] in stats["base_not_chosen"][base]
    b = TTFont(str(out))
    for ch in "ìíîï":
        name = cmap[ord(ch)]
        assert b["glyf"][name].isComposite()
        assert b["hmtx"][name][0] == b["hmtx"]["i"][0]
    x0, _, x1, _ = region_extent(ellipse_nib(*NIB))
    (p0, _, p1, _), (q0, _, q1, _) = bounds(a, base), bounds(b, base)
    assert abs((q1 - q0) - (p1 - p0) - (x1 - x0)) <= 1  # dotlessi swept
    assert_ots(out)


def test_default_glyph_set_is_every_outline():
    a = TTFont(default_font_path())
    names = outline_glyphs(a)
    glyf = a["glyf"]
    assert "A" in names and "space" not in names and "eacute" not in names  # composite
    assert all(glyf[n].numberOfContours > 0 for n in names)
    assert len(names) == sum(1 for n in a.getGlyphOrder() if glyf[n].numberOfContours > 0)
    b = TTFont(cubic_test_font_path())
    cff_names = outline_glyphs(b)
    assert "A" in cff_names and "space" not in cff_names and "eacute" in cff_names


@pytest.fixture(scope="module")
def variable_font(tmp_path_factory):
    return build_variable_font(tmp_path_factory.mktemp("var"))


def test_variable_font_at_location(variable_font, tmp_path):
    """A variable font is brushed at --location (default: the default instance); the
    output is static."""
    nib = ellipse_nib(*NIB)
    x0, _, x1, _ = region_extent(nib)
    src = TTFont(default_font_path())
    for loc, scale in ((None, 1.0), ({"wght": 700}, WIDE), ("wght=550", None)):
        out = tmp_path / "v.ttf"
        brush_font(str(variable_font), out, nib, ["o"], tol=0.5, location=loc)
        b = TTFont(str(out))
        assert "fvar" not in b and "gvar" not in b
        if scale is not None:
            assert b["hmtx"]["o"][0] == round(round(src["hmtx"]["o"][0] * scale) + x1 - x0)
        assert_ots(out)
    r = CliRunner().invoke(main, ["brush", str(variable_font), "-o", str(tmp_path / "c.ttf"),
                                  "--glyphs", "o", "--location", "wght=900"])
    assert r.exit_code == 2 and "wght 400..700" in r.output


def test_location_for_glyph_commands(variable_font, tmp_path):
    """sum/glyph/outline read glyphs at --location (fontTools instancer)."""
    from morph.parse import glyph_region as gr

    w0 = region_extent(gr("o", font=str(variable_font)).region)
    w1 = region_extent(gr("o", font=str(variable_font), location="wght=700").region)
    assert (w1[2] - w1[0]) == pytest.approx((w0[2] - w0[0]) * WIDE, abs=2)
    out = tmp_path / "s.svg"
    r = CliRunner().invoke(main, ["sum", "o", "l", "--font", str(variable_font),
                                  "--location", "wght=700", "-o", str(out), "--tol", "1e-3"])
    assert r.exit_code == 0, r.output
    r = CliRunner().invoke(main, ["outline", "o", "--location", "wght=700",
                                  "-o", str(tmp_path / "x.png")])
    assert r.exit_code == 2 and "not a variable font" in r.output
    r = CliRunner().invoke(main, ["outline", "o", "--font", str(variable_font),
                                  "--location", "wght700", "-o", str(tmp_path / "y.png")])
    assert r.exit_code == 2 and "wght=700" in r.output


def _fontbakery(path):
    """{(check id, status)} of the WARN/FAIL/ERROR results of check-universal."""
    import json
    import subprocess
    import sys

    report = Path(str(path) + ".json")
    subprocess.run([sys.executable, "-m", "fontbakery", "check-universal", "--skip-network",
                    "-l", "WARN", "--json", str(report), str(path)],
                   capture_output=True, check=False, timeout=300)
    data = json.loads(report.read_text())
    return {(c["key"][1], c["result"]) for s in data["sections"] for c in s["checks"]
            if c["result"] in ("WARN", "FAIL", "ERROR", "FATAL")}


@pytest.mark.slow
def test_fontbakery_adds_nothing(mark_font, tmp_path):
    """fontbakery check-universal: the brushed font has no FAIL or WARN the source lacks."""
    pytest.importorskip("fontbakery")
    out = tmp_path / "FB.ttf"
    brush_font(str(mark_font), out, ellipse_nib(*NIB), list("AHOVamneosg") + ["acutecomb"],
               tol=0.5)
    before, after = _fontbakery(mark_font), _fontbakery(out)
    assert after - before == set(), sorted(after - before)


def test_chunk_sums_glyph_by_glyph_where_the_packed_call_raises(monkeypatch):
    """sweep_glyphs sums its glyphs together; where that raises, one by one: the
    same kinds, and outlines within the tolerance of each other."""
    import morph.minkowski
    from morph.fonts.brush import sweep_glyph, sweep_glyphs

    pen = ellipse_nib(*NIB)
    jobs = [(c, glyph_region(c).region, pen, 0.5, "qac", (0.0, 0.0), False) for c in "oTg"]
    together = sweep_glyphs(jobs)

    def broken(*args, **kw):
        raise TopologyError("packed call failed (test)")

    monkeypatch.setattr(morph.minkowski, "minkowski_sums", broken)
    alone = sweep_glyphs(jobs)
    for job, (n1, c1, k1, e1), (n2, c2, k2, e2) in zip(jobs, together, alone):
        assert n1 == n2 and k1 == k2 == "exact" and e1 is None and e2 is None
        assert len(c1) == len(c2)
        single = sweep_glyph(job)[1]                # as if each glyph were swept alone
        assert len(c2) == len(single)
        for a, b in zip(c2, single):                # contours: lists of segments
            assert len(a) == len(b) and all(np.array_equal(s, u) for s, u in zip(a, b))


def _recomputed(path):
    """The font at ``path`` saved again by fontTools with every glyph decoded (its
    boxes and maxp recomputed from the outlines) and read back."""
    import io

    f = TTFont(str(path))
    f.ensureDecompiled()
    buf = io.BytesIO()
    f.save(buf)
    return TTFont(io.BytesIO(buf.getvalue()))


def test_boxes_as_fonttools_recomputes_them(brushed):
    """The save computes the boxes and maxp once, the glyphs not swept read from their
    stored form (morph.fonts.tables, ``saving``): head's box and flags, hhea's side
    bearings and extent, maxp and the CFF font box are what fontTools computes from
    every glyph's outline; the glyphs not swept keep the source's bytes."""
    src, out = brushed
    a, b, source = TTFont(str(out)), _recomputed(out), TTFont(str(src))
    assert [getattr(a["head"], k) for k in ("xMin", "yMin", "xMax", "yMax", "flags")] == \
        [getattr(b["head"], k) for k in ("xMin", "yMin", "xMax", "yMax", "flags")]
    assert a["hhea"].compile(a) == b["hhea"].compile(b)
    assert a["maxp"].compile(a) == b["maxp"].compile(b)
    swept = {source.getBestCmap()[ord(c)] for c in CHARS + " "}
    kept = [n for n in source.getGlyphOrder() if n not in swept]
    if "CFF " in a:
        assert a["CFF "].cff.topDictIndex[0].FontBBox == b["CFF "].cff.topDictIndex[0].FontBBox
        cs, src_cs = (f["CFF "].cff.topDictIndex[0].CharStrings for f in (a, source))
        assert all(cs[n].bytecode == src_cs[n].bytecode for n in kept)
    else:
        stored = [(a["glyf"].glyphs[n], source["glyf"].glyphs[n]) for n in kept]
        simple = [(g, s) for g, s in stored
                  if int.from_bytes(getattr(s, "data", b"\0\0")[:2], "big", signed=True) >= 0]
        assert len(simple) > 50 and all(getattr(g, "data", None) == getattr(s, "data", None)
                                        for g, s in simple)
