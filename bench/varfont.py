"""Variable calligraphic fonts (morph.fonts.variable): cost, size, instance error, and
whether FontForge's Expand Stroke gives interpolation-compatible masters.

    python -m bench.varfont [--part all|stroke|brush|serif] [--skeleton UFO|none] [--subset UFO]
                            [--out bench/varfont.md]
                            [--positions 9] [--random 3] [--jobs 1] [--no-fontforge]
                            [--glyphs a,s,period] [--measure a,s,period]

1. The whole Relief skeleton stroked into a variable font with a nib axis from
   ellipse 40 x 10 at 30 degrees to 120 x 30 (a uniform scale: two masters): CPU
   seconds of the compatible fit per glyph per master (process_time, this machine is
   shared), the variable TTF / OTF sizes.
2. The Relief subset: the variable TTF against the two static (trimmed) fonts at the
   axis' ends, sizes and CPU time; every glyph of the variable font instanced by
   fontTools.varLib.instancer at ``--positions`` positions and ``--random`` random
   ones, each compared with the exact sum (Clipper on finely flattened inputs,
   tests/oracles/varfont.py): the largest distance (the symmetric difference
   within d of the exact boundary, pinholes under 1 unit² aside, and then the
   pinholes counted).
3. Masters a nib axis needs (intermediate ones for aspect or angle changes).
4. FontForge's Expand Stroke (Debian python3-fontforge, bench/fontforge_stroke.py)
   at the two nibs: glyphs whose two results have the same contours and segment
   types (what varLib needs), and whether varLib builds from them.
5. Skeleton designspaces (the subset's glyphs slanted and widened in a second
   master, tests/oracles/varfont.py): the blend error estimate between the given
   masters, the intermediate skeleton masters added, and the measured instance
   error (instancer against Clipper) of the font with and without them.
6. Brushed variable fonts from small mark fonts (tests/fonts/varsources.py): static
   TrueType / CFF sources with a nib axis (NIBW, GRAD, NIBP), variable glyf/gvar and
   CFF2 sources with and without one, written as .ttf and .otf (CFF2), with the
   intermediate source masters and without them: masters, the blend before and
   after, size, CPU time, the measured instance error at 9 positions per axis and
   random points, and the mark anchors' largest error.
7. Source Serif 4's variable font cut to o and e, brushed keeping its axes (each
   glyph its own source masters): masters per glyph, CPU time, size, ots, the
   CFF2 charstrings (a glyph's blended program past 65,535 bytes split into
   subroutines), and the measured instance error at 9 positions per axis and random
   points.  ``--part serif`` remakes this section alone in the existing report.

Writes a Markdown report stamped with the command, commit and date it was made at
(:func:`bench.stamp.stamp`); ``python -m bench.reports --only varfont`` remakes it.
"""

import argparse
import json
import logging
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from morph.fonts.variable import axis_masters, nib_axis, stroke_variable  # noqa: E402
from tests.oracles.varfont import (clipper_stroke, glyph_polygons, pinholes,  # noqa: E402
                                     skeleton_polylines, sum_distance)

SYSTEM_PYTHON = "/usr/bin/python3"
NIB_MIN, NIB_MAX = (40.0, 10.0, 30.0), (120.0, 30.0, 30.0)
TOL = 0.5


def instance_glyphs(vf, loc):
    """The glyph set of a variable font's instance at a user location: fontTools'
    instancer for glyf/gvar; for CFF2 fontTools' own blend evaluation at the location
    (HarfBuzz matches it; the instancer's static CFF of a glyph with many blends can
    differ from both by many units)."""
    from fontTools.varLib import instancer

    if "CFF2" in vf:
        return vf.getGlyphSet(location=loc)
    return instancer.instantiateVariableFont(vf, loc).getGlyphSet()


def whole_font(skeleton, folder, jobs):
    rows = {}
    for suffix in (".ttf", ".otf"):
        out = folder / ("ReliefNib" + suffix)
        c0 = time.process_time()
        st = stroke_variable(skeleton, out, NIB_MIN, NIB_MAX, tol=TOL, overwrite=True,
                             jobs=jobs)
        rows[suffix] = {"glyphs": st["glyphs"], "masters": len(st["masters"]),
                        "fit": st["fit_seconds"], "cpu": time.process_time() - c0,
                        "size": out.stat().st_size, "points": st["points"]}
    return rows


def static_fonts(subset, folder, glyphs):
    from morph.fonts.brush import ellipse_nib
    from morph.fonts.stroke import stroke_ufo

    rows = []
    for nib in (NIB_MIN, NIB_MAX):
        out = folder / ("Static%d.ttf" % nib[0])
        c0 = time.process_time()
        stroke_ufo(str(subset), out, ellipse_nib(*nib), glyphs=glyphs, tol=TOL,
                   overwrite=True, jobs=1)
        rows.append({"nib": nib, "size": out.stat().st_size,
                     "cpu": time.process_time() - c0})
    return rows


