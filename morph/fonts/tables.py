"""Font tables for fonts whose glyphs were replaced (brush, stroke): outlines, anchors,
metrics, names, saving.

Every function edits an open ``fontTools.ttLib.TTFont`` in place and works for
TrueType (``glyf``) and CFF (``CFF ``) fonts.  fontTools' own helpers are used where
they exist (``recalcAvgCharWidth``, ``recalcBounds``, the pens, ``TTFont.save`` with
``recalcBBoxes`` or ``maxp.recalc`` / ``hhea.recalc`` for head/hhea/maxp, the
``woff2`` flavor; :meth:`OutlineWriter.saving` keeps the glyphs not written as
stored); what fontTools has no helper for (moving GPOS anchors by glyph, renaming
a family coherently) is here.

Outlines travel as *contours*: lists of polynomial segments, each an ``(k, 2)``
float array of control points (k = 2 line, 3 quadratic, 4 cubic), first point of
each segment = last point of the previous one.  :func:`contours_from_loops` turns a
region of rational pieces into contours in the font's curve type and direction,
rounded to the integer grid and cleaned (:func:`clean_contour`: no zero-length
segment, no repeated point, no back-and-forth spike, so fontbakery's
``overlapping_path_segments`` has nothing to report).  Contours are plain arrays, so
a worker process can compute them and send them back (:mod:`morph.fonts.jobs`).
"""

import copy
import io
import re
from pathlib import Path

import numpy as np

from .. import bernstein as bz
from ..errors import MorphError, ParseError
from ..outline import Outline
from ..region import reverse_loop
from .cff_encoding import as_bounded, is_bounded
from .contours import draw_contours
from .glyf_headers import Header

__all__ = ["OutlineWriter", "outline_writer", "contours_from_loops", "contours_from_regions",
           "integer_outlines", "clean_contour",
           "outline_glyphs", "move_anchors", "grow_vertical_metrics",
           "rename_family", "finish_font", "save_font", "FONT_SUFFIXES"]

FONT_SUFFIXES = (".ttf", ".otf", ".woff2", ".woff")


# =========================================================================== outlines

def contours_from_loops(loops, tol, quadratic, offset=(0.0, 0.0), reverse=None,
                        splines=False):
    """Region (our loops: outer counter-clockwise) -> cleaned integer contours.

    Each piece is translated by ``offset``, converted within ``tol`` (font units) to
    quadratics (``quadratic``: TrueType, :func:`morph.export.loop_to_quadratics`) or
    cubics (CFF, :func:`morph.export.loop_to_beziers`), both certified, curves
    spanning the loop's smooth joins; lines stay lines.  TrueType contours are
    reversed (outer clockwise, the glyf convention) unless ``reverse`` is False (a
    UFO's quadratic contours keep ours: ufo2ft reverses them when it compiles);
    CFF keeps ours (outer counter-clockwise).  With ``splines`` (quadratic only)
    each converted cubic is one TrueType spline, its on-curve points between
    off-curve points implied.  Points are then rounded to integers (at most 0.71
    units more: an implied point is the midpoint of two rounded ones) and
    :func:`clean_contour` applied; contours that vanish are dropped.

    Raises:
        ToleranceNotMetError: as the converters.
    """
    return contours_from_regions([loops], tol, quadratic, [offset], reverse, splines)[0]


def contours_from_regions(regions, tol, quadratic, offsets=None, reverse=None,
                          splines=False):
    """:func:`contours_from_loops` of several regions (glyphs) at once: one
    :class:`Outline` (a sequence of contours) per region.  The loops of all regions
    are converted in one batch (:func:`morph.export.loops_to_beziers`: the segment
    searches of every loop go in lockstep and each round is fitted and certified
    with a few array calls), then rounded and cleaned together
    (:func:`integer_outlines`).  The fits are those of region by region up to
    rounding (batched array calls may round differently: callers that must be
    reproducible batch the same regions together every time).  ``offsets``: one
    per region (None: zero); ``reverse`` and ``splines`` as
    :func:`contours_from_loops`.

    Raises:
        ToleranceNotMetError: as the converters (for the whole batch).
    """
    from ..export import loops_to_beziers, loops_to_quadratics

    splines = splines and quadratic
    offsets = [(0.0, 0.0)] * len(regions) if offsets is None else offsets
    flip = quadratic if reverse is None else reverse
    loops = [reverse_loop(loop) if flip else loop for loops in regions for loop in loops]
    # cubics span the smooth joins
    converted = (loops_to_quadratics(loops, tol, wrap=True, splines=splines) if quadratic
                 else loops_to_beziers(loops, tol, wrap=True))
    return integer_outlines(converted, [len(r) for r in regions], offsets, quadratic,
                            splines)


def _same_rows(a, b):
    return (a[..., 0] == b[..., 0]) & (a[..., 1] == b[..., 1])


def _steps(frm, to):
    """:func:`_step` of rows."""
    d = to - frm
    n = np.abs(d).max(axis=-1, keepdims=True)
    out = d.copy()
    np.divide(d, n, out=out, where=n > 0)
    return np.where(n > 0, np.round(out), d)


def integer_outlines(converted, counts, offsets, quadratic, splines, spike=3.0):
    """The converted loops of several glyphs as :class:`Outline` objects, rounded
    and cleaned as :func:`clean_contour` cleans each contour, for all the glyphs'
    segments with a few array operations.

    ``converted``: one list of segments per loop (the converters' output), the
    loops of glyph g the next ``counts[g]``; ``offsets``: a translation per glyph;
    ``quadratic``: TrueType (else CFF: a quadratic segment is raised to a cubic,
    exactly); ``splines``: segments of 4 points or more are TrueType splines.

    The joins are set exact, every point rounded, zero-length segments dropped and
    segments simplified (:func:`_simplify_segment`) as arrays.  A contour that has
    something more to clean (collinear consecutive lines, a spike, fewer than three
    segments left, a spline whose rounded points repeat) is a rare defect: it is
    cleaned by :func:`clean_contour` itself, so the result is the same contour by
    contour.
    """
    c = _chunk_segments(converted, counts, offsets, quadratic, bool(splines and quadratic))
    _simplified_segments(c)
    _merged_lines(c, spike)
    return _glyph_outlines(c, counts, spike)


