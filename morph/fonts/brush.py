"""Brush-swept fonts (paper Fig. 5): every chosen glyph replaced by glyph ⊕ nib.

The nib is a convex region swept without rotation (a calligraphic pen held at a
fixed angle); the default is an exact ellipse (:func:`morph.piece.ellipse`).  Each
sum is computed with :func:`morph.trim.minkowski_sum` within ``tol / 2`` and its
rational pieces are converted to the font's curve type within ``tol / 2``
(TrueType: quadratics, :func:`morph.export.piece_to_quadratics`; CFF: cubics,
:func:`morph.export.piece_to_cubics`), both with certified bounds, so each written
outline is within ``tol`` font units of the exact glyph ⊕ nib.

Metrics: the outline is shifted right by the nib's left extent (so it starts no
further left of the origin than the original glyph did) and the advance width grows
by the nib's width.  Contours are written clockwise-outside for TrueType and
counter-clockwise-outside for CFF.  The result is a trimmed boundary: no overlapping
contours are left.

Composite glyphs (TrueType; e.g. eacute = e + acute).  A chosen composite is
decomposed and swept as a whole (it becomes a simple glyph, accent brushed too).  A
composite that is not chosen but uses a swept glyph keeps its components (the default
``composites="follow"``): its advance width grows by the nib's width like the swept
base's, and each component that was not swept (the accent) moves by the translation
of the nib's centre, (nib width / 2, nib centre y), i.e. to where the centre of its own
swept version would be, so it stays centred over the widened base.  Composites with a
scaled / flipped component or one placed by anchor points cannot follow (the swept
outline would be transformed with its nib, or the point numbers changed): they are
decomposed and swept; ``composites="sweep"`` does that for all of them.  CFF fonts
have no composites; seac accented glyphs are not handled (they would follow the
base without metric changes).  GPOS mark anchors are not moved.
"""

import re

import numpy as np

from .. import piece as pc
from ..errors import MorphError

__all__ = ["ellipse_nib", "check_convex_nib", "parse_glyph_spec", "brush_font", "composite_plan",
           "region_extent"]


def ellipse_nib(width, height, angle_deg=0.0):
    """Exact elliptical nib: width x height (font units), rotated by angle (degrees)."""
    if width <= 0 or height <= 0:
        raise MorphError("nib width and height must be positive, got %g x %g"
                         % (width, height))
    return [pc.ellipse((0.0, 0.0), width / 2.0, height / 2.0, np.radians(angle_deg))]


def check_convex_nib(nib):
    """Raise MorphError unless the nib is a single convex loop (Gauss map monotone)."""
    from ..gauss import gauss_map

    if len(nib) != 1:
        raise MorphError("the nib must be one closed convex shape, got %d loops" % len(nib))
    edges = gauss_map(nib[0])
    bad = [e for e in edges if e.sweep < -1e-9]
    if bad:
        raise MorphError("the nib is not convex: it turns clockwise at %s (only convex "
                         "nibs are supported)" % (np.round(bad[0].point, 3).tolist(),))
    total = sum(e.sweep for e in edges)
    if abs(total - 2 * np.pi) > 1e-6:
        raise MorphError("the nib is not convex (total turning %.3f rad)" % total)


def region_extent(loops):
    """Exact bounding box of a region (xmin, ymin, xmax, ymax)."""
    from ..region import region_bbox

    return tuple(float(v) for v in region_bbox(loops))


def parse_glyph_spec(spec):
    """'A-Z,a-z,ampersand,0' -> list of characters / glyph names (ranges of characters)."""
    out = []
    for item in [s.strip() for s in spec.split(",")]:
        if not item:
            continue
        m = re.fullmatch(r"(.)-(.)", item)
        if m and ord(m.group(1)) <= ord(m.group(2)):
            out.extend(chr(c) for c in range(ord(m.group(1)), ord(m.group(2)) + 1))
        else:
            out.append(item)
    return out


def _glyph_name(font, item):
    if len(item) == 1:
        name = font.getBestCmap().get(ord(item))
    else:
        name = item if item in set(font.getGlyphOrder()) else None
    if name is None:
        raise MorphError("the font has no glyph for %r" % item)
    return name


def _reverse_loop(loop):
    return [pc.reverse(p) for p in reversed(loop)]


def _draw(pen, loops, tol, quadratic):
    """Draw loops (ours: outer counter-clockwise) as polynomial contours on a pen.

    TrueType (``quadratic``): quadratics, outer contours clockwise (loops reversed);
    CFF: cubics, outer contours counter-clockwise, as ours.  Lines stay lines.
    """
    from ..export import piece_to_cubics, piece_to_quadratics

    convert = piece_to_quadratics if quadratic else piece_to_cubics
    for loop in loops:
        if quadratic:
            loop = _reverse_loop(loop)
        segs = []
        for p in loop:
            if pc.degree(p) == 1 and pc.is_polynomial(p):
                segs.append(pc.cartesian(p))
            else:
                segs.extend(np.asarray(q, float) for q in convert(p, tol))
        _emit(pen, segs, quadratic)


