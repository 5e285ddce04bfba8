"""morph.fonts.variable_brush: brushed variable fonts from static, variable glyf/gvar
and CFF2 sources, with and without a nib axis, end to end.

Small sources with mark positioning are built from the bundled Noto Sans
(tests/fonts/varsources.py).  Every brushed font is instanced by fontTools'
instancer at 9 positions per axis (the others at their defaults) and at random
points, and each instance's glyphs are compared with the exact sum at that
location (the source instanced by its own interpolation, ⊕ the nib the axis
defines there, by Clipper: tests/oracles/varfont.py).  Mark anchors are checked to
move with the outlines at every position."""

import logging

import numpy as np
import pytest

from morph.compatible import Ellipse
from morph.fonts.variable import BLEND_SHARE
from morph.fonts.variable_brush import brush_variable, grade_axis
from tests.fonts.varsources import (mark_anchor, mark_font, source_instance, to_cff,
                                    variable_mark_font)
from tests.oracles.varfont import clipper_region_sum, glyph_polygons, within

TOL = 0.5
ROUND = 0.5 * 2 ** 0.5      # one integer rounding of a point
SLACK = 0.05                # flattening and Clipper's integer grid in the reference
BOUND = TOL + 2 * ROUND + SLACK
#: the pinhole a swallowtail's cusp opens when the two roundings (a master's and an
#: instance's) move it: a loop at most 2 x 0.71 units across, so <= 2 unit²
PINHOLE = (2 * ROUND) ** 2
#: an anchor: rounded at every master (0.5, and so between them) and rounded again
#: by the instancer (0.5)
ANCHOR = 1.0
NIBS = ((40, 10, 30), (120, 30, 30))
GLYPHS = ("o", "e", "acutecomb")


@pytest.fixture(scope="module")
def sources(tmp_path_factory):
    from fontTools.ttLib import TTFont

    for name in ("fontTools", "ufo2ft"):
        logging.getLogger(name).setLevel(logging.ERROR)
    d = tmp_path_factory.mktemp("vbsrc")
    static = mark_font(d)
    otf = d / "Mark.otf"
    to_cff(TTFont(str(static))).save(str(otf))
    return {"ttf": static, "otf": otf, "var": variable_mark_font(d),
            "cff2": variable_mark_font(d, cff2=True),
            "tall": variable_mark_font(d, scale=(1.0, 2.0)),
            "big": variable_mark_font(d, scale=(1.25, 1.25)),
            "tall_o": variable_mark_font(d, scale=(1.25, 2.5), only=("o",))}


def _instance(path, loc):
    from fontTools.ttLib import TTFont
    from fontTools.varLib import instancer

    return instancer.instantiateVariableFont(TTFont(str(path)), loc)


def _shift(nib, width):
    """The outlines' shift: right by the nib's left extent; a zero-width mark left."""
    hx = nib.extent()[2]
    return hx if width else -hx


def _within(out, src, loc, nib_of, glyphs):
    """Is every glyph of the instance of ``out`` at ``loc`` within BOUND of the
    source's instance ⊕ the nib there?"""
    inst = _instance(out, loc)
    source = source_instance(src, {t: v for t, v in loc.items() if t != "NIBW"})
    gs, sgs, nib = inst.getGlyphSet(), source.getGlyphSet(), nib_of(loc)
    return all(within(glyph_polygons(gs, name),
                      [p + np.array([_shift(nib, sgs[name].width), 0.0])
                       for p in clipper_region_sum(glyph_polygons(sgs, name), tuple(nib))],
                      BOUND, strict=True, area=PINHOLE) for name in glyphs)