def _chunk_segments(converted, counts, offsets, quadratic, splines):
    """:func:`integer_outlines`' chunk as arrays: every segment's points moved by its
    glyph's offset, the joins exact and rounded (``r``), the raw points kept for
    :func:`clean_contour`; the loops of a rare defect marked ``slow_loop``."""
    from types import SimpleNamespace

    loops = [list(loop) for loop in converted]
    if not quadratic:
        for loop in loops:
            for k, q in enumerate(loop):
                if len(q) == 3:
                    loop[k] = bz.to_degree(np.asarray(q, float), 3)  # exact (CFF)
    c = SimpleNamespace(splines=splines)
    c.nloops = nloops = len(loops)
    loop_glyph = np.repeat(np.arange(len(counts)), counts)
    segs = [q for loop in loops for q in loop]
    c.nsegs = nsegs = len(segs)
    c.nseg_loop = np.fromiter(map(len, loops), np.int64, nloops)
    c.lens = lens = np.fromiter(map(len, segs), np.int64, nsegs)
    off = np.asarray(offsets, float).reshape(-1, 2)
    if segs:
        pts = np.concatenate([np.asarray(q, float).reshape(-1, 2) for q in segs])
        c.seg_loop = np.repeat(np.arange(nloops), c.nseg_loop)
        pts = pts + np.repeat(off[loop_glyph[c.seg_loop]], lens, axis=0)
    else:
        pts = np.zeros((0, 2))
        c.seg_loop = np.zeros(0, np.int64)
    c.raw = pts.copy()                          # for the contours clean_contour takes
    c.first = np.concatenate([[0], np.cumsum(lens)[:-1]]).astype(np.int64)[:nsegs]
    c.last = c.first + lens - 1
    c.loop_first = np.concatenate([[0], np.cumsum(c.nseg_loop)[:-1]]).astype(np.int64)
    # exact joins: a segment starts where the one before it (cyclically) ends
    prev = np.arange(nsegs) - 1
    starts_loop = c.loop_first[c.seg_loop] == np.arange(nsegs)
    prev[starts_loop] = (c.loop_first + c.nseg_loop - 1)[c.seg_loop[starts_loop]]
    if nsegs:
        pts[c.first] = pts[c.last[prev]]
    c.r = r = np.round(pts) + 0.0
    c.seg_of_pt = np.repeat(np.arange(nsegs), lens)
    c.slow_loop = np.zeros(nloops, bool)
    c.is_spline = (lens >= 4) & splines
    at = np.arange(len(r))
    c.inner_pt = (at != c.first[c.seg_of_pt]) & (at != c.last[c.seg_of_pt])
    if splines and len(r) > 1:
        repeat = np.zeros(len(r), bool)     # point i equals point i + 1 of its segment
        repeat[:-1] = _same_rows(r[1:], r[:-1]) & (at[:-1] != c.last[c.seg_of_pt[:-1]])
        rep_seg = np.logical_or.reduceat(repeat, c.first) if nsegs else repeat[:0]
        c.slow_loop[c.seg_loop[rep_seg & c.is_spline]] = True
    c.slow_loop[c.seg_loop[(lens > 4) & ~c.is_spline]] = True    # no such segment is written
    c.slow_loop[c.seg_loop[lens < 2]] = True
    return c


def _simplified_segments(c):
    """Zero-length segments (``c.zero``) and those whose control points all sit on
    an end, lines (``c.line``); cubics' retracted handles moved one unit
    (:func:`_simplify_segment`), in ``c.r``."""
    r, first, last, seg_of_pt = c.r, c.first, c.last, c.seg_of_pt
    if c.nsegs:
        at_first = _same_rows(r, r[first[seg_of_pt]])
        c.zero = np.logical_and.reduceat(at_first, first)
        off_ends = c.inner_pt & ~at_first & ~_same_rows(r, r[last[seg_of_pt]])
        has_inner = np.logical_or.reduceat(off_ends, first)
    else:
        c.zero = has_inner = np.zeros(0, bool)
    c.line = (c.lens == 2) | ~has_inner
    cubic = (c.lens == 4) & ~c.is_spline & ~c.zero & ~c.line
    if cubic.any():
        idx = first[cubic][:, None] + np.arange(4)
        s = r[idx]
        m = _same_rows(s[:, 1], s[:, 0])
        s[m, 1] = s[m, 0] + _steps(s[m, 0], s[m, 2])
        m = _same_rows(s[:, 2], s[:, 3])
        s[m, 2] = s[m, 3] + _steps(s[m, 3], s[m, 1])
        m = _same_rows(s[:, 1], s[:, 2])
        s[m, 2] = s[m, 2] + _steps(s[m, 2], s[m, 3])
        chord = (_same_rows(s[:, 0], s[:, 1]) | _same_rows(s[:, 1], s[:, 2])
                 | _same_rows(s[:, 2], s[:, 3]))
        r[idx] = s
        c.line[np.flatnonzero(cubic)[chord]] = True
        c.zero[np.flatnonzero(cubic)[chord & _same_rows(s[:, 0], s[:, 3])]] = True