def instance_errors(subset, font_path, positions, randoms, glyphs):
    from fontTools.ttLib import TTFont
    from fontTools.varLib import instancer

    from morph.parse.ufo import decomposed_paths, load_ufo

    sk = load_ufo(subset, lazy=False)
    vf = TTFont(str(font_path))
    axis = nib_axis(NIB_MIN, NIB_MAX)
    values = [axis.minimum, axis.maximum]
    rng = np.random.default_rng(35)
    spots = list(np.linspace(axis.minimum, axis.maximum, positions)) + \
        list(rng.uniform(axis.minimum, axis.maximum, randoms))
    names = [n for n in vf.getGlyphOrder() if n in sk and decomposed_paths(sk, n) and
             (glyphs is None or n in glyphs)]
    rows = []
    for v in spots:
        glyphs = instancer.instantiateVariableFont(vf, {axis.tag: float(v)}).getGlyphSet()
        nib = axis.nib_at(v)
        hx = float(np.interp(v, values, [axis.nib_at(x).extent()[2] for x in values]))
        grow = float(np.interp(v, values, [round(2 * axis.nib_at(x).extent()[2])
                                           for x in values]))
        worst, holes = (0.0, ""), []
        for n in names:
            shift = hx - (grow if sk[n].width == 0 else 0.0)
            ref = [p + np.array([shift, 0.0])
                   for p in clipper_stroke(skeleton_polylines(decomposed_paths(sk, n)),
                                           tuple(nib))]
            filled = glyph_polygons(glyphs, n)
            d = sum_distance(filled, ref, strict=True)
            worst = max(worst, (d, n))
            holes += [a for a in pinholes(filled, ref) if a > 1e-3]
        rows.append({"value": float(v), "max": worst[0], "glyph": worst[1],
                     "pinholes": len(holes), "largest_pinhole": max(holes, default=0.0)})
    return rows, len(names)


def masters_needed():
    cases = [(NIB_MIN, NIB_MAX), ((40, 10, 30), (120, 20, 30)), ((40, 10, 30), (120, 30, 45)),
             ((60, 60, 0), (90, 20, 30)), ((80, 20, 0), (80, 20, 60))]
    return [(a, b, nib_axis(a, b).tag, len(axis_masters(nib_axis(a, b), 0.4 * TOL)))
            for a, b in cases]


def fontforge_compat(subset, only):
    """(glyphs compared, glyphs with equal structure at both nibs, varLib result)."""
    from morph import piece as pc
    from morph.parse.ufo import decomposed_paths, load_ufo

    if not os.path.exists(SYSTEM_PYTHON):
        return None
    sk = load_ufo(subset, lazy=False)
    glyphs = {n: [[[pc.cartesian(p).tolist() for p in pieces], closed]
                  for pieces, closed in decomposed_paths(sk, n)]
              for n in sk.keys() if decomposed_paths(sk, n) and (only is None or n in only)}
    results = []
    for nib in (NIB_MIN, NIB_MAX):
        job = json.dumps({"nib": ["elliptical", *nib], "accuracy": 0.25, "glyphs": glyphs})
        proc = subprocess.run([SYSTEM_PYTHON, str(ROOT / "bench" / "fontforge_stroke.py")],
                              input=job, capture_output=True, text=True)
        if proc.returncode != 0:
            return {"error": (proc.stderr.strip().splitlines() or ["?"])[-1]}
        results.append(json.loads(proc.stdout))

    def structure(contours):
        return [[len(s) for s in c] for c in contours]

    same = [n for n in glyphs if structure(results[0][n]["contours"]) ==
            structure(results[1][n]["contours"])]
    contours_differ = [n for n in glyphs if len(results[0][n]["contours"]) !=
                       len(results[1][n]["contours"])]
    return {"glyphs": len(glyphs), "same": len(same), "contours_differ": len(contours_differ),
            "varlib": _varlib_build(results, sk)}


def _varlib_build(results, sk):
    """Try ufo2ft.compileVariableTTF on FontForge's two masters: the error, or 'builds'."""
    import ufo2ft
    import ufoLib2
    from fontTools.designspaceLib import AxisDescriptor, DesignSpaceDocument, SourceDescriptor

    doc = DesignSpaceDocument()
    ax = AxisDescriptor()
    ax.tag, ax.name, ax.minimum, ax.default, ax.maximum = "NIBW", "Nib", 40, 40, 120
    doc.addAxis(ax)
    for res, v in zip(results, (40, 120)):
        f = ufoLib2.Font()
        f.info.unitsPerEm, f.info.familyName, f.info.styleName = 1000, "FF", "N%d" % v
        for n, r in res.items():
            g = f.newGlyph(n)
            g.width = sk[n].width
            pen = g.getPen()
            for c in r["contours"]:
                pen.moveTo(tuple(c[0][0]))
                for s in c:
                    (pen.lineTo(tuple(s[1])) if len(s) == 2 else
                     pen.curveTo(*[tuple(p) for p in s[1:]]))
                pen.closePath()
        src = SourceDescriptor()
        src.font, src.location, src.filename = f, {"Nib": v}, "N%d.ufo" % v
        doc.addSource(src)
    try:
        ufo2ft.compileVariableTTF(doc)
        return "builds"
    except Exception as exc:                # noqa: BLE001 - reported as it is
        return "%s: %s" % (type(exc).__name__, str(exc).splitlines()[0][:160])