def _check(out, src, loc, nib_of, shift_nib_of=None, glyphs=GLYPHS):
    """Every glyph of the instance of ``out`` at ``loc`` within BOUND of the source's
    instance ⊕ the nib there; the mark offset on e moved by the outlines' shifts."""
    inst = _instance(out, loc)
    src_loc = {t: v for t, v in loc.items() if t not in ("NIBW", "NIBP", "GRAD")}
    source = source_instance(src, src_loc)
    nib = nib_of(loc)
    shift_nib = (shift_nib_of or nib_of)(loc)
    gs, sgs = inst.getGlyphSet(), source.getGlyphSet()
    for name in glyphs:
        ref = [p + np.array([_shift(shift_nib, sgs[name].width), 0.0])
               for p in clipper_region_sum(glyph_polygons(sgs, name), tuple(nib))]
        assert within(glyph_polygons(gs, name), ref, BOUND, strict=True, area=PINHOLE), \
            (loc, name)
    # each anchor within ANCHOR of the source's moved by its glyph's shift
    for a0, a1, width in zip(mark_anchor(source, "e"), mark_anchor(inst, "e"), (1, 0)):
        want = a0[0] + _shift(shift_nib, width)
        assert abs(a1[0] - want) <= ANCHOR and a1[1] == a0[1], (loc, a0, a1, want)
    return inst


def _nibw(loc):
    w = loc.get("NIBW", 40.0)
    return Ellipse(w, w / 4.0, 30.0)


def test_static_source_gets_a_nib_axis(sources, tmp_path):
    """A static TrueType font with --vary-nib: one NIBW axis, two masters (a uniform
    scale needs no intermediate one), every position within the bound, anchors moved
    with the outlines at every position (they vary along the axis)."""
    from fontTools.ttLib import TTFont

    out = tmp_path / "StaticNib.ttf"
    stats = brush_variable(sources["ttf"], out, NIBS[0], nib_max=NIBS[1], tol=TOL)
    assert stats["nib_values"] == [40.0, 120.0] and len(stats["masters"]) == 2
    font = TTFont(str(out))
    assert [a.axisTag for a in font["fvar"].axes] == ["NIBW"]
    assert "STAT" in font and "gvar" in font and font["glyf"]["o"].flags[0] & 0x40
    import ots  # a test extra: missing, the test fails rather than skips
    assert ots.sanitize(str(out), capture_output=True).returncode == 0
    rng = np.random.default_rng(35)
    for w in list(np.linspace(40, 120, 9)) + list(rng.uniform(40, 120, 2)):
        _check(out, sources["ttf"], {"NIBW": float(w)}, _nibw)
    # the check can fail: the instance at 80 against the sum with a nib 4 bounds wider
    inst = _instance(out, {"NIBW": 80.0})
    sgs = TTFont(str(sources["ttf"])).getGlyphSet()
    ref = clipper_region_sum(glyph_polygons(sgs, "o"), (80 + 4 * BOUND, 20, 30))
    assert not within(glyph_polygons(inst.getGlyphSet(), "o"),
                      [p + np.array([35.0, 0.0]) for p in ref], BOUND, strict=True)


def test_turning_nib_gets_intermediate_masters(sources, tmp_path):
    """A nib that turns (NIBP): intermediate nib masters until each interval's blend
    is within its share, and 9 positions within the bound; the many masters' glyph
    deltas are rounded against each other, so each master is its own rounded
    outline (rounding exact deltas afterwards adds one rounding per region)."""
    from morph.compatible import interpolation_error

    out = tmp_path / "Turn.ttf"
    stats = brush_variable(sources["ttf"], out, (80, 20, 0), nib_max=(80, 20, 40),
                           glyphs=["n", "e", "acutecomb"], tol=TOL)
    axis, values = stats["axis"], stats["nib_values"]
    assert axis.tag == "NIBP" and len(values) > 8
    assert all(interpolation_error(axis.nib_at(a), axis.nib_at(b)) <= BLEND_SHARE * TOL
               for a, b in zip(values[:-1], values[1:]))
    for v in np.linspace(0, 100, 9):
        _check(out, sources["ttf"], {"NIBP": float(v)}, lambda loc: axis.nib_at(loc["NIBP"]),
               glyphs=("n",))