def _merged_lines(c, spike):
    """The kept segments (``c.ks``, their loops ``c.kloop``) and those written
    (``c.kept_out``): a run of collinear lines is one line (its inner ends are not
    written); a run through the contour's start, or the whole contour, is left to
    clean_contour (``c.slow_loop``), and so is a spike, or one the merged lines
    make."""
    r, first, last, seg_loop, nloops = c.r, c.first, c.last, c.seg_loop, c.nloops
    kept = ~c.zero
    c.ks = ks = np.flatnonzero(kept)
    c.kloop = kloop = seg_loop[ks]
    nkept = np.bincount(kloop, minlength=nloops)
    c.slow_loop |= nkept < 3
    merged = ks
    if len(ks):
        kfirst = np.concatenate([[0], np.cumsum(nkept)[:-1]])
        pos = np.arange(len(ks)) - kfirst[kloop]
        nxt = np.where(pos + 1 < nkept[kloop], np.arange(len(ks)) + 1, kfirst[kloop])
        a, b = ks, ks[nxt]
        a0, a1, b0, b1 = r[first[a]], r[last[a]], r[first[b]], r[last[b]]
        u, v = a1 - a0, b1 - b0
        collinear = (c.line[a] & c.line[b] & (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] == 0)
                     & (u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1] > 0))
        spiked = _same_rows(a0, b1) & (np.hypot(*(b0 - b1).T) <= spike)
        c.slow_loop[kloop[spiked]] = True
        wraps = collinear & (nxt <= np.arange(len(ks)))
        c.slow_loop[kloop[wraps]] = True
        c.slow_loop[np.bincount(kloop, ~collinear, minlength=nloops) < 3] = True
        merged = ks[collinear]
        ks2 = ks[~collinear]
        kloop2 = seg_loop[ks2]
        n2 = np.bincount(kloop2, minlength=nloops)
        if len(ks2):
            k2first = np.concatenate([[0], np.cumsum(n2)[:-1]])
            pos2 = np.arange(len(ks2)) - k2first[kloop2]
            before = np.where(pos2 > 0, np.arange(len(ks2)) - 1, k2first[kloop2] + n2[kloop2] - 1)
            after = np.where(pos2 + 1 < n2[kloop2], np.arange(len(ks2)) + 1, k2first[kloop2])
            a0, a1, b1 = r[last[ks2[before]]], r[last[ks2]], r[last[ks2[after]]]
            spiked = _same_rows(a0, b1) & (np.hypot(*(a1 - b1).T) <= spike)
            c.slow_loop[kloop2[spiked]] = True
    c.line[merged] = True
    c.kept_out = kept.copy()
    c.kept_out[merged] = False


def _glyph_outlines(c, counts, spike):
    """The :class:`Outline` of each glyph: the points written (a kept segment's
    after its first, a line's last only, and each fast contour's start), the slow
    contours cleaned by :func:`clean_contour`."""
    slow_loop, seg_loop, first, last, ks = c.slow_loop, c.seg_loop, c.first, c.last, c.ks
    fast_seg = c.kept_out & ~slow_loop[seg_loop]
    take = np.zeros(len(c.r), bool)
    whole = fast_seg & ~c.line
    take[c.inner_pt & whole[c.seg_of_pt]] = True
    take[last[fast_seg]] = True
    fk = ks[~slow_loop[c.kloop]] if len(ks) else ks
    if len(fk):
        lead = np.ones(len(fk), bool)
        lead[1:] = seg_loop[fk[1:]] != seg_loop[fk[:-1]]
        take[first[fk[lead]]] = True
    out_pts = c.r[take]
    out_sizes = np.where(c.line, 1, c.lens - 1)[fast_seg]
    fast_loop = ~slow_loop & (c.nseg_loop > 0)
    loop_npts = np.zeros(c.nloops, np.int64)
    loop_npts[fast_loop] = 1 + np.bincount(seg_loop[fast_seg], out_sizes,
                                           minlength=c.nloops)[fast_loop].astype(np.int64)
    loop_nseg = np.bincount(seg_loop[fast_seg], minlength=c.nloops)
    pt_at = np.concatenate([[0], np.cumsum(loop_npts)])
    sz_at = np.concatenate([[0], np.cumsum(loop_nseg)])
    out = []
    loop_at = 0
    for n in counts:
        lo, hi = loop_at, loop_at + n
        loop_at = hi
        if not slow_loop[lo:hi].any():
            keep = np.flatnonzero(fast_loop[lo:hi]) + lo
            out.append(Outline(out_pts[pt_at[lo]:pt_at[hi]], out_sizes[sz_at[lo]:sz_at[hi]],
                               loop_nseg[keep]))
            continue
        contours = []
        for k in range(lo, hi):
            if fast_loop[k]:
                contours.append(Outline(out_pts[pt_at[k]:pt_at[k + 1]],
                                        out_sizes[sz_at[k]:sz_at[k + 1]], [loop_nseg[k]])[0])
            elif slow_loop[k]:
                a0 = c.loop_first[k]
                contour = clean_contour([c.raw[first[j]:last[j] + 1]
                                         for j in range(a0, a0 + c.nseg_loop[k])],
                                        spike=spike, splines=c.splines)
                if contour:
                    contours.append(contour)
        out.append(Outline.from_contours(contours))
    return out


def _same(a, b):
    return a[0] == b[0] and a[1] == b[1]


def _step(frm, to):
    """The integer unit step (each coordinate -1, 0 or 1) from ``frm`` toward ``to``."""
    d = to - frm
    n = np.abs(d).max()
    return np.round(d / n) if n > 0 else d


def _exact_joins(segs):
    """The segments (copies) with each start set to the end of the segment before
    it, cyclically: joins equal exactly, not within float noise."""
    segs = [np.array(q, float) for q in segs]
    for k in range(len(segs)):
        segs[k][0] = segs[k - 1][-1]
    return segs


def _rounded_segments(segs, splines):
    """The segments rounded to integers and simplified (:func:`_simplify_segment`,
    zero-length ones dropped); with ``splines`` a spline whose rounded points would
    repeat becomes its quadratics (:func:`_spline_quadratics`), each rounded once."""
    work = []
    for s in segs:
        s = np.asarray(s, float)
        parts = [s]
        if splines and len(s) >= 4:
            r = np.round(s)
            if any(_same(a, b) for a, b in zip(r, r[1:])):
                parts = _spline_quadratics(s)
        for q in parts:
            q = _simplify_segment(np.round(q) + 0.0, spline=splines and len(q) >= 4)
            if q is not None:
                work.append(q)
    return work


def _spline_quadratics(s):
    """The quadratics of a TrueType spline (end points, off-curve points), with their
    implied on-curve points (midpoints) explicit: (3, 2) arrays, unrounded."""
    offs = s[1:-1]
    ons = [s[0]] + [0.5 * (offs[i] + offs[i + 1]) for i in range(len(offs) - 1)] + [s[-1]]
    return [np.array([ons[i], off, ons[i + 1]]) for i, off in enumerate(offs)]