def _emit(pen, segs, quadratic):
    """Draw a closed contour of polynomial segments ((k, 2) control points)."""
    segs = [s for s in segs if np.hypot(*(s[-1] - s[0])) > 0 or len(s) > 2]
    if not segs:
        return
    start = segs[0][0]
    pen.moveTo(tuple(map(float, start)))
    for s in segs:
        pts = [tuple(map(float, q)) for q in s[1:]]
        if len(s) == 2:
            pen.lineTo(pts[0])
        elif quadratic:
            pen.qCurveTo(*pts)
        else:
            pen.curveTo(*pts)
    pen.closePath()


class _TrueTypeOutlines:
    """Writes glyph outlines into the ``glyf`` table (quadratic contours)."""

    quadratic = True

    def __init__(self, font):
        self.glyf = font["glyf"]
        self.glyph_set = font.getGlyphSet()

    def pen(self, advance):
        from fontTools.pens.ttGlyphPen import TTGlyphPen

        return TTGlyphPen(self.glyph_set)

    def store(self, name, pen, drawn):
        """Store the pen's glyph; return the new left side bearing."""
        g = pen.glyph()
        self.glyf[name] = g
        g.recalcBounds(self.glyf)
        return g.xMin if drawn else 0


class _CFFOutlines:
    """Writes glyph outlines into the ``CFF `` table (Type 2 charstrings, cubic)."""

    quadratic = False

    def __init__(self, font):
        self.cff = font["CFF "].cff
        top = self.cff.topDictIndex[0]
        self.char_strings = top.CharStrings
        self.private = top.Private
        self.nominal = getattr(self.private, "nominalWidthX", 0) or 0

    def pen(self, advance):
        from fontTools.pens.t2CharStringPen import T2CharStringPen

        return T2CharStringPen(advance - self.nominal, None)

    def store(self, name, pen, drawn):
        """Store the pen's charstring; return the new left side bearing."""
        cs = pen.getCharString(private=self.private, globalSubrs=self.cff.GlobalSubrs)
        self.char_strings[name] = cs
        bounds = cs.calcBounds(self.char_strings) if drawn else None
        return int(np.floor(bounds[0])) if bounds else 0


def _rigid(component):
    """True for a TrueType component placed by an offset only (no 2x2, no anchor points)."""
    return not hasattr(component, "transform") and getattr(component, "firstPt", None) is None


def composite_plan(font, swept, composites="follow"):
    """Which TrueType composite glyphs depend on the swept glyphs, and how.

    Returns ``(follow, sweep)``: glyph names not in ``swept`` whose components include
    a swept glyph, directly or through other such composites, in dependency order.
    ``follow``: composites that stay composites (see :func:`brush_font`); ``sweep``:
    composites to decompose and sweep themselves -- those with a scaled, rotated or
    flipped component or one placed by anchor points (the swept component's outline
    cannot simply be reused there: (M g) ⊕ nib is not M (g ⊕ nib), and the point
    numbers changed), and all of them with ``composites="sweep"``.  CFF fonts have no
    composites (seac accents are not looked at): both lists are empty.
    """
    if composites not in ("follow", "sweep"):
        raise MorphError("composites must be 'follow' or 'sweep', got %r" % (composites,))
    if "glyf" not in font:
        return [], []
    glyf = font["glyf"]
    comps = {n: glyf[n].components for n in font.getGlyphOrder() if glyf[n].isComposite()}
    moved = set(swept)
    follow, sweep = [], []
    changed = True
    while changed:  # discovery order is a dependency order
        changed = False
        for n, components in comps.items():
            if n not in moved and any(c.glyphName in moved for c in components):
                moved.add(n)
                changed = True
                rigid = composites == "follow" and all(map(_rigid, components))
                (follow if rigid else sweep).append(n)
    return follow, sweep


def _follow_composites(font, follow, moved, offset, nib_w):
    """Adjust composites that keep their components (TrueType only).

    Each composite grows by the nib's width like its swept components, and every
    component that was not swept (an accent over a swept base) moves by ``offset``,
    the translation of the nib's centre in the swept glyphs: where the centre of its
    own swept version would be, so it stays centred over its base.
    """
    if not follow:
        return
    glyf, hmtx = font["glyf"], font["hmtx"]
    dx, dy = (int(round(v)) for v in offset)
    for n in follow:
        g = glyf[n]
        for c in g.components:
            if c.glyphName not in moved:
                c.x += dx
                c.y += dy
        g.recalcBounds(glyf)
        adv, _ = hmtx[n]
        hmtx[n] = (int(round(adv + nib_w)), int(getattr(g, "xMin", 0)))


def _rename(font, family):
    name = font["name"]
    style = name.getDebugName(2) or "Regular"
    ps = re.sub(r"[^A-Za-z0-9-]", "", family.replace(" ", "")) + "-" + \
        re.sub(r"[^A-Za-z0-9]", "", style)
    full = "%s %s" % (family, style) if style != "Regular" else family
    for rec in list(name.names):
        if rec.nameID in (1, 16):
            rec.string = family
        elif rec.nameID == 4:
            rec.string = full
        elif rec.nameID == 6:
            rec.string = ps
        elif rec.nameID == 3:
            rec.string = "%s;%s" % (ps, "morph-brush")
        elif rec.nameID == 21:
            rec.string = family
    for nid, text in ((1, family), (4, full), (6, ps)):
        if name.getName(nid, 3, 1, 0x409) is None:
            name.setName(text, nid, 3, 1, 0x409)
    if "CFF " in font:
        cff = font["CFF "].cff
        cff.fontNames = [ps]
        top = cff.topDictIndex[0]
        top.FamilyName = family
        top.FullName = full


