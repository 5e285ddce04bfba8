"""SVG output: regions -> path data (M/L/Q/T/C/S/Z) within a stated tolerance.

Each loop goes through :func:`morph.export.loop_to_beziers`: a line, polynomial
quadratic or cubic between corners is written exactly (L, Q, C); every other run of
pieces with smooth joins becomes certified cubics (C) that may span the joins.  A
quadratic (cubic) whose first control point is, in the written decimals, the
reflection of the previous one's last control point is written T (S), without it:
the reader implies the same point (TrueType's implied on-curve points, kept by a
sum's translated glyph quadratics).
Coordinates are rounded to d decimals, the fewest with ``r = 0.5 * 10^-d * sqrt(2)
<= ROUND_SHARE tol``.  Rounding moves each control point by at most r and hence the
curve by at most r at the same parameter (convex combination); the cubic fit gets
the rest, ``tol - r >= 0.95 tol`` (Fréchet distance, certified under a monotone
reparametrisation), so the written curves are within ``tol`` of the loop in
Fréchet, hence Hausdorff, distance.  A command that computes the pieces
themselves within some tolerance passes this writer only the export share of the
user's tolerance (:func:`morph.budget.plan`).  y is negated (region y-up
-> SVG y-down).
"""

import math

from ..budget import ROUND_SHARE
from ..export import loops_to_beziers
from . import frame_bbox, normalize_shapes

__all__ = ["svg_path_data", "write_svg", "svg_document", "fitted_regions", "document_tol"]

#: what html.escape(value, quote=True) replaces, in its order (``&`` first); written
#: out because xml.sax.saxutils imports urllib.request and html imports html.entities
_ESCAPES = (("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"), ("'", "&#x27;"))


def quoteattr(value):
    """An XML attribute value in double quotes (``&``, ``<``, ``>``, ``"``, ``'``
    escaped as html.escape does)."""
    text = str(value)
    for char, entity in _ESCAPES:
        text = text.replace(char, entity)
    return '"%s"' % text


def rounding(tol):
    """(d, r): the fewest decimals d whose rounding moves a point by r = 0.5 * 10^-d *
    sqrt(2) <= ROUND_SHARE tol, and that r."""
    d = max(0, int(math.ceil(math.log10(0.5 * math.sqrt(2.0) / (ROUND_SHARE * tol)))))
    return d, 0.5 * math.sqrt(2.0) * 10.0 ** -d


def _fmt(v, d):
    s = "%.*f" % (d, v)
    if "." in s:
        s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def svg_path_data(loops, tol):
    """SVG ``d`` string of a region (y flipped to SVG's y-down), within ``tol``.

    One subpath per loop: ``M`` at the start of its first Bézier (the loop's start,
    or the start of its last smooth run when cubics span the closing join), then
    ``L`` (lines), ``Q`` (polynomial quadratics), ``C`` (polynomial cubics, and the
    exported cubics of every other run of smooth joins,
    :func:`morph.export.loop_to_beziers` with ``wrap``), ``Z``; ``T`` / ``S`` where
    the first control point is the reflection of the previous one's last.  The written
    curves are within ``tol`` (absolute, region units; Fréchet distance) of the
    loop: certified cubic bound plus rounding, see the module docstring.

    Raises:
        ValueError: tol <= 0.
        ToleranceNotMetError: from the cubic export.
    """
    if not tol > 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    d, r = rounding(tol)

    def pt(p):
        return "%s %s" % (_fmt(p[0], d), _fmt(-p[1], d))

    parts = []
    loops = [loop for loop in loops if loop]
    # all loops fitted in one batch; each may start elsewhere than its first piece
    for beziers in loops_to_beziers(loops, tol - r, wrap=True):
        parts.append("M" + pt(beziers[0][0]))
        implied = _implied_controls(beziers, d)
        for b, short in zip(beziers, implied):
            if short:  # T / S: the first control point is the reflection of the last
                parts.append("TS"[len(b) - 3] + " ".join(pt(p) for p in b[2:]))
            else:
                parts.append("LQC"[len(b) - 2] + " ".join(pt(p) for p in b[1:]))
        parts.append("Z")
    return "".join(parts)


def fitted_regions(regions, tols):
    """Each region as the Béziers :func:`svg_path_data` writes for it at its
    tolerance in ``tols``, as a region of polynomial pieces (weights 1), all
    regions' loops fitted in one batch (:func:`morph.export.loops_to_beziers`: the
    searches of every loop go in lockstep, so a round's array calls serve all the
    regions; 10 frames of the bundled bird and butterfly convert in half the time
    of frame by frame).  The batch is fitted within the smallest ``tol - r`` of
    the regions (r the rounding of each one's tol, :func:`rounding`), so that
    :func:`svg_path_data` of a fitted region at its own tol writes its Béziers as
    they are (polynomial pieces of degree <= 3 are exact: no fit) and is within
    that tol of the region.

    Raises:
        ValueError: a tol <= 0.
    """
    import numpy as np

    tols = [float(t) for t in tols]
    if not all(t > 0 for t in tols):
        raise ValueError("tol must be positive, got %r" % (min(tols),))
    loops = [[loop for loop in region if loop] for region in regions]
    flat = [loop for region in loops for loop in region]
    if not flat:
        return [[] for _ in regions]
    fit_tol = min(t - rounding(t)[1] for t in tols)
    beziers = iter(loops_to_beziers(flat, fit_tol, wrap=True))
    return [[[np.column_stack([np.asarray(b, float), np.ones(len(b))])
              for b in next(beziers)] for _ in region] for region in loops]