def _simplify_segment(s, spline=False):
    """A rounded segment whose consecutive points all differ; None if it has zero length.

    A quadratic whose control point coincides with an end point is a line.  A cubic
    with both handles retracted is a line; a single retracted handle (or two equal
    handles) is moved one unit toward the next control point, which moves the curve
    by at most 4/9 unit; a cubic so short that this still leaves two equal points
    becomes its chord (None when its ends are equal: a loop of a unit or two).
    """
    if all(_same(q, s[0]) for q in s[1:]):
        return None
    if len(s) == 2:
        return s
    inner = [q for q in s[1:-1] if not (_same(q, s[0]) or _same(q, s[-1]))]
    if not inner:
        return np.array([s[0], s[-1]])
    if len(s) == 3 or spline:
        return s    # a spline's rounded points all differ (clean_contour checked)
    s = s.copy()
    if _same(s[1], s[0]):
        s[1] = s[0] + _step(s[0], s[2])
    if _same(s[2], s[3]):
        s[2] = s[3] + _step(s[3], s[1])
    if _same(s[1], s[2]):
        s[2] = s[2] + _step(s[2], s[3])
    if any(_same(a, b) for a, b in zip(s, s[1:])):  # a curve of a unit or two: its chord
        return None if _same(s[0], s[-1]) else np.array([s[0], s[-1]])
    return s


def _collinear_lines(a, b):
    """Two consecutive line segments on one straight line, same direction."""
    u, v = a[1] - a[0], b[1] - b[0]
    return u[0] * v[1] - u[1] * v[0] == 0 and u[0] * v[0] + u[1] * v[1] > 0


def clean_contour(segs, spike=3.0, splines=False):
    """Round a closed contour's segments to integers and remove what fonts must not have.

    ``segs``: polynomial segments (``(k, 2)`` arrays), each starting where the
    previous one ends, the last ending at the first's start, up to float noise
    (converted segments meet within ~1e-12): each join is taken from the end of
    the segment before it, so it is rounded once (rounded from its two sides, a
    join at x.5 +- 1e-12 fell on two integers and broke the chain).  Returns a list
    of integer-valued ``(k, 2)`` arrays, possibly empty, where:

    - no segment has zero length (all points equal) and no control point repeats an
      end point (a quadratic whose control point coincides with an end becomes a line,
      so no two consecutive points of the written contour are equal);
    - consecutive collinear lines are merged (one segment, no redundant point);
    - a segment followed by its reverse between the same two points (a spike p -> q
      -> p shorter than ``spike`` units, left when rounding collapses a tiny cusp or
      fold) is removed, so no two segments share both end points (fontbakery
      ``overlapping_path_segments``);
    - fewer than 2 segments, or two segments forming a zero-area lens: nothing.

    A change moves the outline by at most ``spike`` units, only at such defects.
    With ``splines``, segments of 4 points or more are TrueType splines (end points,
    off-curve points, the on-curve points between them implied); one whose rounded
    points would repeat is written as its quadratics with explicit on-curve points,
    each rounded once.
    """
    work = _rounded_segments(_exact_joins(segs), splines)
    changed = True
    while changed and work:
        work, changed = _merge_and_despike(work, spike)
    if len(work) < 2 or (len(work) == 2 and len(work[0]) == 2 and len(work[1]) == 2):
        return []
    # the segments must still chain (spike removal joins p .. p)
    for a, b in zip(work, work[1:] + work[:1]):
        if not _same(a[-1], b[0]):  # pragma: no cover - exact joins, each step keeps them
            raise MorphError("contour cleaning broke the chain at %s" % (a[-1].tolist(),))
    return work


def _merge_and_despike(work, spike):
    """One pass of :func:`clean_contour` over rounded segments: consecutive collinear
    lines merged, p -> q -> p spikes shorter than ``spike`` removed, the closing
    join (last segment -> first) included.  Returns (segments, whether anything
    changed)."""
    changed = False
    out = []
    for s in work:
        if out and len(s) == 2 and len(out[-1]) == 2 and _collinear_lines(out[-1], s):
            out[-1] = np.array([out[-1][0], s[1]])
            changed = True
            continue
        if (out and _same(out[-1][0], s[-1]) and _same(out[-1][-1], s[0])
                and np.hypot(*(s[0] - s[-1])) <= spike):
            out.pop()  # p -> q -> p spike
            changed = True
            continue
        out.append(s)
    if len(out) >= 2:
        a, b = out[-1], out[0]
        if len(a) == 2 and len(b) == 2 and _collinear_lines(a, b):
            out[0] = np.array([a[0], b[1]])
            out.pop()
            changed = True
        elif (_same(a[0], b[-1]) and _same(a[-1], b[0])
              and np.hypot(*(b[0] - b[-1])) <= spike and len(out) > 2):
            out = out[1:-1]
            changed = True
    return out, changed


class OutlineWriter:
    """Writes glyph outlines into a font: ``pen(advance)``, draw, ``store(name, pen)``.

    ``quadratic`` tells the curve type (TrueType glyf: True; CFF: False).  ``store``
    returns the new left side bearing (the outline's xMin; 0 for an empty glyph).
    """

    quadratic = None

    def pen(self, advance):  # pragma: no cover - interface
        raise NotImplementedError

    def store(self, name, pen):  # pragma: no cover - interface
        raise NotImplementedError

    def write(self, name, contours, advance):
        """Draw ``contours`` as glyph ``name`` with ``advance``; return its lsb."""
        pen = self.pen(advance)
        draw_contours(pen, contours, self.quadratic)
        return self.store(name, pen)

    def write_many(self, glyphs):
        """:meth:`write` of several ``(name, contours, advance)``; their lsbs."""
        return [self.write(*g) for g in glyphs]

    def saving(self):
        """A context for the font's save: the bounds of the glyphs not written found
        without decoding them again where the writer can (a context doing nothing
        by default)."""
        import contextlib

        return contextlib.nullcontext()