def test_grade_axis_keeps_the_advances(sources, tmp_path):
    """Two growing disks on a static CFF font: the registered GRAD axis (0 to the
    diameter's growth per 1000 em), TrueType output, advances and anchors those of
    the default disk at every position, outlines within the bound of glyph ⊕ disk."""
    from fontTools.ttLib import TTFont

    assert grade_axis((20, 20, 0), (50, 50, 0), 1000).maximum == 30.0
    assert grade_axis((20, 10, 0), (50, 50, 0), 1000) is None
    out = tmp_path / "Grade.ttf"
    stats = brush_variable(sources["otf"], out, (20, 20, 0), nib_max=(50, 50, 0), tol=TOL)
    assert stats["axis"].tag == "GRAD" and len(stats["masters"]) == 2
    font = TTFont(str(out))
    assert "glyf" in font and "CFF " not in font
    axis = font["fvar"].axes[0]
    assert (axis.axisTag, axis.minValue, axis.defaultValue, axis.maxValue) == \
        ("GRAD", 0.0, 0.0, 30.0)
    import ots  # a test extra: missing, the test fails rather than skips
    assert ots.sanitize(str(out), capture_output=True).returncode == 0
    widths = None
    for g in np.linspace(0, 30, 9):
        inst = _check(out, sources["otf"], {"GRAD": float(g)},
                      lambda loc: Ellipse(20 + loc["GRAD"], 20 + loc["GRAD"], 0),
                      lambda loc: Ellipse(20, 20, 0))
        w = [inst["hmtx"][n][0] for n in inst.getGlyphOrder()]
        assert widths is None or w == widths
        widths = w


def test_variable_cff2_source_keeps_its_axis(sources, tmp_path):
    """A CFF2 variable font, read through fontTools at each master location: its wght
    axis kept (TrueType output), 9 positions within the bound, anchors moved."""
    from fontTools.ttLib import TTFont

    out = tmp_path / "Cff2Brush.ttf"
    stats = brush_variable(sources["cff2"], out, NIBS[0], tol=TOL)
    rep = stats["refinement"]
    assert rep["given"] == 2 and rep["error"] <= BLEND_SHARE * TOL
    assert len(stats["source_masters"]) == 2 + rep["added"]
    font = TTFont(str(out))
    assert [a.axisTag for a in font["fvar"].axes] == ["wght"]
    assert "glyf" in font and "gvar" in font and "CFF2" not in font
    import ots  # a test extra: missing, the test fails rather than skips
    assert ots.sanitize(str(out), capture_output=True).returncode == 0
    for w in np.linspace(400, 700, 9):
        _check(out, sources["cff2"], {"wght": float(w)}, lambda loc: Ellipse(*NIBS[0]))


@pytest.mark.parametrize("kind", ["var", "cff2"])
def test_variable_source_gets_a_nib_axis(sources, tmp_path, kind):
    """A variable source (glyf/gvar, CFF2) with --vary-nib: wght kept, NIBW after it;
    9 positions along each axis and random points of the plane within the bound,
    anchors (varying with wght in the source) moved with the outlines everywhere."""
    from fontTools.ttLib import TTFont

    out = tmp_path / ("Nib%s.ttf" % kind)
    stats = brush_variable(sources[kind], out, NIBS[0], nib_max=NIBS[1], tol=TOL)
    rep = stats["refinement"]      # the wide nib's part turns with the wider master
    assert rep["added"] > 0 and rep["error"] <= BLEND_SHARE * TOL
    assert len(stats["masters"]) == (2 + rep["added"]) * 2
    font = TTFont(str(out))
    assert [a.axisTag for a in font["fvar"].axes] == ["wght", "NIBW"]
    assert [i.coordinates for i in font["fvar"].instances] == [] or \
        all(i.coordinates["NIBW"] == 40 for i in font["fvar"].instances)
    rng = np.random.default_rng(7)
    spots = [{"wght": float(w), "NIBW": 40.0} for w in np.linspace(400, 700, 9)] + \
        [{"wght": 400.0, "NIBW": float(v)} for v in np.linspace(40, 120, 9)] + \
        [{"wght": float(rng.uniform(400, 700)), "NIBW": float(rng.uniform(40, 120))}
         for _ in range(3)]
    for k, loc in enumerate(spots):
        _check(out, sources[kind], loc, _nibw, glyphs=GLYPHS[k % 3:k % 3 + 1] + ("acutecomb",))