SLANTS = ((0.15, 0.25), (0.6, 0.5))
DS_GLYPHS = ["a", "s", "o", "period"]


NIB_NARROW = (120.0, 20.0, 30.0)


def _skeleton_spots(axis, positions, randoms, rng):
    """(wdth u, nib axis value or None) of section 5's instances: ``positions`` along
    wdth (the nib axis at its maximum), ``positions`` along the nib axis (wdth at
    its middle) and ``randoms`` random points of the plane."""
    us = np.linspace(0, 1, positions)
    if axis is None:
        return [(float(u), None) for u in list(us) + list(rng.uniform(0, 1, randoms))]
    vs = np.linspace(axis.minimum, axis.maximum, positions)
    return [(float(u), axis.maximum) for u in us] + [(0.5, float(v)) for v in vs] + \
        [(float(rng.uniform(0, 1)), float(rng.uniform(axis.minimum, axis.maximum)))
         for _ in range(randoms)]


def skeleton_designspaces(subset, folder, positions, randoms):
    """Section 5: per (slant, widen) and nib: masters and measured instance errors with
    and without the intermediate skeleton masters (.ttf; the nib axis with three or
    more masters on both axes as .otf too)."""
    from fontTools.ttLib import TTFont

    from morph.compatible import Ellipse
    from morph.fonts import variable_skeleton
    from morph.parse.ufo import decomposed_paths, load_ufo
    from tests.oracles.varfont import skeleton_designspace

    sk = load_ufo(subset, lazy=False)
    real = variable_skeleton.refine_skeleton
    rows = []
    for slant, widen in SLANTS:
        sub = folder / ("ds%g" % slant)
        sub.mkdir(exist_ok=True)
        ds = skeleton_designspace(sub, subset, DS_GLYPHS, slant=slant, widen=widen)
        for nibs, suffix in ((((120, 30, 30), None), ".ttf"), ((NIB_MIN, NIB_MAX), ".ttf"),
                             ((NIB_MIN, NIB_NARROW), ".ttf"), ((NIB_MIN, NIB_NARROW), ".otf")):
            row = {"slant": slant, "widen": widen, "nibs": nibs, "suffix": suffix}
            for kind in ("given", "refined"):
                if kind == "given":
                    variable_skeleton.refine_skeleton = \
                        lambda s, n, b, budget, k, c=(): real(s, n, b, float("inf"), k, c)
                try:
                    c0 = time.process_time()
                    out = sub / ("%s%d%s" % (kind, len(rows), suffix))
                    st = stroke_variable(ds, out, nibs[0], nibs[1], tol=TOL, overwrite=True)
                    cpu = time.process_time() - c0
                finally:
                    variable_skeleton.refine_skeleton = real
                vf = TTFont(str(out))
                axis = st["axis"]
                worst = (0.0, "")
                rng = np.random.default_rng(35)
                for u, v in _skeleton_spots(axis, positions, randoms, rng):
                    loc = {"wdth": 100 + 25 * u}
                    nib = Ellipse(*nibs[0])
                    if axis is not None:
                        loc[axis.tag] = v
                        nib = axis.nib_at(v)
                    gs = instance_glyphs(vf, loc)
                    m = np.array([[1 + widen * u, slant * u], [0.0, 1.0]])
                    for n in DS_GLYPHS:
                        lines = [p @ m.T for p in skeleton_polylines(decomposed_paths(sk, n))]
                        ref = [p + np.array([nib.extent()[2], 0.0])
                               for p in clipper_stroke(lines, tuple(nib))]
                        d = sum_distance(glyph_polygons(gs, n), ref, strict=True, area=2.0,
                                         hi=6.0)
                        worst = max(worst, (d, "%s at %s" % (n, ", ".join(
                            "%s %.5g" % kv for kv in loc.items()))))
                row[kind] = {"masters": len(st["masters"]), "report": st["skeleton"],
                             "nib_masters": len(st["values"]) or 1, "cpu": cpu,
                             "worst": worst}
            rows.append(row)
    return rows