class _TrueTypeOutlines(OutlineWriter):
    """``glyf`` table (quadratic contours, TTGlyphPen; :meth:`write_many` builds
    the same glyphs from point arrays)."""

    quadratic = True

    def __init__(self, font):
        self.font = font
        self.glyf = font["glyf"]
        self.glyph_set = None   # the pens', made on first use

    def pen(self, advance):
        from fontTools.pens.ttGlyphPen import TTGlyphPen

        if self.glyph_set is None:
            self.glyph_set = self.font.getGlyphSet()
        return TTGlyphPen(self.glyph_set)

    def write_many(self, glyphs):
        """:meth:`write` of several glyphs: the glyph bytes ``TTGlyphPen`` and
        ``Glyph.compile`` make of the drawn contours, encoded from the outlines'
        point arrays for all glyphs at once
        (:func:`morph.fonts.stream.compile_glyf`) rather than drawn point by point
        and compiled glyph by glyph; a glyph whose contours the pen would trim (a
        contour of fewer than two points, or closing on a repeated point), or
        which the arrays do not take, is drawn."""
        from fontTools.ttLib.tables._g_l_y_f import Glyph

        from .stream import compile_glyf

        outlines = [Outline.from_contours(c) for _, c, _ in glyphs]
        drawn = _pen_draws(outlines)
        lsbs = []
        for (name, contours, advance), made, draw in zip(glyphs, compile_glyf(outlines, False),
                                                         drawn):
            if draw or made is None:
                lsbs.append(self.write(name, contours, advance))
                continue
            self.glyf[name] = Glyph(made[0])   # its box in its header, as recalcBounds'
            lsbs.append(made[1][0] if made[1] else 0)
        return lsbs

    def store(self, name, pen):
        return self._put(name, pen.glyph())

    def saving(self):
        """The save with ``recalcBBoxes`` off, maxp, head's box and hhea computed
        first as fontTools' save computes them (``maxp.recalc``, ``hhea.recalc``),
        each glyph not written read from its stored header (:class:`_StoredGlyphs`):
        the save would decode and compile every glyph of the font again, not always
        to the same bytes; the glyphs written are compiled with their bounds set
        where they were stored (``recalcBounds``), and the composites that follow
        them where they moved (:func:`morph.fonts.brush._follow_composites`)."""
        import contextlib

        font = self.font
        view = _HeaderView(font, _StoredGlyphs(self.glyf))
        font["maxp"].recalc(view)
        font["hhea"].recalc(view)

        @contextlib.contextmanager
        def bounds_known():
            old = font.recalcBBoxes
            font.recalcBBoxes = False
            try:
                yield
            finally:
                font.recalcBBoxes = old
        return bounds_known()

    def _put(self, name, g):
        self.glyf[name] = g
        g.recalcBounds(self.glyf)
        return int(getattr(g, "xMin", 0)) if g.numberOfContours else 0


class _StoredGlyphs:
    """A glyf table as fontTools' ``maxp.recalc`` and ``hhea.recalc`` read it: a
    glyph still held as its stored bytes is read from them without decoding its
    points (a simple glyph's header and point count,
    :class:`morph.fonts.glyf_headers.Header`; a composite decoded apart, its
    components only), the others as they are."""

    def __init__(self, glyf):
        self.glyf = glyf

    def __len__(self):
        return len(self.glyf)

    def __getitem__(self, name):
        from fontTools.ttLib.tables._g_l_y_f import Glyph


        g = self.glyf.glyphs[name]
        data = getattr(g, "data", None)
        if not data:
            return g
        if int.from_bytes(data[:2], "big", signed=True) >= 0:
            return Header(data)
        g = Glyph(data)
        g.expand(self.glyf)
        return g


class _HeaderView:
    """The font as ``maxp.recalc`` and ``hhea.recalc`` read it, its glyf table a
    :class:`_StoredGlyphs`."""

    def __init__(self, font, glyf):
        self.font, self.glyf = font, glyf

    def __contains__(self, tag):
        return tag in self.font

    def __getitem__(self, tag):
        return self.glyf if tag == "glyf" else self.font[tag]

    def getGlyphOrder(self):
        return self.font.getGlyphOrder()


def _pen_draws(outlines):
    """Per outline whether :meth:`_TrueTypeOutlines.write_many` draws it with the
    pen: an empty outline, or one with a contour ``TTGlyphPen`` would trim (fewer
    than two points without its closing point, or a closing point repeated)."""
    if not outlines:
        return []
    points = np.concatenate([o.points for o in outlines]).astype(np.int64)
    sizes = np.concatenate([o.sizes for o in outlines])
    counts = np.concatenate([o.counts for o in outlines])
    per_glyph = np.array([len(o.counts) for o in outlines])
    seg_contour = np.repeat(np.arange(len(counts)), counts)
    n = np.bincount(seg_contour, sizes, minlength=len(counts)).astype(np.int64)
    end = np.cumsum(n + 1) - 1                 # each contour's closing point
    start = end - n
    last_line = sizes[np.cumsum(counts) - 1] == 1
    closes = (points[end] == points[start]).all(axis=1)
    trimmed = ((n < 2) | (last_line & (points[end - 1] == points[start]).all(axis=1))
               | (~last_line & ~closes))
    glyph_of = np.repeat(np.arange(len(outlines)), per_glyph)
    bad = np.bincount(glyph_of[trimmed], minlength=len(outlines)) > 0
    return (bad | (per_glyph == 0)).tolist()


#: glyphs whose bounds :meth:`_CFFOutlines.saving` reads at once: a few MB of outline
#: arrays at most, and a few array calls per batch
BOUNDS_BATCH = 1024


