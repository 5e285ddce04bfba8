"""Skeleton strokes and calligraphic fonts: morph.fonts.stroke, ``morph stroke`` (issue
#15); reading the skeletons (morph.parse.ufo) is tests/parse/test_ufo.py.

References are independent: the written glyphs are read back from the compiled font
and compared with a Clipper polygon of the flattened skeleton ⊕ the flattened nib
(``tests/stroke_reference.py``); the plumbing (metrics, components, anchors,
features) is also run with that polygon stroker, so it is checked apart from the
exact geometry.  The full A-Z, a-z, 0-9 sweep is ``python -m bench.stroke``.
"""

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely
import shapely.affinity
import ufoLib2
from click.testing import CliRunner
from fontTools.pens.boundsPen import BoundsPen
from fontTools.ttLib import TTFont

from morph.cli import main
from morph.errors import MorphError, ParseError
from morph.fonts.brush import ellipse_nib, region_extent
from morph.fonts.fea import move_feature_anchors, moved_features
from morph.fonts.stroke import stroke_plan, stroke_ufo
from morph.nib import nib_is_symmetric
from morph.parse import glyph_region
from morph.region import translate_region
from morph.parse.ufo import decomposed_paths
from tests import RELIEF_SUBSET as SUBSET
from tests.oracles.reference import count_outer_and_holes, hausdorff, region_to_shapely
from tests.oracles.stroke_reference import polygon_stroker, stroke_polygon

NIB_SPEC = (90.0, 20.0, 30.0)
ROUNDING = 0.71  # integer coordinates in the written font: sqrt(2) / 2
REF_TOL = 0.05   # flattening of the Clipper reference (font units)


def nib():
    return ellipse_nib(*NIB_SPEC)


def shift_of(font, name, nib_region):
    """The written glyph's horizontal shift (stroke_ufo's metric rule)."""
    x0, _, x1, _ = region_extent(nib_region)
    grow = int(round(x1 - x0))
    return int(round(-x0)) - (grow if font[name].width == 0 else 0)


# =========================================================================== features

FEA = """# a comment kept
markClass [acutecomb] <anchor 78 555> @mark_top;
feature mark {
\tlookup mark_latn {
\t\tpos base e <anchor 295 555> mark @mark_top;   # trailing
\t\tpos base [o c] <anchor  296 555> mark @mark_top;
\t\tpos base x <anchor 10 20> mark @mark_top;
\t} mark_latn;
} mark;
"""


def test_move_feature_anchors():
    offsets = {"acutecomb": (-40, 0), "e": (39, 0), "o": (39, 0), "c": (39, 0)}
    out = move_feature_anchors(FEA, ["acutecomb", "e", "o", "c", "x"], offsets.get)
    assert "markClass [acutecomb] <anchor 38 555> @mark_top;" in out
    assert "pos base e <anchor 334 555> mark @mark_top;   # trailing" in out
    assert "pos base [o c] <anchor 335 555> mark @mark_top;" in out
    assert "pos base x <anchor 10 20> mark @mark_top;" in out  # not moved: no offset
    assert out.startswith("# a comment kept\n")
    with pytest.raises(MorphError, match="different offsets"):
        move_feature_anchors(FEA, ["acutecomb", "e", "o", "c", "x"],
                             {"acutecomb": (0, 0), "e": (1, 0), "o": (1, 0), "c": (2, 0)}.get)
    bad = "feature x { sub a by ; } x;"
    with pytest.raises(ParseError, match="cannot parse") as info:
        move_feature_anchors(bad, ["a"], offsets.get)
    assert info.value.source == bad


def test_moved_features_tree_is_the_moved_text_parsed(tmp_path):
    """The tree handed to the compiler (parsed once, anchors moved in it) is the one
    feaLib makes of the moved text; a text that includes files gets no tree (its
    includes resolve where the font is); a tree whose anchors were not moved fails."""
    import io

    from fontTools.feaLib.parser import Parser

    names = ["acutecomb", "e", "o", "c", "x"]
    offsets = {"acutecomb": (-40, 0), "e": (39.4, 0), "o": (39, 0), "c": (39, 0)}
    text, tree = moved_features(FEA, names, offsets.get)
    assert text == move_feature_anchors(FEA, names, offsets.get)
    parsed = Parser(io.StringIO(text), glyphNames=set(names)).parse()
    assert tree.asFea() == parsed.asFea()
    unmoved = Parser(io.StringIO(FEA), glyphNames=set(names)).parse()
    assert unmoved.asFea() != parsed.asFea()   # the comparison can fail
    (tmp_path / "more.fea").write_text("languagesystem DFLT dflt;\n")
    included = "include(%s);\n%s" % (tmp_path / "more.fea", FEA)
    text, tree = moved_features(included, names, offsets.get)
    assert tree is None and "<anchor 38 555>" in text