def brush_font(font_path, out_path, nib_region, glyphs, tol=0.5, family_name=None,
               progress=None, method="qac", composites="follow"):
    """Write a copy of the font with each chosen glyph replaced by glyph ⊕ nib.

    ``font_path``: a TrueType (glyf) or CFF OpenType font (None: the bundled font).
    ``nib_region``: a convex region in font units (e.g. :func:`ellipse_nib`).
    ``glyphs``: characters or glyph names; a chosen composite glyph is decomposed and
    swept as a whole.  ``tol``: total outline tolerance in font units (half for the
    sum, half for the curve conversion).  ``family_name``: the new family name
    (default: "<family> Brush").  ``progress(name)`` is called after each chosen
    glyph.  ``composites``: what happens to TrueType composites that are not chosen
    but use a swept glyph (e.g. eacute = e + acute when e is swept): "follow" (they
    stay composites, grow by the nib width and their unswept components move with
    the nib's centre, see :func:`composite_plan`) or "sweep" (decomposed and swept
    too).  Returns a dict of statistics: glyphs (chosen, swept), contours, segments,
    followed and decomposed (composites not chosen).

    Raises:
        MorphError: non-convex nib, variable font, a glyph missing from the font, a
            sum that fails (the message names the glyph).
    """
    from fontTools.ttLib import TTFont

    from ..parse import default_font_path, glyph_region
    from ..trim import minkowski_sum

    if font_path is None:
        font_path = default_font_path()
    check_convex_nib(nib_region)
    font = TTFont(str(font_path))
    if "fvar" in font:
        raise MorphError("variable fonts are not supported: instantiate one style first "
                         "(fontTools.varLib.instancer)")
    if "glyf" in font:
        outlines = _TrueTypeOutlines(font)
    elif "CFF " in font:
        outlines = _CFFOutlines(font)
    else:
        raise MorphError("font %s has neither TrueType (glyf) nor CFF outlines" % font_path)
    nx0, ny0, nx1, ny1 = region_extent(nib_region)
    nib_w = nx1 - nx0
    shift = -nx0  # glyph ⊕ nib starts -nx0 further left: move it back
    names = []
    for item in glyphs:
        n = _glyph_name(font, item)
        if n not in names:
            names.append(n)
    follow, extra = composite_plan(font, names, composites)
    if family_name is None:
        family_name = "%s Brush" % (font["name"].getDebugName(1) or "Morph")

    # read all source outlines before anything is changed
    sources = {}
    for n in names + extra:
        try:
            sources[n] = (glyph_region(n, font=font).region if len(n) > 1
                          else _region_by_name(font, n))
        except MorphError:
            sources[n] = []  # empty glyph (space): metrics only
    half = tol / 2.0
    stats = {"glyphs": 0, "contours": 0, "segments": 0, "followed": len(follow),
             "decomposed": len(extra)}
    hmtx = font["hmtx"]
    for n in names + extra:
        adv, lsb = hmtx[n]
        region = sources[n]
        new_adv = int(round(adv + nib_w))
        loops = []
        if region:
            try:
                loops = minkowski_sum(region, nib_region, half, method=method)
            except MorphError as exc:
                raise type(exc)("glyph %r: %s" % (n, exc)) from exc
            loops = [[pc.translate(p, (shift, 0.0)) for p in loop] for loop in loops]
        pen = outlines.pen(new_adv)
        _draw(pen, loops, half, outlines.quadratic)
        hmtx[n] = (new_adv, int(outlines.store(n, pen, bool(loops))))
        if n in extra:
            continue
        stats["glyphs"] += 1
        stats["contours"] += len(loops)
        stats["segments"] += sum(map(len, loops))
        if progress is not None:
            progress(n)
    centre = (shift + (nx0 + nx1) / 2.0, (ny0 + ny1) / 2.0)
    _follow_composites(font, follow, set(names + extra + follow), centre, nib_w)
    for tag in ("hdmx", "LTSH", "VDMX"):
        if tag in font:
            del font[tag]
    _rename(font, family_name)
    font.save(str(out_path))  # recalcBBoxes: head / hhea / maxp bounds
    return stats


def _region_by_name(font, name):
    """Region of glyph ``name`` of an open TTFont (a 1-letter name is not a char)."""
    from ..parse import glyph_region

    # glyph_region reads a 1-character string as a character: go through the cmap
    # only when the character maps to this very glyph, else use a temporary lookup
    cmap = font.getBestCmap()
    chars = [chr(c) for c, g in cmap.items() if g == name]
    if chars:
        return glyph_region(chars[0], font=font).region
    raise MorphError("cannot address glyph %r by character or name" % name)