class _CFFOutlines(OutlineWriter):
    """``CFF `` table (Type 2 charstrings, cubic, T2CharStringPen).

    Every charstring answers ``calcBounds`` with bounds computed once
    (:func:`morph.fonts.cff_encoding.as_bounded`): the save asks each glyph for
    them twice (the CFF font box and hhea), which drew every glyph in Python; a
    written glyph's are its new program's, the others' (:meth:`saving`)
    those of a copy, so that they keep their source bytes (a charstring fontTools
    decompiles is compiled again, not always to the same bytes)."""

    quadratic = False

    def __init__(self, font):
        from .deferred import cff_table

        self.cff = cff_table(font).cff
        top = self.cff.topDictIndex[0]
        self.char_strings = top.CharStrings
        self.private = top.Private
        self.nominal = getattr(self.private, "nominalWidthX", 0) or 0

    def pen(self, advance):
        from fontTools.pens.t2CharStringPen import T2CharStringPen

        return T2CharStringPen(advance - self.nominal, None)

    def write(self, name, contours, advance):
        """Draw ``contours`` as glyph ``name``; its bounds are those of the same
        points drawn into fontTools' bounds pen in the same order (what
        ``calcBounds`` of the new charstring computes, without decoding it)."""
        from fontTools.pens.boundsPen import BoundsPen

        bounds_pen = BoundsPen(None)
        draw_contours(bounds_pen, contours, self.quadratic)
        pen = self.pen(advance)
        draw_contours(pen, contours, self.quadratic)
        return self._put(name, pen, bounds_pen.bounds)

    def store(self, name, pen):
        cs = pen.getCharString(private=self.private, globalSubrs=self.cff.GlobalSubrs)
        return self._put(name, pen, cs.calcBounds(self.char_strings), cs)

    def _put(self, name, pen, bounds, cs=None):

        if cs is None:
            cs = pen.getCharString(private=self.private, globalSubrs=self.cff.GlobalSubrs)
        self.char_strings[name] = as_bounded(cs, bounds)
        return int(np.floor(bounds[0])) if bounds else 0

    def saving(self):
        """The charstrings not written answer ``calcBounds`` with their bounds,
        read from their bytes :data:`BOUNDS_BATCH` glyphs at a time (the outlines
        of one batch in memory, not the font's)
        (:func:`morph.parse.charstrings.charstring_outlines`, the boxes by
        :func:`morph.fonts.stream.outline_bounds`, ``BoundsPen``'s arithmetic); one
        the reader does not take, with those of a copy drawn by fontTools (the
        charstring keeps its bytes, compiled as they are).  The save recomputes
        the font's boxes from them as usual."""
        import contextlib

        from ..parse.charstrings import charstring_outlines
        from .stream import outline_bounds

        todo = [cs for cs in map(self.char_strings.__getitem__, self.char_strings.keys())
                if not is_bounded(cs)]
        for at in range(0, len(todo), BOUNDS_BATCH):
            batch = todo[at:at + BOUNDS_BATCH]
            outlines = charstring_outlines(batch)
            read = iter(outline_bounds([o for o in outlines if o is not None]))
            for cs, outline in zip(batch, outlines):
                bounds = (copy.copy(cs).calcBounds(self.char_strings) if outline is None
                          else next(read))
                as_bounded(cs, bounds)
        return contextlib.nullcontext()


def outline_writer(font):
    """The :class:`OutlineWriter` of a TrueType or CFF font.

    Raises:
        ValueError: a variable font (instantiate it first,
            :func:`morph.parse.instantiate_font`).
        ParseError: CFF2 or no outlines (``.source`` names the font).
    """
    if "fvar" in font:
        raise ValueError("instantiate the variable font first (morph.parse.instantiate_font)")
    if "glyf" in font:
        return _TrueTypeOutlines(font)
    if "CFF " in font:
        return _CFFOutlines(font)
    from ..parse import font_display_name

    label = font_display_name(font, "")
    raise ParseError("font %s has neither TrueType (glyf) nor CFF outlines" % label, label)


def outline_glyphs(font):
    """Names of the glyphs drawn by their own contours, in glyph order.

    TrueType: simple glyphs with at least one contour (composites are left to
    follow their components, see :func:`morph.fonts.brush.composite_plan`);
    CFF: glyphs whose charstring draws something.
    """
    if "glyf" in font:
        glyphs = _StoredGlyphs(font["glyf"])   # headers: no glyph decoded to ask
        return [n for n in font.getGlyphOrder() if glyphs[n].numberOfContours > 0]
    from fontTools.pens.boundsPen import ControlBoundsPen

    gs = font.getGlyphSet()
    names = []
    for n in font.getGlyphOrder():
        pen = ControlBoundsPen(gs)
        gs[n].draw(pen)
        if pen.bounds is not None:
            names.append(n)
    return names


# =========================================================================== anchors

#: GPOS lookup types whose subtables hold anchors: cursive, mark-to-base,
#: mark-to-ligature, mark-to-mark (:data:`_ANCHOR_MOVERS`); 9 is the extension
_ANCHOR_LOOKUPS, _EXTENSION = frozenset((3, 4, 5, 6)), 9


def _stored(font, tag):
    """The table's bytes as the font file stores them, or None when the table is
    decompiled already (or the font was not read from a file)."""
    if font.isLoaded(tag) or font.reader is None or tag not in font.reader:
        return None
    return font.reader[tag]


def _no_anchors(font):
    """True when the font's GPOS has no lookup holding anchors, read from its stored
    bytes (lookup types, and an extension's type): the table is then left as stored,
    not decompiled and compiled again (about 0.1 G instructions for Noto Sans's
    kerning, and the OpenType layout classes and HarfBuzz's packer loaded for it)."""
    import struct

    data = _stored(font, "GPOS")
    if data is None:
        return "GPOS" not in font
    try:
        lookups = struct.unpack_from(">H", data, 8)[0]
        if not lookups:
            return True
        for at in struct.unpack_from(">%dH" % struct.unpack_from(">H", data, lookups)[0],
                                     data, lookups + 2):
            lookup = lookups + at
            kind, _, count = struct.unpack_from(">3H", data, lookup)
            if kind == _EXTENSION:
                kinds = {struct.unpack_from(">H", data, lookup + sub + 2)[0] for sub in
                         struct.unpack_from(">%dH" % count, data, lookup + 6)}
            else:
                kinds = {kind}
            if kinds & _ANCHOR_LOOKUPS:
                return False
    except struct.error:  # a truncated table: fontTools reads (and reports) it
        return False
    return True


def _no_carets(font):
    """True when the font has no GDEF ligature caret list, read from GDEF's stored
    bytes (its header's LigCaretList offset) where it is not decompiled."""
    data = _stored(font, "GDEF")
    if data is None:
        return "GDEF" not in font
    return len(data) >= 10 and data[8:10] == b"\0\0"