# =========================================================================== plumbing

def test_nib_symmetry():
    assert nib_is_symmetric(nib())
    off_centre = translate_region(nib(), (5.0, 0.0))
    assert not nib_is_symmetric(off_centre)


def _line_glyph(font, name, lines=(), components=()):
    g = font.newGlyph(name)
    g.width = 600
    pen = g.getPen()
    for (x0, y0), (x1, y1) in lines:
        pen.moveTo((x0, y0))
        pen.lineTo((x1, y1))
        pen.endPath()
    for base, (dx, dy) in components:
        pen.addComponent(base, (1, 0, 0, 1, dx, dy))
    return g


def test_points_near_is_every_difference_in_every_direction():
    """_Separation._points_near (the nearest differences first, then each
    difference's nearest direction before all of them) answers as the plain test:
    some difference of the points in the disc lies within the reach in all the
    directions.  A thin nib; random point sets, the second one a bit too high
    above the first to be near, but for one point moved along the nib's length
    (farther than the nearest differences) to just within or just beyond the
    reach."""
    from morph.fonts.stroke import _projected, _Separation

    sep = _Separation(ufoLib2.Font(), None, ellipse_nib(200.0, 10.0, 0.0), 0.5)
    r = float(sep.reach.max())
    disc = (r / np.cos(np.pi / sep.DIRECTIONS)) ** 2 * (1.0 + 1e-9)
    up = sep.reach[sep.DIRECTIONS // 4]     # the reach upwards, along +y
    rng = np.random.default_rng(7)
    answers, late = [], 0
    for k in range(200):
        a = rng.uniform(-0.05, 0.05, (int(rng.integers(20, 60)), 2)) * [r, up]
        b = a[rng.integers(0, len(a), int(rng.integers(20, 60)))] + [0.0, 1.5 * up]
        b[0] = a[0] + [rng.uniform(0.8, 1.2) * sep.reach[0], 0.0]
        d = a[:, None, :] - b[None, :, :]
        d2 = d[..., 0] ** 2 + d[..., 1] ** 2
        i, j = np.nonzero(d2 <= disc)
        inside = np.all(_projected(a, sep.u)[i] - _projected(b, sep.u)[j] <= sep.reach, axis=1)
        nearest = np.argsort(d2[i, j], kind="stable")[:sep.NEAREST]
        late += bool(inside.any()) and not inside[nearest].any()
        box_a, box_b = (*a.min(axis=0), *a.max(axis=0)), (*b.min(axis=0), *b.max(axis=0))
        assert sep._points_near(a, box_a, b, box_b) == bool(inside.any()), k
        answers.append(bool(inside.any()))
    assert 30 < sum(answers) < 170 and late > 20


@pytest.mark.parametrize("gap", [1.0, 3.0])
def test_components_whose_strokes_meet_are_decomposed(tmp_path, gap):
    """A translated component is kept only where its stroke stays 2 (tol + rounding)
    away from the rest of the glyph's; nearer, the parts are stroked as one outline
    (kept, the written strokes would overlap).  ``gap`` times the nib's height apart:
    gap 1 the strokes just meet, gap 3 they are well apart."""
    n = nib()
    _, ny0, _, ny1 = region_extent(n)
    dy = gap * (ny1 - ny0)
    font = ufoLib2.Font()
    font.info.unitsPerEm = 1000
    _line_glyph(font, "bar", [((0, 0), (300, 0))])
    _line_glyph(font, "own", [((0, dy), (300, dy))], [("bar", (0, 0))])
    _line_glyph(font, "two", [], [("bar", (0, 0)), ("bar", (150, dy))])
    stroked, followed = stroke_plan(font, ["own", "two"], n)
    out = tmp_path / "parts.ufo"
    stats = stroke_ufo(font, out, n, ["own", "two"], tol=0.5)
    f = ufoLib2.Font.open(out)
    kept = gap > 2
    assert ("bar" in stroked) == kept
    assert stats["decomposed"] == (0 if kept else 3)
    for name in ("own", "two"):
        assert bool(f[name].components) == kept, name
    if not kept:  # one trimmed outline each
        assert len(f["own"].contours) == 1 and len(f["two"].contours) == 1


def test_font_plumbing_with_polygon_stroker(skeleton, tmp_path):
    """Metrics, components, anchors, features, kerning: independent of the geometry."""
    n = nib()
    out = tmp_path / "plumb.ufo"
    chosen = ["H", "eacute", "i", "nine", "ordfeminine"]
    stroked, followed = stroke_plan(skeleton, chosen, n)
    assert set(stroked) == set(chosen) | {"e", "acutecomb", "dotlessi", "uni0307", "six"}
    assert followed == []  # nothing else in the subset is built from those only
    stats = stroke_ufo(SUBSET, out, n, chosen, tol=0.5, stroker=polygon_stroker(0.25))
    assert stats["glyphs"] == len(stroked) and stats["decomposed"] == 1 and not stats["fallback"]
    f = ufoLib2.Font.open(out)
    x0, _, x1, _ = region_extent(n)
    grow = int(round(x1 - x0))
    for name in stroked:
        src, new = skeleton[name], f[name]
        assert new.width == (src.width + grow if src.width else 0), name
        s = shift_of(skeleton, name, n)
        for a, b in zip(src.anchors, new.anchors):
            assert (b.name, b.x, b.y) == (a.name, a.x + s, a.y), name
    # composites: kept (translation, 180-degree turn with a symmetric nib), offsets
    # corrected for the shifts; the scaled 'a' of ordfeminine decomposed and stroked
    assert [c.baseGlyph for c in f["eacute"].components] == ["e", "acutecomb"]
    assert [c.baseGlyph for c in f["nine"].components] == ["six"]
    assert not f["ordfeminine"].components and f["ordfeminine"].contours
    for name in ("eacute", "i", "nine"):
        for c_src, c_new in zip(skeleton[name].components, f[name].components):
            m = tuple(c_src.transformation)
            s_c, s_b = shift_of(skeleton, name, n), shift_of(skeleton, c_src.baseGlyph, n)
            assert tuple(c_new.transformation) == pytest.approx(
                (m[0], m[1], m[2], m[3], m[4] + s_c - m[0] * s_b, m[5] - m[1] * s_b))
    # mark attachment agrees with the composite, as in the source
    top = {a.name: (a.x, a.y) for a in f["e"].anchors}["top"]
    mark = {a.name: (a.x, a.y) for a in f["acutecomb"].anchors}["_top"]
    acute = tuple(f["eacute"].components[1].transformation)[4:]
    assert (top[0] - mark[0], top[1] - mark[1]) == acute
    # features: explicit anchors moved by the same rule, the rest untouched
    assert "markClass [acutecomb] <anchor %d 555> @mark_top;" % (78 + shift_of(skeleton, "acutecomb", n)) \
        in f.features.text
    assert "pos base e <anchor %d 555> mark @mark_top;" % (295 + shift_of(skeleton, "e", n)) \
        in f.features.text
    assert "sub g by g.ss01;" in f.features.text
    assert dict(f.kerning) == dict(skeleton.kerning)
    assert dict(f.groups) == dict(skeleton.groups)
    assert f.info.familyName == "Relief SingleLine Stroke"
    assert f.info.postscriptStemSnapH is None
    # glyphs not chosen are left empty in a UFO (so that it compiles), their
    # skeletons kept in the layer 'skeleton' ...
    assert not f["B"].contours and f["B"].width == skeleton["B"].width
    assert [[(p.x, p.y, p.type) for p in c.points] for c in f.layers["skeleton"]["B"].contours] \
        == [[(p.x, p.y, p.type) for p in c.points] for c in skeleton["B"].contours]
    # ... and in a compiled font
    stats = stroke_ufo(skeleton, tmp_path / "plumb.otf", n, ["H"], tol=0.5,
                       stroker=polygon_stroker(0.25))
    assert stats["emptied"] > 60
    font = TTFont(str(tmp_path / "plumb.otf"))
    gs = font.getGlyphSet()
    pen = BoundsPen(gs)
    gs["B"].draw(pen)
    assert pen.bounds is None
    assert font["hmtx"]["B"][0] == skeleton["B"].width
    with pytest.raises(MorphError, match="exists"):
        stroke_ufo(skeleton, tmp_path / "plumb.otf", n, ["H"], stroker=polygon_stroker(0.25))
    with pytest.raises(ValueError):
        stroke_ufo(skeleton, tmp_path / "plumb.pdf", n, ["H"])


# =========================================================================== geometry

# A: a counter closed by two different strokes (bar and legs), filled by an early
# stroke_paths; 4 likewise (in bench/stroke.py)
ACCURACY_GLYPHS = ["o", "e", "a", "eight", "g", "A", "s"]


@pytest.fixture(scope="module", params=[".otf", ".ttf"])
def stroked_font(tmp_path_factory, request):
    out = tmp_path_factory.mktemp("stroke") / ("Relief-Stroke" + request.param)
    stats = stroke_ufo(SUBSET, out, nib(), ACCURACY_GLYPHS + ["eacute", "i", "nine"], tol=0.5)
    return out, stats


@pytest.mark.parametrize("name", ACCURACY_GLYPHS)
def test_written_glyph_matches_reference(skeleton, stroked_font, name):
    """Hausdorff <= tol + 0.71 (integer rounding) + the reference's own flattening,
    and the counters (holes) of o, e, a, 8 kept, against the Clipper polygon; in
    the CFF and in the TrueType font (whose quadratic splines are converted before
    the one rounding: TrueType g was 1.38 units off when ufo2ft converted the
    rounded cubics and rounded again)."""
    out, stats = stroked_font
    assert not stats["fallback"]
    n = nib()
    got = region_to_shapely(glyph_region(name, font=str(out)).region, 0.05)
    ref = stroke_polygon(decomposed_paths(skeleton, name), n, REF_TOL)
    ref = shapely.affinity.translate(ref, shift_of(skeleton, name, n), 0.0)
    d = hausdorff(got, ref, 0.5)
    assert d <= 0.5 + ROUNDING + REF_TOL, (name, d)
    assert count_outer_and_holes(got, 1.0) == count_outer_and_holes(ref, 1.0)
    # each counter's area agrees within its perimeter times the distance bound
    bound = 0.5 + ROUNDING + REF_TOL
    for (a, _), (b, perimeter) in zip(holes(got), holes(ref)):
        assert abs(a - b) <= perimeter * bound, (name, a, b)


def holes(geom):
    """Sorted (area, perimeter) of the holes of a shapely (Multi)Polygon."""
    polys = getattr(geom, "geoms", [geom])
    return sorted((shapely.Polygon(r).area, shapely.Polygon(r).length)
                  for p in polys for r in p.interiors)


# =========================================================================== fonts

@pytest.mark.parametrize("suffix", [".otf", ".ttf"])
def test_compiled_font_loads_sanitizes_renders(skeleton, tmp_path, suffix):
    """ufo2ft output: fontTools reads it, ots-sanitize passes it, Pillow renders it
    at 9 to 300 px; TrueType keeps the composites."""
    import ots
    from PIL import Image, ImageDraw, ImageFont

    out = tmp_path / ("Relief-Stroke" + suffix)
    text = "Hoeaé8i9"
    stats = stroke_ufo(skeleton, out, nib(), list(text) + ["nine"], tol=0.5)
    assert not stats["fallback"]
    font = TTFont(str(out))
    assert ("glyf" in font) == (suffix == ".ttf") and ("CFF " in font) == (suffix == ".otf")
    if suffix == ".ttf":
        assert font["glyf"]["eacute"].isComposite() and font["glyf"]["nine"].isComposite()
    result = ots.sanitize(str(out), capture_output=True)
    assert result.returncode == 0, result.stderr.decode(errors="replace")
    for px in (9, 12, 16, 24, 48, 96, 300):
        fnt = ImageFont.truetype(str(out), px)
        left, top, right, bottom = fnt.getbbox(text)
        img = Image.new("L", (right - left + 4, bottom - top + 4), 255)
        ImageDraw.Draw(img).text((2 - left, 2 - top), text, font=fnt, fill=0)
        ink = np.asarray(img) < 128
        assert ink.mean() > 0.05, px  # glyphs drawn
        assert ink.mean() < 0.7, px   # not filled boxes
    # the stroke's thick/thin contrast survives: 'o' is wider than the skeleton + nib
    # height, narrower than the skeleton + nib width
    gs = font.getGlyphSet()
    pen = BoundsPen(gs)
    gs["o"].draw(pen)
    xmin, ymin, xmax, ymax = pen.bounds
    x0, y0, x1, y1 = region_extent(nib())
    assert xmax - xmin == pytest.approx(412 + (x1 - x0), abs=1.5)   # skeleton o: 90..502
    assert ymax - ymin == pytest.approx(555 + (y1 - y0), abs=1.5)   # 0..555


# =========================================================================== CLI

def test_cli_stroke_ufo(tmp_path):
    out = tmp_path / "R.otf"
    runner = CliRunner()
    res = runner.invoke(main, ["stroke", str(SUBSET), "-o", str(out), "--glyphs", "H,o"])
    assert res.exit_code == 0, res.output
    assert out.is_file() and out.with_name(out.name + ".png").is_file()
    assert "glyphs stroked" in res.output
    again = runner.invoke(main, ["stroke", str(SUBSET), "-o", str(out), "--glyphs", "H"])
    assert again.exit_code == 2 and "exists" in again.output
    ufo = tmp_path / "Round.ufo"
    res = runner.invoke(main, ["stroke", str(SUBSET), "-o", str(ufo), "--glyphs", "o",
                               "--nib", "ellipse:60,60,0", "--tol", "1e-3"])
    assert res.exit_code == 0, res.output
    f = ufoLib2.Font.open(ufo)
    assert f["o"].width == 592 + 60 and ufo.with_name(ufo.name + ".png").is_file()


@pytest.mark.parametrize("args, message", [
    (["-o", "x.pdf"], "cannot tell the output format"),
    (["-o", "x.otf", "--nib", "ellipse:a,b"], "--nib"),
    (["-o", "x.otf", "--glyphs", "Ω"], "no glyph"),
])
def test_cli_stroke_errors(tmp_path, args, message):
    args = [a if a != "x.pdf" and not a.startswith("x.") else str(tmp_path / a) for a in args]
    res = CliRunner().invoke(main, ["stroke", str(SUBSET)] + args)
    assert res.exit_code == 2, res.output
    assert message in res.output and res.output.count("\n") == 1


def test_cli_stroke_missing_skeleton(tmp_path):
    res = CliRunner().invoke(main, ["stroke", str(tmp_path / "none.ufo"), "-o",
                                    str(tmp_path / "x.otf")])
    assert res.exit_code == 2 and "does not exist" in res.output


SKELETON_SVG = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 120">
  <path d="M 20 100 C 40 10, 90 10, 100 60 S 160 110, 180 20" fill="none" stroke="black"/>
  <circle cx="60" cy="100" r="10" fill="none" stroke="black"/>
</svg>
"""


def test_cli_stroke_svg(tmp_path):
    """An SVG skeleton: the open path and the circle's outline stroked (the circle's
    inside stays empty), checked against the Clipper polygon of the same paths."""
    from morph.parse import svg_region
    from morph.parse.svg import svg_paths

    src = tmp_path / "skel.svg"
    src.write_text(SKELETON_SVG)
    out = tmp_path / "skel-stroke.svg"
    res = CliRunner().invoke(main, ["stroke", str(src), "-o", str(out), "--nib",
                                    "ellipse:16,4,30", "--tol", "0.01"])
    assert res.exit_code == 0, res.output
    got = region_to_shapely(svg_region(str(out)), 0.005)
    n = ellipse_nib(16, 4, 30)
    ref = stroke_polygon(svg_paths(str(src)), n, 0.005)
    # --tol covers the stroke and the SVG export together (as for `morph sum`)
    assert hausdorff(got, ref, 0.05) <= 0.01 + 0.005 + 0.005  # tol + reading + reference
    assert count_outer_and_holes(got, 0.1) == count_outer_and_holes(ref, 0.1) == (2, 1)
    png = tmp_path / "skel.png"
    res = CliRunner().invoke(main, ["stroke", str(src), "-o", str(png), "--size", "200"])
    assert res.exit_code == 0 and png.is_file()
    res = CliRunner().invoke(main, ["stroke", str(src), "-o", str(tmp_path / "x.otf")])
    assert res.exit_code == 2



PENCIL_SVG = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24" fill="none"
  stroke="currentColor" stroke-width="2"><path d="M17 3a2.828 2.828 0 1 1 4 4L7.5 20.5 2 22l1.5-5.5L17
  3z"/></svg>
"""