def test_source_masters_added_until_the_bound_holds(sources, tmp_path):
    """A variable source whose wght master is twice as tall turns the outlines'
    normals: brushed with its two masters only, an instance between them misses the
    exact sum by more than the bound (the nib points of turned normals do not blend
    linearly); so intermediate source masters are added until the measured blend is
    within its share, and then 9 positions and random ones are within the bound."""
    nib, glyphs = (80, 20, 30), ("o", "e", "n")
    out = tmp_path / "Tall.ttf"
    stats = brush_variable(sources["tall"], out, nib, glyphs=list(glyphs), tol=TOL)
    rep = stats["refinement"]
    assert rep["errors_before"]["wght"] > BOUND and rep["given"] == 2
    assert rep["added"] > 0 and rep["error"] <= BLEND_SHARE * TOL
    assert len(stats["masters"]) == 2 + rep["added"]
    rng = np.random.default_rng(37)
    spots = list(np.linspace(400, 700, 9)) + list(rng.uniform(400, 700, 2))
    for w in spots:
        assert _within(out, sources["tall"], {"wght": float(w)}, lambda loc: Ellipse(*nib),
                       glyphs), w
    coarse = tmp_path / "TallCoarse.ttf"
    stats = brush_variable(sources["tall"], coarse, nib, glyphs=list(glyphs), tol=TOL,
                           refine=False)
    assert len(stats["masters"]) == 2
    assert not all(_within(coarse, sources["tall"], {"wght": float(w)},
                           lambda loc: Ellipse(*nib), glyphs) for w in spots)


def test_each_glyph_gets_its_own_source_masters(sources, tmp_path):
    """A variable source whose wght master makes o twice as tall as wide and scales e
    and n uniformly: o gets intermediate source masters, e and n keep the source's
    two (each glyph's variations over its own masters: one gvar tuple over the whole
    wght tent, not the tents of o's grid), and 9 positions and random ones are
    within the bound for all three."""
    from fontTools.ttLib import TTFont

    nib, glyphs = (80, 20, 30), ("o", "e", "n")
    out = tmp_path / "TallO.ttf"
    stats = brush_variable(sources["tall_o"], out, nib, glyphs=list(glyphs), tol=TOL)
    rep, masters = stats["refinement"], stats["glyph_masters"]
    assert rep["hardest"] == "o" and masters["o"] == rep["most"] == 2 + rep["added"] > 2
    assert masters["e"] == masters["n"] == 2 and rep["refined"] == 1
    gvar = TTFont(str(out))["gvar"].variations
    assert [v.axes for v in gvar["e"]] == [{"wght": (0.0, 1.0, 1.0)}]
    assert len(gvar["o"]) == masters["o"] - 1
    rng = np.random.default_rng(39)
    for w in list(np.linspace(400, 700, 9)) + list(rng.uniform(400, 700, 2)):
        assert _within(out, sources["tall_o"], {"wght": float(w)}, lambda loc: Ellipse(*nib),
                       glyphs), w


def test_no_source_master_where_the_blend_holds(sources, tmp_path):
    """A variable source whose wght master is the Regular one scaled uniformly keeps
    the normals (up to the integer rounding of its points): its two masters blend
    within the share, no master is added, and 9 positions are within the bound."""
    nib = (80, 20, 30)
    out = tmp_path / "Big.ttf"
    stats = brush_variable(sources["big"], out, nib, tol=TOL)
    rep = stats["refinement"]
    assert rep["added"] == 0 and rep["error"] <= BLEND_SHARE * TOL
    assert len(stats["masters"]) == 2
    for w in np.linspace(400, 700, 9):
        assert _within(out, sources["big"], {"wght": float(w)}, lambda loc: Ellipse(*nib),
                       ("o", "e", "n", "acutecomb")), w