def _lookup_subtables(font, tag="GPOS"):
    if tag not in font or font[tag].table.LookupList is None:
        return
    for lookup in font[tag].table.LookupList.Lookup:
        for st in lookup.SubTable:
            if getattr(st, "ExtSubTable", None) is not None:  # Extension (type 9)
                st = st.ExtSubTable
            yield st


def _moved(anchor, d):
    """A copy of ``anchor`` moved by d (format 2 contour points become format 1: the
    points were renumbered)."""
    if anchor is None:
        return None
    a = copy.copy(anchor)
    a.XCoordinate = int(round(a.XCoordinate + d[0]))
    a.YCoordinate = int(round(a.YCoordinate + d[1]))
    if a.Format == 2:
        a.Format = 1
        del a.AnchorPoint
    return a


def _move_records(glyphs, records, attrs, offsets):
    """Move the anchors ``attrs`` (an anchor or a list of anchors each) of the records
    of the glyphs that have an offset; the number of anchors moved."""
    moved = 0
    for g, rec in zip(glyphs, records):
        d = offsets.get(g)
        if not d:
            continue
        for attr in attrs:
            value = getattr(rec, attr)
            if isinstance(value, list):
                setattr(rec, attr, [_moved(a, d) for a in value])
                moved += len(value)
            else:
                setattr(rec, attr, _moved(value, d))
                moved += 1
    return moved


def _marks(st, offsets):
    """The marks' own anchors of a mark-to-base, -ligature or -mark subtable."""
    if type(st).__name__ == "MarkMarkPos":
        return _move_records(st.Mark1Coverage.glyphs, st.Mark1Array.MarkRecord,
                             ("MarkAnchor",), offsets)
    return _move_records(st.MarkCoverage.glyphs, st.MarkArray.MarkRecord, ("MarkAnchor",),
                         offsets)


def _bases(st, offsets):
    return _move_records(st.BaseCoverage.glyphs, st.BaseArray.BaseRecord, ("BaseAnchor",),
                         offsets)


def _mark2s(st, offsets):
    """The anchors a mark offers to other marks."""
    return _move_records(st.Mark2Coverage.glyphs, st.Mark2Array.Mark2Record, ("Mark2Anchor",),
                         offsets)


def _ligatures(st, offsets):
    return sum(_move_records([g] * len(att.ComponentRecord), att.ComponentRecord,
                             ("LigatureAnchor",), offsets)
               for g, att in zip(st.LigatureCoverage.glyphs, st.LigatureArray.LigatureAttach))


def _cursive(st, offsets):
    return _move_records(st.Coverage.glyphs, st.EntryExitRecord, ("EntryAnchor", "ExitAnchor"),
                         offsets)


#: GPOS subtable type -> the functions moving its anchors
_ANCHOR_MOVERS = {"MarkBasePos": (_marks, _bases), "MarkLigPos": (_marks, _ligatures),
                  "MarkMarkPos": (_marks, _mark2s), "CursivePos": (_cursive,)}


def _move_carets(font, offsets):
    """GDEF ligature carets placed by a coordinate (formats 1 and 3) move in x."""
    gdef = font["GDEF"].table if "GDEF" in font else None
    carets = getattr(gdef, "LigCaretList", None)
    if carets is None:
        return
    for g, lig in zip(carets.Coverage.glyphs, carets.LigGlyph):
        d = offsets.get(g)
        if d:
            for cv in lig.CaretValue:
                if cv.Format in (1, 3):
                    cv.Coordinate = int(round(cv.Coordinate + d[0]))


def move_anchors(font, offsets):
    """Move the GPOS anchors (and GDEF ligature carets) of glyphs by their offsets.

    ``offsets``: glyph name -> (dx, dy) font units, the translation that glyph's
    marks must follow (for a swept glyph: the image of its pen point, see
    :func:`morph.fonts.brush.brush_font`).  Mark-to-base, mark-to-ligature,
    mark-to-mark (both the mark's own anchor and the anchors it offers to other
    marks) and cursive entry/exit anchors are moved; each anchor is replaced by a
    moved copy, so anchors shared between glyphs move once per glyph.  Format 2
    anchors (on a contour point) become format 1: swept outlines renumber their
    points.  Returns the number of anchors moved.  A GPOS without anchor lookups and a
    GDEF without carets are left as stored (:func:`_no_anchors`, :func:`_no_carets`).
    """
    moved = 0
    if not _no_anchors(font):
        for st in _lookup_subtables(font):
            for mover in _ANCHOR_MOVERS.get(type(st).__name__, ()):
                moved += mover(st, offsets)
    if not _no_carets(font):
        _move_carets(font, offsets)
    return moved


# =========================================================================== metrics

def grow_vertical_metrics(font, below, above):
    """Grow the font's vertical metrics by ``above`` / ``below`` font units (>= 0).

    For glyphs that grew by at most that much up and down (a nib's extent above and
    below its pen point): hhea ascender / descender and OS/2 typo ascender /
    descender (kept equal to each other when they were), OS/2 win ascent / descent
    (so nothing is clipped where the source was not), x height and cap height (the
    flat tops of x and H rise by ``above``).
    """
    up, down = int(np.ceil(max(above, 0.0))), int(np.ceil(max(below, 0.0)))
    hhea = font["hhea"]
    hhea.ascent += up
    hhea.descent -= down
    if "OS/2" in font:
        os2 = font["OS/2"]
        os2.sTypoAscender += up
        os2.sTypoDescender -= down
        os2.usWinAscent += up
        os2.usWinDescent += down
        if getattr(os2, "version", 0) >= 2:
            if os2.sxHeight:
                os2.sxHeight += up
            if os2.sCapHeight:
                os2.sCapHeight += up


# =========================================================================== names

_RIBBI = ("Regular", "Bold", "Italic", "Bold Italic")


def _ps(text):
    return re.sub(r"[^A-Za-z0-9]", "", text)