@pytest.mark.parametrize("angle", [0, 45, 129.2])
def test_cli_stroke_svg_of_one_closed_path_through_its_start(tmp_path, angle):
    """Feather's edit-2 icon: one closed path that runs on smoothly through its start
    (a semicircle, then lines back to it), the document's only path, so summed alone:
    stroked with its counter at every nib angle, against the Clipper polygon (it
    was refused, exit 2, 'loop 0 turns -8.48e-16 times', at every angle)."""
    from morph.parse import svg_region
    from morph.parse.svg import svg_paths

    src = tmp_path / "edit-2.svg"
    src.write_text(PENCIL_SVG)
    out = tmp_path / "pencil.svg"
    res = CliRunner().invoke(main, ["stroke", str(src), "-o", str(out), "--nib",
                                    "ellipse:3,1,%s" % angle, "--tol", "0.002"])
    assert res.exit_code == 0, res.output
    got = region_to_shapely(svg_region(str(out)), 0.001)
    ref = stroke_polygon(svg_paths(str(src)), ellipse_nib(3, 1, angle), 0.001)
    assert hausdorff(got, ref, 0.01) <= 0.002 + 0.001 + 0.001  # tol + reading + reference
    assert count_outer_and_holes(got, 0.01) == count_outer_and_holes(ref, 0.01) == (1, 1)