def _brushed_error(vf, st, src, lo, spots):
    """(worst (d, where), largest anchor error, pinholes) of a brushed font's
    instances at ``spots`` against the source's instance ⊕ the nib there."""
    from fontTools.varLib import instancer

    from morph.compatible import Ellipse
    from tests.fonts.varsources import mark_anchor, source_instance
    from tests.oracles.varfont import clipper_region_sum

    worst, anchor, holes = (0.0, ""), 0.0, 0
    for loc in spots:
        inst = instancer.instantiateVariableFont(vf, loc)       # its anchors
        source = source_instance(src, {t: v for t, v in loc.items() if t == "wght"})
        axis = st["axis"]
        v = loc.get(axis.tag, axis.minimum) if axis else None
        nib = axis.nib_at(v) if axis else Ellipse(*lo)
        shift_nib = axis.nib_min if axis and axis.tag == "GRAD" else nib
        gs, sgs = instance_glyphs(vf, loc), source.getGlyphSet()
        for n in ("o", "e", "n", "acutecomb"):
            hx = shift_nib.extent()[2] * (1 if sgs[n].width else -1)
            ref = [p + np.array([hx, 0.0])
                   for p in clipper_region_sum(glyph_polygons(sgs, n), tuple(nib))]
            got = glyph_polygons(gs, n)
            d = sum_distance(got, ref, strict=True, area=2.0, hi=30.0)
            worst = max(worst, (d, "%s at %s" % (n, ", ".join(
                "%s %.4g" % kv for kv in loc.items()))))
            holes += len([a for a in pinholes(got, ref) if a > 1e-3])
        for a0, a1, w in zip(mark_anchor(source, "e"), mark_anchor(inst, "e"), (1, 0)):
            want = a0[0] + shift_nib.extent()[2] * (1 if w else -1)
            anchor = max(anchor, abs(a1[0] - want))
    return worst, anchor, holes


def _spots(axes, positions, randoms, rng):
    """``positions`` per axis (the others at their defaults) and ``randoms`` random
    points of the design space, user coordinates."""
    spots = [{a.axisTag: float(v)} for a in axes
             for v in np.linspace(a.minValue, a.maxValue, positions)]
    if len(axes) > 1 or randoms:
        spots += [{a.axisTag: float(rng.uniform(a.minValue, a.maxValue)) for a in axes}
                  for _ in range(randoms)]
    return spots


def brushed_fonts(folder, positions, randoms, count=None):
    """Section 6: the small mark fonts brushed with and without nib axes, as .ttf
    and .otf, with the source masters refined and (for the variable sources) not."""
    from fontTools.ttLib import TTFont

    from morph.fonts.variable_brush import brush_variable
    from tests.fonts.varsources import mark_font, to_cff, variable_mark_font

    static = mark_font(folder)
    otf = folder / "Mark.otf"
    to_cff(TTFont(str(static))).save(str(otf))
    var, cff2 = variable_mark_font(folder), variable_mark_font(folder, cff2=True)
    tall = variable_mark_font(folder, scale=(1.0, 2.0))
    cases = [("static TTF", static, NIB_MIN, NIB_MAX, ".ttf"),
             ("static TTF", static, NIB_MIN, NIB_MAX, ".otf"),
             ("static CFF", otf, (20, 20, 0), (50, 50, 0), ".ttf"),
             ("static TTF, turning nib", static, (80, 20, 0), (80, 20, 60), ".ttf"),
             ("variable TTF", var, NIB_MIN, None, ".ttf"),
             ("variable TTF", var, NIB_MIN, NIB_MAX, ".ttf"),
             ("variable TTF", var, NIB_MIN, NIB_MAX, ".otf"),
             ("variable CFF2", cff2, NIB_MIN, None, ".ttf"),
             ("variable CFF2", cff2, NIB_MIN, NIB_MAX, ".otf"),
             ("variable TTF, tall wght master", tall, (80, 20, 30), None, ".ttf")]
    rows = []
    rng = np.random.default_rng(35)
    for label, src, lo, hi, suffix in cases[:count]:
        for refine in ((True, False) if "variable" in label else (True,)):
            out = folder / ("Brush%d%s" % (len(rows), suffix))
            c0 = time.process_time()
            st = brush_variable(src, out, lo, nib_max=hi, tol=TOL, refine=refine)
            cpu = time.process_time() - c0
            vf = TTFont(str(out))
            axes = vf["fvar"].axes
            spots = _spots(axes, positions, randoms, rng)
            worst, anchor, holes = _brushed_error(vf, st, src, lo, spots)
            rep = st["refinement"]
            rows.append({"label": label + ("" if refine else ", source masters only"),
                         "suffix": suffix, "size": out.stat().st_size,
                         "axes": ", ".join("%s %g..%g" % (a.axisTag, a.minValue, a.maxValue)
                                           for a in axes),
                         "nibs": (lo, hi), "masters": len(st["masters"]),
                         "sources": "-" if rep is None else "%d + %d (most %d, %s)" % (
                             rep["given"], rep["added"], rep["most"], rep["hardest"] or "-"),
                         "blend": "-" if rep is None else "%.2f / %.2f" % (
                             max(rep["errors_before"].values()), rep["error"]),
                         "cpu": cpu, "per": 1000 * st["fit_seconds"] / max(1, st["glyphs"]) /
                         len(st["masters"]), "worst": worst, "anchor": anchor,
                         "positions": len(spots), "pinholes": holes})
    return rows