def rename_family(font, family, tool="morph"):
    """Give the font a new family name, with name IDs 1/2/3/4/6/16/17/21/25 coherent.

    The style is the source's typographic subfamily (ID 17, else ID 2).  A RIBBI
    style (Regular, Bold, Italic, Bold Italic): ID 1 = family, ID 2 = style, IDs 16/17
    removed.  Any other style (e.g. "Medium"): ID 1 = "family style", ID 2 = Regular
    or Italic, ID 16 = family, ID 17 = style.  ID 4 = "family style", ID 6 =
    "Family-Style" (PostScript characters only), ID 3 = "revision;tool;ID 6", ID 25
    (variations PostScript prefix) and ID 21 (WWS family) follow the family where the
    source had them.  CFF FontName, FamilyName and FullName follow.  Records are
    written on every platform/encoding/language the source used for ID 1.
    """
    from ..parse.names import name_keys, name_table, set_names

    name = name_table(font, install=True)
    style = (name.getDebugName(17) or name.getDebugName(2) or "Regular").strip()
    ps_family = _ps(family)
    ps = "%s-%s" % (ps_family, _ps(style) or "Regular")
    full = "%s %s" % (family, style)
    if style in _RIBBI:
        ids = {1: family, 2: style}
        drop = (16, 17)
    else:
        legacy = "Italic" if "Italic" in style.split() else "Regular"
        ids = {1: "%s %s" % (family, style.replace(" Italic", "").replace("Italic", "")
                              .strip()), 2: legacy, 16: family, 17: style}
        drop = ()
    rev = "%.3f" % font["head"].fontRevision
    ids.update({3: "%s;%s;%s" % (rev, tool, ps), 4: full, 6: ps})
    keys = name_keys(name)
    for nid, text in ((21, family), (25, ps_family)):
        if any(k[3] == nid for k in keys):
            ids[nid] = text
    where = {k[:3] for k in keys if k[3] == 1} or {(3, 1, 0x409)}
    set_names(name, ids, where, drop)
    if "CFF " in font:
        cff = font["CFF "].cff
        cff.fontNames = [ps]
        top = cff.topDictIndex[0]
        top.FamilyName = family
        top.FullName = full
    return ps


# =========================================================================== saving

def finish_font(font):
    """Table clean-up after outlines and advances changed.

    OS/2 xAvgCharWidth recomputed (fontTools ``recalcAvgCharWidth``); tables that
    cache per-size metrics of the old outlines (hdmx, LTSH, VDMX) are dropped.  Bounds
    in head/hhea/maxp are recomputed at the save (:meth:`OutlineWriter.saving`, then
    :func:`save_font`).
    """
    for tag in ("hdmx", "LTSH", "VDMX"):
        if tag in font:
            del font[tag]
    if "OS/2" in font:
        font["OS/2"].recalcAvgCharWidth(font)


def save_atomically(path, write, overwrite=True):
    """Write an output as a whole or not at all: ``write(tmp)`` writes it to a
    temporary name in the output's folder (a file, or a folder such as a UFO), which
    then replaces ``path``; a failure leaves what was there.  The one save of the
    font writers (brush, stroke).  Returns the path.

    Raises:
        MorphError: ``path`` exists and ``overwrite`` is false.
    """
    import os
    import shutil
    import tempfile

    from ..errors import MorphError

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp_dir = tempfile.mkdtemp(prefix=".morph-", dir=str(path.parent))
    tmp = Path(tmp_dir) / path.name
    try:
        write(tmp)
        if path.exists():
            if not overwrite:
                raise MorphError("%s exists" % path)
            if path.is_dir():
                shutil.rmtree(path)
            else:
                path.unlink()
        os.replace(str(tmp), str(path))
    finally:
        shutil.rmtree(tmp_dir, ignore_errors=True)
    return path


def save_font(font, path):
    """Save to ``path`` (:func:`save_atomically`); ``.woff2`` / ``.woff`` suffixes save
    that web flavor.

    ``.woff2`` needs the brotli package.  Returns the path.

    Raises:
        ValueError: an unknown suffix.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FONT_SUFFIXES:
        raise ValueError("cannot tell the font format of %s: use %s"
                         % (path, ", ".join(FONT_SUFFIXES)))
    flavor = {".woff2": "woff2", ".woff": "woff"}.get(suffix)
    old = font.flavor
    font.flavor = flavor
    try:
        save_atomically(path, lambda tmp: _save(font, str(tmp)))
    finally:
        font.flavor = old
    return path


#: tables whose fontTools class depends on no other table (its ``dependencies``) and
#: whose module loads the OpenType layout classes and HarfBuzz's packer (about 0.19
#: G instructions): a save writes them as stored, where they are, without it
_LAYOUT_TAGS = frozenset(("GDEF", "GPOS", "GSUB", "STAT", "BASE", "JSTF", "MATH"))


def _written_as_is(font, tag):
    """The bytes the save writes for ``tag`` without importing its fontTools class, or
    None: a layout table not decompiled (:data:`_LAYOUT_TAGS`), a name table not
    decompiled or held as its records (:class:`morph.parse.names.NameTable`;
    fontTools' name table depends on ``ltag`` only)."""
    if tag in _LAYOUT_TAGS:
        return _stored(font, tag)
    if tag == "name" and "ltag" not in font:
        from ..parse.names import records_of

        table = font.tables.get("name")
        if table is None:
            return _stored(font, tag)
        if records_of(table) is not None:
            return table.compile(font)
    return None


def _save(font, file):
    """``font.save(file)``, the tables :func:`_written_as_is` tells written as those
    bytes, in the order fontTools writes them (``TTFont._writeTable``, which imports
    each table's class to read the tables it depends on, is bypassed for them)."""
    def write_table(tag, writer, done, *args, **kwargs):
        data = None if tag in done else _written_as_is(font, tag)
        if data is None:
            return type(font)._writeTable(font, tag, writer, done, *args, **kwargs)
        done.append(tag)
        writer[tag] = data
        return None

    font._writeTable = write_table
    try:
        font.save(file)
    finally:
        del font._writeTable


def font_bytes(font, flavor=None):
    """The font compiled to bytes (``flavor``: None, "woff" or "woff2")."""
    buf = io.BytesIO()
    old = font.flavor
    font.flavor = flavor
    try:
        _save(font, buf)
    finally:
        font.flavor = old
    return buf.getvalue()