def test_chunk_strokes_glyph_by_glyph_where_the_packed_call_raises(skeleton, monkeypatch):
    """The chunk job strokes its glyphs together; where that raises, one by one, so
    the glyphs come out as if stroked alone (and only a failing one falls back)."""
    import morph.stroke
    from morph.budget import plan
    from morph.fonts.stroke import _stroked_regions
    from morph.stroke import stroke_paths

    tols, pen = plan(0.5), nib()
    chunk = [(n, decomposed_paths(skeleton, n), pen, tols, (0.0, 0.0), None)
             for n in ("o", "i", "H")]
    together = _stroked_regions(chunk)

    real = morph.stroke.stroke_many

    def broken(path_sets, *args):
        if len(path_sets) > 1:                      # the packed call, not stroke_paths
            raise MorphError("packed call failed (test)")
        return real(path_sets, *args)

    monkeypatch.setattr(morph.stroke, "stroke_many", broken)
    alone = _stroked_regions(chunk)
    for (n, paths, *_), (r1, e1, _), (r2, e2, _) in zip(chunk, together, alone):
        assert e1 is None and e2 is None
        assert len(r1) == len(r2)
        exact = stroke_paths(paths, pen, tols[0])
        assert all(np.array_equal(p, q) for l, m in zip(r2, exact) for p, q in zip(l, m))
        a1 = region_to_shapely(r1, 0.05)
        a2 = region_to_shapely(r2, 0.05)
        assert hausdorff(a1.boundary, a2.boundary) <= 2 * tols[0]