SERIF_NIB = (60.0, 15.0, 30.0)


def serif_brush(folder, glyphs, positions, randoms):
    """Section 7: Source Serif 4's variable font (fontpkg-source-serif-4) cut to
    ``glyphs`` and brushed keeping wght and opsz, as .ttf and .otf: each glyph's own
    source masters, CPU time, size, ots, and the instances at ``positions`` per axis
    (the other at its default) and ``randoms`` random points against the source's
    instance ⊕ the nib (Clipper).  None when the package is missing."""
    from fontTools import subset
    from fontTools.ttLib import TTFont
    from fontTools.varLib import instancer

    from morph.compatible import Ellipse
    from morph.fonts.variable_brush import brush_variable
    from tests.oracles.varfont import clipper_region_sum

    try:
        import fontpkg_source_serif_4 as pkg
    except ImportError:
        return None
    font = TTFont(str(Path(pkg.__file__).parent / "files" / "SourceSerif4[opsz,wght].ttf"))
    opts = subset.Options()
    opts.glyph_names, opts.notdef_outline = True, True
    sub = subset.Subsetter(opts)
    sub.populate(glyphs=glyphs)
    sub.subset(font)
    src = folder / "SerifCut.ttf"
    font.save(str(src))
    source = TTFont(str(src))
    shift = Ellipse(*SERIF_NIB).extent()[2]
    rows = []
    for suffix in (".ttf", ".otf"):
        out = folder / ("SerifBrush" + suffix)
        c0 = time.process_time()
        try:
            st = brush_variable(src, out, SERIF_NIB, glyphs=glyphs, tol=TOL)
        except Exception as exc:            # noqa: BLE001 - reported as it is
            rows.append({"suffix": suffix, "error": "%s: %s" % (type(exc).__name__, exc)})
            continue
        cpu = time.process_time() - c0
        ots = _ots(out)
        vf = TTFont(str(out))
        rng = np.random.default_rng(35)
        spots = _spots(vf["fvar"].axes, positions, randoms, rng)
        worst, by_instancer = (0.0, ""), (0.0, "")
        for loc in spots:
            got = [instance_glyphs(vf, loc)]
            if suffix == ".otf":            # and the instancer's static font
                got.append(instancer.instantiateVariableFont(TTFont(str(out)),
                                                             loc).getGlyphSet())
            exact = instancer.instantiateVariableFont(source, loc).getGlyphSet()
            for n in glyphs:
                ref = [p + np.array([shift, 0.0])
                       for p in clipper_region_sum(glyph_polygons(exact, n), SERIF_NIB)]
                where = "%s at %s" % (n, ", ".join("%s %.4g" % kv for kv in loc.items()))
                d = [sum_distance(glyph_polygons(g, n), ref, strict=True, area=2.0, hi=6.0)
                     for g in got]
                worst = max(worst, (d[0], where))
                by_instancer = max(by_instancer, (d[-1], where))
        rows.append({"suffix": suffix, "cpu": cpu, "fit": st["fit_seconds"],
                     "size": out.stat().st_size, "ots": ots, "report": st["refinement"],
                     "glyph_masters": st["glyph_masters"], "masters": len(st["masters"]),
                     "positions": len(spots), "worst": worst,
                     "instancer": by_instancer if suffix == ".otf" else None,
                     "charstrings": _charstrings(TTFont(str(out))) if suffix == ".otf" else None})
    return rows


def _charstrings(vf):
    """Per glyph of a CFF2 font: (its charstring's bytes, the bytes of the local
    subroutines it calls, their count), and the longest subroutine."""
    top = vf["CFF2"].cff.topDictIndex[0]
    private = top.FDArray[0].Private
    subrs = [len(s.bytecode) for s in (getattr(private, "Subrs", None) or [])]
    bias = 107 if len(subrs) < 1240 else (1131 if len(subrs) < 33900 else 32768)
    out = {}
    for name in vf.getGlyphOrder():
        cs = top.CharStrings[name]
        size = len(cs.bytecode)
        cs.decompile()
        called = [t for t, op in zip(cs.program, cs.program[1:]) if op == "callsubr"]
        out[name] = (size, sum(subrs[c + bias] for c in called), len(called))
    return out, max(subrs, default=0)