def test_cff2_output(sources, tmp_path):
    """``.otf``: the same masters as CFF2 (blended charstrings, HVAR): ots passes;
    fontTools' instances at 9 positions per axis and random ones within the bound of
    the exact sum, and within the roundings and the quadratic conversion of the
    .ttf's instance there; anchors as the .ttf's, advances within a rounding."""
    from fontTools.ttLib import TTFont

    out, ttf = tmp_path / "Nib.otf", tmp_path / "Nib.ttf"
    stats = brush_variable(sources["var"], out, NIBS[0], nib_max=NIBS[1], tol=TOL)
    brush_variable(sources["var"], ttf, NIBS[0], nib_max=NIBS[1], tol=TOL)
    font = TTFont(str(out))
    assert "CFF2" in font and "HVAR" in font and "glyf" not in font
    assert [a.axisTag for a in font["fvar"].axes] == ["wght", "NIBW"]
    # one VarData per glyph's own set of masters: its regions those of its masters
    store = font["CFF2"].cff.topDictIndex[0].VarStore.otVarStore
    assert {len(d.VarRegionIndex) + 1 for d in store.VarData} >= \
        set(stats["glyph_masters"].values())
    assert max(stats["glyph_masters"].values()) == len(stats["masters"])
    import ots  # a test extra: missing, the test fails rather than skips
    r = ots.sanitize(str(out), capture_output=True)
    assert r.returncode == 0, r.stderr
    rng = np.random.default_rng(38)
    spots = [{"wght": float(w), "NIBW": 40.0} for w in np.linspace(400, 700, 9)] + \
        [{"wght": 400.0, "NIBW": float(v)} for v in np.linspace(40, 120, 9)] + \
        [{"wght": float(rng.uniform(400, 700)), "NIBW": float(rng.uniform(40, 120))}
         for _ in range(2)]
    for k, loc in enumerate(spots):
        inst = _check(out, sources["var"], loc, _nibw, glyphs=GLYPHS[k % 3:k % 3 + 1])
        other = _instance(ttf, loc)
        # the same interpolated advance, rounded by HVAR's instancer and by gvar's
        # phantom points: a tie may go either way
        assert all(abs(inst["hmtx"][n][0] - other["hmtx"][n][0]) <= 1 for n in GLYPHS)
        assert mark_anchor(inst, "e") == mark_anchor(other, "e")
        for name in GLYPHS[k % 3:k % 3 + 1]:
            a, b = glyph_polygons(inst.getGlyphSet(), name), \
                glyph_polygons(other.getGlyphSet(), name)
            assert within(a, b, 2 * ROUND + TOL * 0.2 + SLACK, area=PINHOLE), (loc, name)
    # the comparison can fail: against the .ttf's neighbour position
    far = _instance(ttf, {"wght": 400.0, "NIBW": 50.0})
    near = _instance(out, {"wght": 400.0, "NIBW": 40.0})
    assert not within(glyph_polygons(near.getGlyphSet(), "o"),
                      glyph_polygons(far.getGlyphSet(), "o"), 2 * ROUND + SLACK)


def test_brush_vary_nib_cli(sources, tmp_path, runner):
    from fontTools.ttLib import TTFont

    from morph.cli import main

    out = tmp_path / "Cli.ttf"
    r = runner.invoke(main, ["brush", str(sources["otf"]), "-o", str(out), "--nib",
                             "ellipse:20,20", "--vary-nib", "ellipse:50,50", "--jobs", "1"])
    assert r.exit_code == 0, r.output
    assert "GRAD 0..30" in r.output
    r = runner.invoke(main, ["brush", str(sources["var"]), "-o", str(tmp_path / "Cli.otf"),
                             "--nib", "ellipse:40,10,30", "--glyphs", "o", "--jobs", "1"])
    assert r.exit_code == 0, r.output
    assert "CFF2" in TTFont(str(tmp_path / "Cli.otf"))
    assert [a.axisTag for a in TTFont(str(out))["fvar"].axes] == ["GRAD"]
    for args, message in (
            (["-o", str(tmp_path / "y.ttf"), "--vary-nib", "ellipse:80,30,30"], "two nibs"),
            (["-o", str(tmp_path / "z.ttf"), "--vary-nib", "circle"], "--vary-nib")):
        r = runner.invoke(main, ["brush", str(sources["otf"]), *args])
        assert r.exit_code == 2 and message in r.output, r.output
        assert len(r.output.strip().splitlines()) == 1