@pytest.mark.parametrize("suffix", [".otf", ".ttf"])
def test_written_ink_and_cmap_are_the_fonts(tmp_path, suffix):
    """The ink and character map the writer reports (for the sample and specimen,
    which then do not read the font) are those of the written font read back:
    composites (kept components, one of them nested) draw what their bases draw,
    glyphs not chosen draw nothing, the names are the production names."""
    import plistlib
    import shutil

    from morph.fonts.specimen import _ink_test
    from morph.fonts.stream import SkeletonSource

    src = tmp_path / "src.ufo"
    shutil.copytree(SUBSET, src)
    lib = plistlib.loads((src / "lib.plist").read_bytes())
    lib["public.postscriptNames"] = {"eacute": "e_acute", "A": "A.prod"}
    (src / "lib.plist").write_bytes(plistlib.dumps(lib))
    chosen = ["H", "eacute", "i", "nine", "ordfeminine", "A", "space"]
    out = tmp_path / ("ink" + suffix)
    stats = stroke_ufo(SkeletonSource(src, light=True), out, nib(), chosen, tol=0.5,
                       stroker=polygon_stroker(0.25))   # read light, as the command reads it
    assert stats["composites"] > 0
    cmap, has_ink = _ink_test(TTFont(str(out)))
    assert stats["cmap"] == cmap
    source_names = {u: g.name for g in stats["font"] for u in g.unicodes}
    assert cmap[ord("A")] == "A.prod" and cmap[ord("é")] == "e_acute"   # production names
    inked = {u for u, name in cmap.items() if has_ink(name)}
    assert {u for u in cmap if source_names[u] in stats["inked"]} == inked
    assert {ord(c) for c in "Héi9ªA"} <= inked and ord(" ") not in inked