def serif_section(rows, serif, args):
    """Section 7's Markdown lines from :func:`serif_brush`'s ``rows`` (none when it
    was skipped or every output failed)."""
    done = [r for r in (rows or []) if "error" not in r]
    if not done:
        return []
    rep = done[0]["report"]
    lines = ["", "## 7. Source Serif 4 (wght, opsz) cut to %s, nib %s" % (
        ", ".join(serif), SERIF_NIB), "",
        "The source's variable font (9 masters: wght and opsz at -1, 0, 1) brushed "
        "keeping its axes. Each glyph refines its own grid of source masters "
        "until its blend is within %.2f units, and the font stores each glyph's "
        "variations over its own masters (gvar tuples per glyph; CFF2 a VarData "
        "per glyph, chosen by vsindex; HVAR rows per glyph), so a glyph whose "
        "outline turns fast between the source's masters adds masters to itself "
        "only. Masters per glyph: %s (given %d, %d locations added over all "
        "glyphs; blend before refining %s, after %.3f). Instances: %d positions "
        "per axis and %d random points against the source's own instance there ⊕ "
        "the nib (Clipper), pinholes < 2 unit² aside; bound: tol + 2 x 0.71 = %.2f "
        "units per 1000 em. A .ttf's instance is fontTools' instancer's; a .otf's "
        "is fontTools' CFF2 blend evaluation at the location (max d), and the "
        "instancer's static font (max d, instancer)." % (
            0.4 * TOL, ", ".join("%s %d" % kv for kv in done[0]["glyph_masters"].items()),
            rep["given"], rep["added"], ", ".join(
                "%s %.1f" % kv for kv in rep["errors_before"].items()), rep["error"],
            args.positions, args.random, TOL + 2 ** 0.5), ""]
    cff2 = [r for r in done if r["charstrings"]]
    if cff2:
        per, longest = cff2[0]["charstrings"]
        lines += ["CFF2 charstrings (bytes; a blended program past 65,535 bytes, the most "
                  "a reader takes, is split into local subroutines the charstring "
                  "calls): %s; %s." % ("; ".join(
                      "%s %d" % (n, size) + (" calling %d subroutines of %d bytes in all" % (
                          count, called) if count else "")
                      for n, (size, called, count) in per.items()),
                      "the longest subroutine %d bytes" % longest if longest
                      else "no subroutines"), ""]
    lines += ["| output | masters (all glyphs) | CPU s (whole call) | fit CPU s | size | "
              "ots-sanitize | max d | where | max d, instancer | where |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append("| %s | %s | | | | | | | | |" % (r["suffix"], r["error"][:200]))
            continue
        inst = r["instancer"]
        lines.append("| %s | %d | %.1f | %.1f | %d | %s | %.3f | %s | %s | %s |" % (
            r["suffix"], r["masters"], r["cpu"], r["fit"], r["size"], r["ots"],
            r["worst"][0], r["worst"][1], "-" if inst is None else "%.3f" % inst[0],
            "-" if inst is None else inst[1]))
    return lines


def _splice_section(path, lines, seconds):
    """Section 7 (``lines``, from its heading) written into the report at ``path`` in
    place of the one there (at its end; appended when it has none), stamped with how
    and when it alone was made."""
    from bench.stamp import stamp

    at = next(k for k, line in enumerate(lines) if line.startswith("## 7."))
    section = lines[at:at + 2] + ["Section 7 alone: " + stamp(seconds=seconds), ""] + \
        lines[at + 2:]
    old = path.read_text().rstrip("\n").split("\n") if path.exists() else []
    keep = next((k for k, line in enumerate(old) if line.startswith("## 7.")), len(old))
    while keep and not old[keep - 1].strip():
        keep -= 1
    path.write_text("\n".join(old[:keep] + [""] + section) + "\n")
    print("\n".join(section))


def _ots(path):
    """ots-sanitize's verdict on a font: "passes", the first line of its complaint,
    or "not run" (no ots module)."""
    try:
        import ots
    except ImportError:
        return "not run"
    r = ots.sanitize(str(path), capture_output=True)
    return "passes" if r.returncode == 0 else \
        (r.stderr.decode(errors="replace").strip().splitlines() or ["fails"])[0][:100]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--skeleton", default=str(ROOT.parent.parent / "shared" / "data" /
                                              "relief-singleline" / "Relief-SingleLine.ufo"))
    ap.add_argument("--subset", default=str(ROOT / "tests" / "data" / "relief" /
                                            "Relief-SingleLine-subset.ufo"))
    ap.add_argument("--out", default=None,
                    help="the report (default bench/varfont.md, with --part brush "
                         "bench/varfont_brush.md)")
    ap.add_argument("--part", choices=("all", "stroke", "brush", "serif"), default="all",
                    help="sections 1-5 (stroke), 6-7 (brush), all, or section 7 alone "
                         "(serif: written into the existing report in place of its own)")
    ap.add_argument("--positions", type=int, default=9)
    ap.add_argument("--random", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cases", type=int, default=None,
                    help="section 6: the first this many brushed cases (default: all)")
    ap.add_argument("--no-fontforge", action="store_true")
    ap.add_argument("--serif", default="o,e",
                    help="section 7: the Source Serif 4 glyphs brushed ('' to skip)")
    ap.add_argument("--glyphs", default=None, help="glyph names of the subset (default: all)")
    ap.add_argument("--measure", default=None,
                    help="glyphs whose instances are measured (default: --glyphs)")
    args = ap.parse_args()
    if args.out is None:
        args.out = str(ROOT / "bench" / ("varfont_brush.md" if args.part in ("brush", "serif")
                                         else "varfont.md"))
    glyphs = None if args.glyphs is None else args.glyphs.split(",")
    measured = glyphs if args.measure is None else args.measure.split(",")
    for name in ("ufo2ft", "fontTools"):
        logging.getLogger(name).setLevel(logging.ERROR)
    folder = Path(tempfile.mkdtemp(prefix="varfont-bench-"))
    from bench.stamp import stamp

    t_start = time.perf_counter()
    lines = ["# Variable calligraphic fonts: cost, size, instance error, FontForge", "",
             "STAMP", "",
             "CPU times are process_time (the machine is shared); tol %g font units." % TOL,
             ""]
    if args.part in ("all", "stroke"):
        whole = None
        if Path(args.skeleton).is_dir():
            whole = whole_font(args.skeleton, folder, args.jobs)
            r = whole[".ttf"]
            lines += ["## 1. Relief SingleLine (%d glyphs), nib axis %s -> %s" % (
                r["glyphs"], NIB_MIN, NIB_MAX), "",
                "| output | masters | fit CPU s | per glyph per master | whole call CPU s | "
                "size |", "|---|---|---|---|---|---|"]
            for suffix, r in whole.items():
                lines.append("| %s | %d | %.1f | %.1f ms | %.1f | %d bytes |" % (
                    suffix, r["masters"], r["fit"], 1000 * r["fit"] / r["glyphs"] / r["masters"],
                    r["cpu"], r["size"]))
            lines.append("")
        var_path = folder / "SubsetNib.ttf"
        c0 = time.process_time()
        st = stroke_variable(args.subset, var_path, NIB_MIN, NIB_MAX, glyphs=glyphs, tol=TOL,
                             overwrite=True)
        var_cpu = time.process_time() - c0
        statics = static_fonts(args.subset, folder, glyphs)
        lines += ["## 2. Relief subset (%d glyphs): variable against static" % st["glyphs"], "",
                  "Compatible fit: %.1f CPU s for %d glyphs x %d masters, %.1f ms per glyph per "
                  "master." % (st["fit_seconds"], st["glyphs"], len(st["masters"]),
                               1000 * st["fit_seconds"] / st["glyphs"] / len(st["masters"])), "",
                  "| font | size | CPU s |", "|---|---|---|",
                  "| variable TTF (2 masters, overlapping, no IUP) | %d | %.1f |" % (
                      var_path.stat().st_size, var_cpu)]
        for r in statics:
            lines.append("| static TTF, nib %s (trimmed) | %d | %.1f |" % (
                r["nib"], r["size"], r["cpu"]))
        lines += ["", "Instances (fontTools.varLib.instancer) against the exact sum, every glyph: "
                  "the least d with erode(S, d) ⊆ F ⊆ dilate(S, d) (pinholes < 1 unit² aside), "
                  "and the pinholes (> 0.001 unit²) the rounded outline leaves at swallowtail "
                  "cusps. Bound: tol + 2 x 0.71 (the masters' and the instance's integer "
                  "rounding) = %.2f units." % (TOL + 2 ** 0.5), ""]
        rows, count = instance_errors(args.subset, var_path, args.positions, args.random,
                                      measured)
        lines += ["| NIBW | max d | glyph | pinholes | largest pinhole (unit²) |",
                  "|---|---|---|---|---|"]
        for r in rows:
            lines.append("| %.2f | %.3f | %s | %d | %.3f |" % (r["value"], r["max"], r["glyph"],
                                                              r["pinholes"], r["largest_pinhole"]))
        lines += ["", "Largest over %d glyphs x %d locations: %.3f units." % (
            count, len(rows), max(r["max"] for r in rows)), ""]
        lines += ["## 3. Masters a nib axis needs (blend share %.2f units)" % (0.4 * TOL), "",
                  "| from | to | tag | masters |", "|---|---|---|---|"]
        for a, b, tag, n in masters_needed():
            lines.append("| %s | %s | %s | %d |" % (a, b, tag, n))
        ff = None if args.no_fontforge else fontforge_compat(args.subset, glyphs)
        lines += ["", "## 4. FontForge Expand Stroke at the two nibs", ""]
        if ff is None:
            lines.append("Not measured (--no-fontforge, or no %s with python3-fontforge)."
                         % SYSTEM_PYTHON)
        elif "error" in ff:
            lines.append("FontForge failed: %s" % ff["error"])
        else:
            lines.append("Of %d glyphs, %d have the same contours and segment types at both "
                         "nibs (%d differ in the number of contours); varLib on FontForge's two "
                         "masters: %s. morph's masters are compatible by construction (every "
                         "glyph)." % (ff["glyphs"], ff["same"], ff["contours_differ"],
                                      ff["varlib"]))
        lines += ["", "## 5. Skeleton designspaces: intermediate skeleton masters", "",
                  "The subset's glyphs %s in a Regular master and a Wide master (x' = (1 + "
                  "widen) x + slant y). Bound: tol + 2 x 0.71 = %.2f units; the blend share "
                  "of tol %.2f units (halved when the nib axis is inexact too). Estimate: the "
                  "nib parts' blend at equal parameter (an upper bound); measured: instancer "
                  "against Clipper at %d positions of wdth (the nib axis at its maximum), %d "
                  "of the nib axis (wdth 112.5) and %d random points, the least d with "
                  "erode(S, d) ⊆ F ⊆ dilate(S, d), pinholes < 2 unit² aside. ufo2ft "
                  "compiles the designspace with the grid's tents as the variation "
                  "model's supports (fontTools' own weigh a master between others 1/2 or "
                  "1/3 at its neighbours, and the rounded deltas then reproduce a master "
                  "only within 0.5 unit per coordinate): every master is exact. The rows "
                  "with %s -> %s have several masters on both axes (.ttf and .otf). A "
                  ".otf's instance is fontTools' CFF2 blend evaluation at the location "
                  "(the instancer's static CFF can differ)."
                  % (", ".join(DS_GLYPHS), TOL + 2 ** 0.5, 0.4 * TOL, args.positions,
                     args.positions, args.random, NIB_MIN, NIB_NARROW), "",
                  "| slant, widen | nibs | output | estimate before | skeleton masters | nib "
                  "masters | estimate after | measured, given masters | measured, with "
                  "intermediate | CPU s (given / refined) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for r in skeleton_designspaces(args.subset, folder, args.positions, args.random):
            g, f = r["given"], r["refined"]
            rep = f["report"]
            lines.append("| %g, %g | %s | %s | %.2f | 2 + %d | %d | %.2f | %.2f (%s) | %.2f "
                         "(%s) | %.1f / %.1f |" % (
                             r["slant"], r["widen"], " -> ".join(
                                 str(tuple(n)) for n in r["nibs"] if n is not None),
                             r["suffix"], rep["errors_before"]["Width"], rep["added"],
                             f["nib_masters"], rep["error"], g["worst"][0], g["worst"][1],
                             f["worst"][0], f["worst"][1], g["cpu"], f["cpu"]))
    if args.part in ("all", "brush"):
        lines += ["", "## 6. Brushed variable fonts (small mark fonts: o, e, n, acutecomb)", "",
                  "Each axis at %d positions (the others at their defaults) and %d random "
                  "points (fontTools' instancer) against the source's instance ⊕ the nib "
                  "there (Clipper), pinholes < 2 unit² aside; bound: tol + 2 x 0.71 = %.2f "
                  "units per 1000 em. Source masters: the source's grid (every region's "
                  "start, peak and end) + the intermediate ones added, each glyph its own, "
                  "until its blend (the "
                  "filled outlines' distance between the blend of two masters and the exact "
                  "sum at 1/4, 1/2, 3/4 of the way) is within its share of tol (%.2f units, "
                  "halved with an inexact nib axis); source masters: given + added over "
                  "all glyphs (the most one glyph has, and which); blend: before / after. "
                  "Anchors: the "
                  "largest distance of the e / acutecomb mark anchors from the source's moved "
                  "by their glyph's shift (rounding: <= 1 unit)."
                  % (args.positions, args.random, TOL + 2 ** 0.5, 0.4 * TOL), "",
                  "| source | output | nibs | axes | masters | source masters | blend | size | "
                  "CPU s | fit ms per glyph per master | max d | where | pinholes | anchor "
                  "error |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in brushed_fonts(folder, args.positions, args.random, args.cases):
            lines.append("| %s | %s | %s | %s | %d | %s | %s | %d | %.1f | %.1f | %.3f | %s | %d "
                         "| %.1f |" % (
                             r["label"], r["suffix"], " -> ".join(
                                 str(tuple(n)) for n in r["nibs"] if n is not None),
                             r["axes"], r["masters"], r["sources"], r["blend"], r["size"],
                             r["cpu"], r["per"], r["worst"][0], r["worst"][1], r["pinholes"],
                             r["anchor"]))
    if args.part in ("all", "brush", "serif"):
        serif = [g for g in args.serif.split(",") if g]
        rows = serif_brush(folder, serif, args.positions, args.random) if serif else None
        lines += serif_section(rows, serif, args)
    if args.part == "serif":
        if not any(line.startswith("## 7.") for line in lines):
            sys.exit("section 7 not made: %s" % (rows or "no glyphs (--serif) or no "
                                                 "fontpkg-source-serif-4"))
        _splice_section(Path(args.out), lines, time.perf_counter() - t_start)
        print("fonts in %s" % folder)
        return
    lines[2] = stamp(seconds=time.perf_counter() - t_start)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