def document_tol(shapes, tol=None, margin=0.05, bbox=None):
    """The path data's tolerance of :func:`svg_document`: ``tol``, or for None 1e-5
    of the frame's larger side."""
    if tol is not None:
        return tol
    x0, y0, x1, y1 = frame_bbox(normalize_shapes(shapes), bbox, margin)
    return 1e-5 * max(x1 - x0, y1 - y0)


def _implied_controls(beziers, d):
    """For each Bézier of a subpath: whether SVG's T (quadratic after a quadratic)
    or S (cubic after a cubic) writes it exactly, that is, whether its first control
    point rounded to d decimals is the reflection of the previous Bézier's last
    control point about their common point, all rounded to d decimals (compared as
    integers in units of 10^-d, so the reader's implied point is the one Q / C would
    have written).  TrueType outlines store such quadratics with implied on-curve
    points; a glyph's quadratics translated by a sum keep the property."""
    scale = 10.0 ** d

    def units(v):  # the written number (as _fmt rounds it) in units of 10^-d
        return round(float("%.*f" % (d, v)) * scale)

    out = [False] * len(beziers)
    for k in range(1, len(beziers)):
        prev, b = beziers[k - 1], beziers[k]
        if len(b) == len(prev) and len(b) in (3, 4):
            (x0, y0), (x1, y1), (x2, y2) = [(units(p[0]), units(-p[1]))
                                            for p in (prev[-2], b[0], b[1])]
            out[k] = (2 * x1 - x0, 2 * y1 - y0) == (x2, y2)
    return out


def _color(c):
    if c is None:
        return "none"
    if isinstance(c, str):
        return c
    c = tuple(int(v) for v in c)
    return "#%02x%02x%02x" % c[:3]


def svg_document(shapes, tol=None, margin=0.05, fill="black", stroke=None,
                 stroke_width=1.0, background=None, size=None, bbox=None):
    """SVG document text for shapes (see :mod:`morph.render` for the shapes forms).

    ``tol``: absolute tolerance of the path data in region units (None: 1e-5 of the
    frame's larger side).  ``margin``: fraction of the larger side added around the
    frame (``bbox`` or the shapes' union box).  ``size``: the longer side of the
    ``width``/``height`` attributes in px (default 512); ``stroke_width`` is in those
    px.  ``background``: a colour for a full-frame rectangle, None for none.
    Paths use ``fill-rule="nonzero"`` (regions are oriented).
    """
    items = normalize_shapes(shapes)
    x0, y0, x1, y1 = frame_bbox(items, bbox, margin)
    w, h = x1 - x0, y1 - y0
    side = max(w, h)
    tol = document_tol(shapes, tol, margin, bbox)
    size = 512 if size is None else size
    px_per_unit = size / side
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             '<svg xmlns="http://www.w3.org/2000/svg" version="1.1" '
             'width="%s" height="%s" viewBox="%s %s %s %s">'
             % (_fmt(w * px_per_unit, 3), _fmt(h * px_per_unit, 3),
                _fmt(x0, 9), _fmt(-y1, 9), _fmt(w, 9), _fmt(h, 9))]
    if background is not None:
        lines.append('<rect x="%s" y="%s" width="%s" height="%s" fill=%s/>'
                     % (_fmt(x0, 9), _fmt(-y1, 9), _fmt(w, 9), _fmt(h, 9),
                        quoteattr(_color(background))))
    for loops, style in items:
        f = style.get("fill", fill)
        s = style.get("stroke", stroke)
        sw = style.get("stroke_width", stroke_width) / px_per_unit
        attrs = 'fill=%s fill-rule="nonzero"' % quoteattr(_color(f))
        if s is not None:
            attrs += ' stroke=%s stroke-width="%s" stroke-linejoin="round"' % (
                quoteattr(_color(s)), _fmt(sw, 9))
        if "opacity" in style:
            attrs += ' opacity="%s"' % _fmt(style["opacity"], 4)
        lines.append('<path %s d="%s"/>' % (attrs, svg_path_data(loops, tol)))
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def write_svg(path, shapes, **kwargs):
    """Write :func:`svg_document` ``(shapes, **kwargs)`` to ``path``; returns path."""
    text = svg_document(shapes, **kwargs)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)
    return path