def test_variable_sample_image_shows_axis_positions(sources, tmp_path):
    """The sample PNG of a variable font has one line per position of
    sample_locations (the nib axis' minimum, middle, maximum), each matching Pillow's
    rendering of fontTools' instancer instance there (within 2 px), and the lines
    differ."""
    import io

    from fontTools.ttLib import TTFont
    from PIL import Image, ImageDraw, ImageFont

    from morph.fonts.specimen import SAMPLE_PX, sample_locations, write_sample_image
    from tests.fonts.test_variable import _near

    out = tmp_path / "Sample.ttf"
    brush_variable(sources["ttf"], out, NIBS[0], nib_max=NIBS[1], tol=TOL)
    spots = sample_locations(out.read_bytes())
    assert [name for name, _ in spots] == ["NIBW 40", "NIBW 80", "NIBW 120"]
    img = write_sample_image(out, "oeo", tmp_path / "s.png")
    ink = np.asarray(img.convert("L")) < 90          # the labels are grey (110)
    rows = np.flatnonzero(ink.any(axis=1))
    bands = np.split(rows, np.flatnonzero(np.diff(rows) > 1) + 1)
    assert len(bands) == 3
    lines = []
    for band in bands:
        part = ink[band[0]:band[-1] + 1]
        xs = np.flatnonzero(part.any(axis=0))
        lines.append(part[:, xs[0]:xs[-1] + 1])
    for k, (_, values) in enumerate(spots):
        inst = _instance(out, {"NIBW": values[0]})
        data = io.BytesIO()
        inst.save(data)
        fnt = ImageFont.truetype(io.BytesIO(data.getvalue()), SAMPLE_PX)
        ref = Image.new("L", (SAMPLE_PX * 4, SAMPLE_PX * 2), 255)
        ImageDraw.Draw(ref).text((SAMPLE_PX // 2, SAMPLE_PX // 2), "oeo", font=fnt, fill=0)
        a = np.asarray(ref) < 90
        ys, xs = np.nonzero(a)
        a = a[ys.min():ys.max() + 1, xs.min():xs.max() + 1]
        assert _near(lines[k], a) >= 0.97, k
        assert abs(lines[k].shape[1] - a.shape[1]) <= 2
    assert lines[0].shape[1] + 10 < lines[2].shape[1]        # the nib grows
    assert "fvar" not in TTFont(str(sources["ttf"]))          # a static font: one line
    assert sample_locations(sources["ttf"].read_bytes()) is None


@pytest.mark.slow
@pytest.mark.parametrize("suffix", [".ttf", ".otf"])
def test_fontbakery_adds_no_fail(sources, tmp_path, suffix):
    """check-universal on the variable source brushed with a nib axis (.ttf glyf/gvar,
    .otf CFF2) has no FAIL the source lacks but the one fontbakery gives the
    registered-axes check of a private nib axis' Regular instance."""
    pytest.importorskip("fontbakery")
    from tests.fonts.test_brush import _fontbakery
    from tests.fonts.test_variable import PRIVATE_AXES_ONLY

    out = tmp_path / ("FB" + suffix)
    brush_variable(sources["var"], out, NIBS[0], nib_max=NIBS[1], tol=TOL)
    fails = {k for k in _fontbakery(out) - _fontbakery(sources["var"]) if k[1] != "WARN"}
    assert fails <= PRIVATE_AXES_ONLY, sorted(fails)

