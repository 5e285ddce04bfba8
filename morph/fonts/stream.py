"""Streaming font building for ``morph stroke``: memory that does not grow with the
outlines of the font.

A stroked glyph leaves its worker process as *compiled* data, not as point objects:
:func:`compile_outline` turns its integer contours (:mod:`morph.fonts.tables`) into
the bytes the font will hold, a Type 2 charstring (CFF, without its advance) or a
``glyf`` glyph (TrueType direction), with its bounding box.  The main process keeps
those bytes in a temporary file (:class:`OutlineStore`: a few numbers a glyph in
memory) and the glyph's *shell*: a ufoLib2 glyph without contours (advance,
unicodes, anchors, kept components, lib).  At the end ufo2ft
compiles the shells, as it compiled the whole font before, with an outline compiler
that takes the stored bytes (:func:`compile_stored`): the names, metrics, cmap, OS/2,
kerning and mark features, GDEF and post tables come from ufo2ft as they did; the
glyph programs are the bytes ufo2ft would have made from the same contours, because
they are made by the same pens in the same order:

- CFF: ``T2CharStringPen``, specialized (ufo2ft's ``optimizeCFF``); the advance is
  prepended when the font's nominal and default widths are known
  (:func:`morph.fonts.cff_encoding.width_prefix`, what the pen does);
- TrueType: ``TTGlyphPen`` behind a contour reversal, as ufo2ft's
  cubic-to-quadratic filter reverses them (the contours are quadratic already).

Composites: a TrueType glyph of components only stays a composite (ufo2ft draws its
shell); a glyph with components and contours, and every CFF glyph with components,
is decomposed here as ufo2ft's ``DecomposeComponentsFilter`` does it (the glyph's
own contours, then each component's base drawn the same way, transformed), from
the stored outlines.

The source is read the same way (:class:`SkeletonSource`): one pass over the glyphs
for their shells, then each glyph's contours read again when its chunk is prepared,
and dropped (by the worker that strokes the chunk, :func:`worker_source`, when the
source is a UFO on disk and there are workers).  A UFO output is written glyph by glyph (:class:`UfoGlyphWriter`): the
shells are saved first by ufoLib2 (info, kerning, groups, features, lib, layers,
data), then each stroked glyph's ``.glif`` is rewritten as it arrives.  A compiled
font is saved by :func:`save_font`, table by table into its file (a table whose bytes
are in a file, :func:`file_table`, copied a chunk at a time): the bytes fontTools'
save writes, without its copies of the whole font in memory.
"""

import copy
import os
import re

import numpy as np

from .cff_encoding import _NO_WIDTHS
from .contours import draw_contours

__all__ = ["compile_outline", "compile_outlines", "outline_bounds",
           "SkeletonSource", "compile_stored", "UfoGlyphWriter", "shell_glyph", "sample_font",
           "worker_source", "OutlineStore", "save_font", "write_tables", "file_table",
           "table_checksum"]


# =========================================================================== worker side

def compile_outline(contours, flavor):
    """``(data, bounds)`` of integer contours (an :class:`morph.outline.Outline`,
    or the contour lists of :func:`morph.fonts.tables.clean_contour`) compiled for
    the font ufo2ft compiles from a UFO glyph holding those contours: see
    :func:`compile_outlines`, of which this is one glyph's."""
    return compile_outlines([contours], flavor)[0]


def compile_outlines(outlines, flavor):
    """:func:`compile_outline` of several glyphs: their point arrays are encoded
    together, with array operations, not drawn point by point.

    ``flavor``: ``"cff"`` (cubic contours; ``data`` a Type 2 charstring without the
    advance, see :func:`morph.fonts.cff_encoding.width_prefix`) or ``"glyf"``
    (quadratic splines in the UFO's direction; ``data`` the compiled ``glyf`` glyph,
    reversed).  ``bounds``: (xMin, yMin, xMax, yMax), None when empty: for CFF the
    outline's tight box (what ``BoundsPen`` and so the charstring's ``calcBounds``
    compute, the same arithmetic), for glyf the glyph's (integers).

    - glyf: the bytes fontTools' ``TTGlyphPen`` and ``Glyph.compile`` make of the
      contours drawn through a ``ReverseContourPen`` (ufo2ft's drawing);
    - CFF: the charstring ``T2CharStringPen`` makes unspecialized (one operator a
      segment: rmoveto, rlineto, rrcurveto).  ufo2ft's subroutinizer (cffsubr's
      ``tx``) rewrites every charstring of the font from its path, so the font
      written is the one the specialized charstrings gave, byte for byte; the
      specializer's Python was most of a glyph's compile time.

    Both are tested against the pens (tests/fonts/test_stream.py).  A glyph the
    arrays do not take (a coordinate beyond 16 bits, a segment the flavor cannot
    draw) is drawn with the pens, which raise what they raise.
    """
    from ..outline import Outline

    outlines = [Outline.from_contours(c) for c in outlines]
    if not outlines:
        return []
    both = _Batch(outlines)
    done = both.cff() if flavor == "cff" else both.glyf()
    return [d if d is not None else _compile_with_pens(o, flavor)
            for d, o in zip(done, outlines)]


def compile_glyf(outlines, reverse=True):
    """``_Batch.glyf`` of :class:`morph.outline.Outline` objects: [(``glyf`` glyph
    bytes, integer box) or None], each contour drawn reversed (``reverse``, the UFO's
    direction, as ufo2ft draws it) or as it is (an outline already in TrueType's
    direction), from its start point."""
    return _Batch(outlines).glyf(reverse) if outlines else []


def outline_bounds(outlines):
    """The tight boxes of cubic integer outlines (what :func:`compile_outlines`
    gives a CFF glyph), None for an empty one."""
    from ..outline import Outline

    outlines = [Outline.from_contours(c) for c in outlines]
    return _Batch(outlines)._cubic_bounds() if outlines else []


def _compile_with_pens(contours, flavor, optimize=False):
    """:func:`compile_outline` drawn with fontTools' pens (``optimize``: the CFF
    charstring specialized, as ufo2ft writes it before subroutinizing)."""
    from fontTools.misc.roundTools import otRound
    from fontTools.pens.recordingPen import RecordingPen

    outline = RecordingPen()
    draw_contours(outline, contours, flavor == "glyf")
    if flavor == "cff":
        from fontTools.pens.boundsPen import BoundsPen
        from fontTools.pens.t2CharStringPen import T2CharStringPen

        pen = T2CharStringPen(None, None, roundTolerance=0.5)
        outline.replay(pen)
        cs = pen.getCharString(_NO_WIDTHS, optimize=optimize)
        cs.compile()
        box = BoundsPen(None)
        outline.replay(box)
        return bytes(cs.bytecode), (None if box.bounds is None
                                    else tuple(float(v) for v in box.bounds))
    from fontTools.pens.reverseContourPen import ReverseContourPen
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    pen = TTGlyphPen(None)
    outline.replay(ReverseContourPen(pen))
    g = pen.glyph(dropImpliedOnCurves=False, round=otRound)
    if not g.numberOfContours:
        return b"", None
    g.recalcBounds(None)
    box = (g.xMin, g.yMin, g.xMax, g.yMax)
    return g.compile(None), (None if box == (0, 0, 0, 0) else box)


#: Type 2 operators
_RMOVETO, _RLINETO, _RRCURVETO, _ENDCHAR = 21, 5, 8, 14


def _firsts(counts):
    return np.cumsum(counts) - counts


def _packed(tokens, sizes):
    """The bytes of rows ``tokens`` (n, k), each its first ``sizes`` bytes."""
    return tokens[np.arange(tokens.shape[1]) < sizes[:, None]].astype(np.uint8).tobytes()


def _split(data, sizes):
    at = np.concatenate([[0], np.cumsum(sizes)]).tolist()
    return [data[a:b] for a, b in zip(at[:-1], at[1:])]


class _Batch:
    """The outlines of several glyphs as one set of arrays (points, segments,
    contours, each with its glyph)."""

    def __init__(self, outlines):
        self.n = len(outlines)
        self.points = np.concatenate([o.points for o in outlines]).astype(np.int64)
        self.sizes = np.concatenate([o.sizes for o in outlines])
        self.counts = np.concatenate([o.counts for o in outlines])
        g_contours = np.array([len(o.counts) for o in outlines], np.int64)
        self.g_points = np.array([len(o.points) for o in outlines], np.int64)
        self.contour_glyph = np.repeat(np.arange(self.n), g_contours)
        self.g_contours = g_contours
        self.point_glyph = np.repeat(np.arange(self.n), self.g_points)
        seg_contour = np.repeat(np.arange(len(self.counts)), self.counts)
        self.seg_glyph = self.contour_glyph[seg_contour]
        self.seg_first = np.cumsum(self.sizes) - self.sizes + seg_contour
        per = np.bincount(seg_contour, self.sizes, minlength=len(self.counts)).astype(np.int64)
        self.ends = np.cumsum(per + 1) - 1
        self.starts = self.ends - per
        self.last_seg = np.cumsum(self.counts) - 1

    def _bad(self, point_bad=None, seg_bad=None):
        bad = np.zeros(self.n, bool)
        if point_bad is not None:
            bad[self.point_glyph[point_bad]] = True
        if seg_bad is not None:
            bad[self.seg_glyph[seg_bad]] = True
        return bad

    def cff(self):
        """[(charstring bytes without the advance, tight bounds) or None], as
        ``T2CharStringPen`` (unspecialized) and ``BoundsPen`` make them from
        :func:`morph.fonts.contours.draw_contours`: a contour's closing line is
        left implied.  None for a glyph the arrays do not take."""
        p, sizes = self.points, self.sizes
        op = np.zeros(len(p), np.int64)
        op[self.starts] = _RMOVETO
        op[self.seg_first + sizes] = np.where(sizes == 1, _RLINETO, _RRCURVETO)
        drawn = np.ones(len(p), bool)
        drawn[self.ends[sizes[self.last_seg] == 1]] = False   # the implied closing line
        d, dg = p[drawn], self.point_glyph[drawn]
        delta = np.diff(d, axis=0, prepend=np.zeros((1, 2), np.int64))
        lead = np.ones(len(d), bool)
        lead[1:] = dg[1:] != dg[:-1]
        delta[lead] = d[lead]                   # each glyph from (0, 0)
        bad = self._bad(seg_bad=~np.isin(sizes, (1, 3)))
        bad[dg[(np.abs(delta) > 32767).any(axis=1)]] = True
        nb, nsize = _t2_numbers(np.clip(delta, -32767, 32767).reshape(-1))
        n_drawn = np.bincount(dg, minlength=self.n)
        at = 3 * np.arange(len(d)) + dg           # each glyph's tokens, then endchar
        end_at = 3 * np.cumsum(n_drawn) + np.arange(self.n)
        tok = np.zeros((3 * len(d) + self.n, 3), np.int64)
        size = np.zeros(len(tok), np.int64)
        tok[at], size[at] = nb[0::2], nsize[0::2]
        tok[at + 1], size[at + 1] = nb[1::2], nsize[1::2]
        ops = op[drawn]
        tok[at + 2, 0], size[at + 2] = ops, ops > 0
        tok[end_at, 0], size[end_at] = _ENDCHAR, 1
        glyph_of_tok = np.repeat(np.arange(self.n), 3 * n_drawn + 1)
        data = _split(_packed(tok, size), np.bincount(glyph_of_tok, size, self.n).astype(int))
        bounds = self._cubic_bounds()
        return [None if b else (x, box) for x, box, b in zip(data, bounds, bad)]

    def _cubic_bounds(self):
        """Each glyph's tight box as ``BoundsPen`` computes it: the on-curve
        points, and the extremes of each cubic whose control points reach past
        them (fontTools' ``calcCubicBounds``, the same arithmetic)."""
        p = self.points
        cubic = np.flatnonzero(self.sizes == 3)
        first = self.seg_first[cubic]
        on = np.ones(len(p), bool)
        on[first + 1] = on[first + 2] = False
        lo = np.full((self.n, 2), np.inf)
        hi = np.full((self.n, 2), -np.inf)
        np.minimum.at(lo, self.point_glyph[on], p[on])
        np.maximum.at(hi, self.point_glyph[on], p[on])
        glyph = self.seg_glyph[cubic]
        c = p[first[:, None] + np.arange(4)].astype(float)
        out = ((c[:, 1:3] < lo[glyph, None]) | (c[:, 1:3] > hi[glyph, None])).any(axis=(1, 2))
        c, glyph = c[out], glyph[out]
        if len(c):
            p1, p2, p3, p4 = c[:, 0], c[:, 1], c[:, 2], c[:, 3]
            cc = (p2 - p1) * 3.0
            bb = (p3 - p2) * 3.0 - cc
            aa = p4 - p1 - cc - bb
            qa, qb = aa * 3.0, bb * 2.0
            with np.errstate(divide="ignore", invalid="ignore"):
                linear = np.abs(qa) < 1e-10
                lin_root = np.where(np.abs(qb) >= 1e-10, -cc / qb, np.nan)
                dd = qb * qb - 4.0 * qa * cc
                rdd = np.sqrt(np.where(dd >= 0.0, dd, np.nan))
                t = np.concatenate([np.where(linear, lin_root, (-qb + rdd) / 2.0 / qa),
                                    np.where(linear, np.nan, (-qb - rdd) / 2.0 / qa)],
                                   axis=1)     # (k, 4): the roots of x' and of y'
            t = np.where((t >= 0) & (t < 1), t, np.nan)[:, :, None]
            aa, bb, cc, p1 = aa[:, None], bb[:, None], cc[:, None], p1[:, None]
            val = aa * t * t * t + bb * t * t + cc * t + p1     # (k, root, axis)
            ok = ~np.isnan(t[:, :, 0])
            rows, _ = np.nonzero(ok)
            np.minimum.at(lo, glyph[rows], val[ok])
            np.maximum.at(hi, glyph[rows], val[ok])
        return [None if not np.isfinite(a[0]) else
                (float(a[0]), float(a[1]), float(b[0]), float(b[1]))
                for a, b in zip(lo.tolist(), hi.tolist())]

    def glyf(self, reverse=True):
        """[(``glyf`` glyph bytes, integer box) or None] of quadratic outlines in
        the UFO's direction, as ``TTGlyphPen`` behind a ``ReverseContourPen``
        draws them and ``Glyph.compile`` packs them (greedy flag repeats, short
        or same coordinates); with ``reverse`` False, as ``TTGlyphPen`` alone
        draws them.  None for a glyph the arrays do not take."""
        import struct

        p = self.points
        on = np.zeros(len(p), bool)
        on[self.starts] = True
        on[self.seg_first + self.sizes] = True
        # each contour from its start (reversed: the start kept first), its
        # closing point dropped
        n = self.ends - self.starts
        owner = np.repeat(np.arange(len(n)), n)
        k = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
        idx = (np.where(k == 0, self.starts[owner], self.ends[owner] - k) if reverse
               else self.starts[owner] + k)
        q, flags = p[idx], on[idx].astype(np.int64)
        qg = self.contour_glyph[owner]
        bad = np.zeros(self.n, bool)
        bad[qg[(np.abs(q) > 32767).any(axis=1)]] = True
        delta = np.diff(q, axis=0, prepend=np.zeros((1, 2), np.int64))
        lead = np.ones(len(q), bool)
        lead[1:] = qg[1:] != qg[:-1]
        delta[lead] = q[lead]
        xs, xb, xn = _glyf_axis(delta[:, 0], 0x02, 0x10)
        ys, yb, yn = _glyf_axis(delta[:, 1], 0x04, 0x20)
        flags = flags | xs | ys
        fb, fn = _repeated_flags(flags, lead, qg)
        xb = _split(xb, np.bincount(qg, xn, self.n).astype(int))
        yb = _split(yb, np.bincount(qg, yn, self.n).astype(int))
        fb = _split(fb, np.bincount(fn[0], fn[1], self.n).astype(int))
        npts = np.bincount(qg, minlength=self.n)
        lo = np.full((self.n, 2), 1 << 40)
        hi = np.full((self.n, 2), -(1 << 40))
        np.minimum.at(lo, qg, q)
        np.maximum.at(hi, qg, q)
        end_pts = np.cumsum(n) - np.repeat(_firsts(np.bincount(qg, minlength=self.n)),
                                           self.g_contours) - 1
        ends_b = _split(np.clip(end_pts, 0, 0xFFFF).astype(">u2").tobytes(),
                        2 * self.g_contours)
        out = []
        for g in range(self.n):
            if bad[g] or npts[g] > 0xFFFF:
                out.append(None)
            elif not self.g_contours[g]:
                out.append((b"", None))
            else:
                box = (int(lo[g, 0]), int(lo[g, 1]), int(hi[g, 0]), int(hi[g, 1]))
                out.append((struct.pack(">hhhhh", int(self.g_contours[g]), *box) + ends_b[g]
                            + b"\x00\x00" + fb[g] + xb[g] + yb[g],
                            None if box == (0, 0, 0, 0) else box))
        return out


def _t2_numbers(v):
    """(bytes (n, 3), lengths) of Type 2 integers of at most 16 bits (fontTools'
    ``encodeIntT2``)."""
    out = np.zeros((len(v), 3), np.int64)
    size = np.full(len(v), 3, np.int64)
    small = np.abs(v) <= 107
    pos = (v >= 108) & (v <= 1131)
    neg = (v <= -108) & (v >= -1131)
    out[small, 0] = v[small] + 139
    size[small] = 1
    w = v[pos] - 108
    out[pos, 0], out[pos, 1] = (w >> 8) + 247, w & 0xFF
    w = -v[neg] - 108
    out[neg, 0], out[neg, 1] = (w >> 8) + 251, w & 0xFF
    size[pos | neg] = 2
    big = ~(small | pos | neg)
    w = v[big] & 0xFFFF
    out[big, 0], out[big, 1], out[big, 2] = 28, w >> 8, w & 0xFF
    return out, size


def _glyf_axis(d, short, same):
    """(flag bits, bytes, byte count per point) of one coordinate's deltas, as
    fontTools' greedy packing writes them."""
    flag = np.zeros(len(d), np.int64)
    small = (d != 0) & (np.abs(d) <= 255)
    flag[d == 0] = same
    flag[small] = short
    flag[small & (d > 0)] |= same
    wide = (d != 0) & ~small
    nbytes = np.where(small, 1, np.where(wide, 2, 0))
    out = np.zeros((len(d), 2), np.int64)
    out[small, 0] = np.abs(d[small])
    w = d[wide] & 0xFFFF
    out[wide, 0], out[wide, 1] = w >> 8, w & 0xFF
    return flag, _packed(out, nbytes), nbytes


def _repeated_flags(flags, lead, glyph):
    """fontTools' greedy flag bytes of glyphs whose points start where ``lead``
    (``glyph``: each point's glyph):
    a run of equal flags in groups of at most 256, a group of g >= 3 written as
    (flag | REPEAT, g - 1), a shorter one flag by flag.  Returns (bytes,
    (glyph index, byte count) per group)."""
    change = lead.copy()
    change[1:] |= flags[1:] != flags[:-1]
    run_start = np.flatnonzero(change)
    run_len = np.diff(np.append(run_start, len(flags)))
    run_glyph = glyph[run_start]
    ngroups = (run_len + 255) // 256
    g_flag = np.repeat(flags[run_start], ngroups)
    g_run = np.repeat(np.arange(len(run_len)), ngroups)
    g_k = np.arange(ngroups.sum()) - np.repeat(_firsts(ngroups), ngroups)
    g_len = np.minimum(256, run_len[g_run] - 256 * g_k)
    out = np.zeros((len(g_len), 2), np.int64)
    size = np.minimum(g_len, 2)
    out[:, 0] = np.where(g_len >= 3, g_flag | 0x08, g_flag)
    out[:, 1] = np.where(g_len >= 3, g_len - 1, g_flag)
    return _packed(out, size), (run_glyph[g_run], size)


# =========================================================================== source

def shell_glyph(glyph):
    """A ufoLib2 glyph like ``glyph`` without its contours (advance, unicodes,
    anchors, guidelines, components, image, note, lib: copies)."""
    from ufoLib2.objects import Glyph

    return Glyph(glyph.name, width=glyph.width, height=glyph.height,
                 unicodes=list(glyph.unicodes), image=copy.deepcopy(glyph.image),
                 lib=copy.deepcopy(glyph.lib), note=glyph.note,
                 anchors=copy.deepcopy(glyph.anchors),
                 components=copy.deepcopy(glyph.components),
                 guidelines=copy.deepcopy(glyph.guidelines))


class _ShellPen:
    """A point pen that keeps a glyph's components and counts its contours."""

    def __init__(self, glyph):
        self.inner = glyph.getPointPen()
        self.contours = 0

    def beginPath(self, identifier=None, **kwargs):
        self.contours += 1

    def addPoint(self, *args, **kwargs):
        pass

    def endPath(self):
        pass

    def addComponent(self, base, transformation, identifier=None, **kwargs):
        self.inner.addComponent(base, transformation, identifier=identifier, **kwargs)


class SkeletonSource:
    """The glyphs of a skeleton UFO, read when asked and not kept.

    ``src``: a ``.ufo`` path (read with fontTools.ufoLib, glyph by glyph) or an open
    ``ufoLib2.Font`` (not modified).  ``source[name]`` is a fresh ufoLib2 glyph with
    its contours (from the open font: the font's own glyph); ``name in source``.
    :meth:`shell_font` is the font to write: the source's font data and layers with
    every default-layer glyph a shell (:func:`shell_glyph`), and ``contour_counts``
    how many contours each source glyph had.

    ``light`` (a path only): the UFO is first read without ufoLib2
    (:mod:`morph.parse.light_ufo`: its plists and each glyph's shell), for a compiled
    output; a UFO that reader does not take is read as above when the shells are
    asked for.  A worker reads its glyphs' ``.glif`` files this way.

    Raises:
        ParseError: a UFO that cannot be read, a glyph that does not parse.
    """

    def __init__(self, src, light=False):
        self.path = None if _is_open_font(src) else str(src)
        self.open_font = src if self.path is None else None
        self.font = self._glyph_set = self._glyph_dir = self._contents = self._shells = None
        self.contour_counts = {}
        # outlines read and held (:meth:`skeleton_outlines`), and the names of those
        # kept for the run (component bases)
        self._outlines, self._kept = {}, set()
        # glyph name -> hash of the .glif bytes whose markup but the outline the
        # shells read as a plain GLIF 2 glyph (the outline scan does not parse it again)
        self._plain = {}
        if self.path is not None and light:
            from ..parse.light_ufo import NotLight, read_contents

            try:
                folder, self._contents = read_contents(self.path)
            except NotLight:
                light = False
            else:
                self._glyph_dir = folder
                self._names = set(self._contents)
                self._keys = list(self._contents)
        self.light = light and self.path is not None
        if not self.light:
            self._open()

    def _open(self):
        """The font read by ufoLib2 (lazily: its glyphs read when asked) and the
        glyph set of a UFO on disk (fontTools.ufoLib)."""
        from ..parse.ufo import load_ufo

        self.font = self.open_font or load_ufo(self.path, lazy=True)
        if self.path is not None:
            self._reader()
        self._names = set(self.font.keys())
        self._keys = list(self.font.keys())

    def _reader(self):
        if self._glyph_set is None:
            from fontTools.ufoLib import UFOReader

            reader = UFOReader(self.path, validate=False)
            self._glyph_set = reader.getGlyphSet(reader.getDefaultLayerName(),
                                                 validateRead=False)
        return self._glyph_set

    def keys(self):
        return list(self._keys)

    def __contains__(self, name):
        return name in self._names

    def __getitem__(self, name):
        if self.open_font is not None:
            return self.open_font[name]
        return self._read(name, None)[0]

    def glif_data(self, name):
        """The ``.glif`` bytes of glyph ``name`` of a UFO on disk (None for an open
        font, or a glyph the glyph set cannot give: the reader then reads it the
        ufoLib2 way, which names the defect)."""
        if self.path is None:
            return None
        try:
            return self._glif(name)
        except Exception:  # noqa: BLE001 - read again (and judged) by _read
            return None

    def skeleton_outlines(self, names, hold=False, keep=False):
        """Per glyph name its skeleton ``(paths, components)`` from its ``.glif`` bytes
        (:func:`morph.parse.glif.skeleton_outlines`: the files not read yet, all in
        one batch), or None where that reader declines or the source is an open font
        (the caller reads that glyph the ufoLib2 way, which names a defect).  The
        lists are the caller's own (copies of the held ones).

        A file is read once for the run where its outline is asked for again:
        ``hold`` keeps the outlines until they are next asked for (the plan reads
        the composites its chunks stroke again), ``keep`` for the run (component
        bases, decomposed in many glyphs); others are dropped as they are given, so
        that memory does not grow with the font's outlines."""
        memo = self._outlines
        missing = [n for n in dict.fromkeys(names) if n not in memo]
        if missing:
            from ..parse.glif import skeleton_outlines

            datas = [self.glif_data(n) for n in missing]
            plain = [d is not None and self._plain.get(n) == hash(d)
                     for n, d in zip(missing, datas)]
            memo.update(zip(missing, skeleton_outlines(datas, plain)))
        if keep:
            self._kept.update(names)
        out = [None if memo[n] is None else (list(memo[n][0]), list(memo[n][1]))
               for n in names]
        if not (hold or keep):
            for n in names:
                if n not in self._kept:
                    memo.pop(n, None)
        return out

    def drop_outlines(self):
        """Forget the outlines held or kept (:meth:`skeleton_outlines`)."""
        self._outlines.clear()
        self._kept.clear()

    def _read(self, name, pen_of):
        from ufoLib2.objects import Glyph

        from ..errors import ParseError, one_line

        glyph = Glyph(name)
        pen = pen_of(glyph) if pen_of else glyph.getPointPen()
        try:
            self._reader().readGlyph(name, glyph, pen, validate=False)
        except Exception as exc:  # glifLib raises several types for a bad .glif
            raise ParseError("cannot read glyph %r of %s: %s" % (name, self.path,
                                                                  one_line(exc)),
                             name) from exc
        return glyph, pen

    def shell_font(self):
        """The font to write (see the class docstring); read once, glyph by glyph, on
        the first call (later calls return the same font).  A source opened
        ``light`` gives a :class:`morph.parse.light_ufo.LightFont` (no ufoLib2; its
        tables built without ufo2ft, :mod:`morph.fonts.tables_static`) where the
        UFO allows it, else the ufoLib2 font."""
        if self._shells is None:
            if self.light:
                from ..parse.light_ufo import NotLight, read_light_font

                try:
                    self._shells = read_light_font(self.path, self._glif, self.contour_counts,
                                                   self._contents, self._plain)
                except NotLight:
                    self.light = False
                    self.contour_counts.clear()
                    self._plain.clear()
                    self._open()
            if self._shells is None:
                self._shells = self._shell_font()
        return self._shells

    def _shell_font(self):
        import ufoLib2

        src = self.font
        if self.open_font is not None:
            from ufoLib2.objects import Layer, LayerSet

            src.unlazify()
            default = Layer(src.layers.defaultLayer.name)
            for g in src:
                default.insertGlyph(shell_glyph(g), copy=False)
                self.contour_counts[g.name] = len(g.contours)
            layers = [default if layer is src.layers.defaultLayer else copy.deepcopy(layer)
                      for layer in src.layers]
            return ufoLib2.Font(layers=LayerSet.from_iterable(layers, default.name),
                                info=copy.deepcopy(src.info),
                                features=copy.deepcopy(src.features),
                                groups=copy.deepcopy(src.groups),
                                kerning=copy.deepcopy(src.kerning),
                                lib=copy.deepcopy(src.lib), data=copy.deepcopy(src.data),
                                images=copy.deepcopy(src.images))
        font = src
        default = font.layers.defaultLayer
        for name in list(default.keys()):
            shell, contours = self._read_shell(name)
            default.insertGlyph(shell, overwrite=True, copy=False)
            self.contour_counts[name] = contours
        return font

    def _glif(self, name):
        """The .glif bytes of glyph ``name``: from the UFO folder's ``glyphs``
        directory (the default layer's, by the UFO specification) with a plain
        read, a sixth of the time of glifLib's file system layer; from that layer
        where there is no such folder (a zipped UFO)."""
        if self._glyph_dir is None:
            folder = os.path.join(self.path, "glyphs")
            self._glyph_dir = folder if os.path.isdir(folder) else False
        if self._glyph_dir is False:
            return self._reader().getGLIF(name)
        contents = self._contents if self._contents is not None else self._reader().contents
        with open(os.path.join(self._glyph_dir, contents[name]), "rb") as f:  # no pathlib
            return f.read()

    def _read_shell(self, name):
        """(shell, number of contours) of glyph ``name``, its points not read: the
        .glif's data but its outline by glifLib, the outline's contours counted
        and its components read from the XML tree (in GLIF 2, a component is
        one element, a contour one element of points: reading every point was
        60 % of the shells' time); the XML is parsed once, for both.  A GLIF 1
        glyph (whose anchors are contours of one point) is read whole."""
        from fontTools.misc import etree
        from ufoLib2.objects import Glyph

        from ..parse.glif_xml import glif_number

        glyph = Glyph(name)
        try:
            text, contours = _without_outline(self._glif(name))
            root = etree.fromstring(text)
            if root.get("format", "2").split(".")[0] == "1" or root.tag != "glyph" \
                    or (root.text or "").strip():
                shell, pen = self._read(name, _ShellPen)
                return shell, pen.contours
            _glyph_from_tree(root, text, glyph)
            if contours is not None:        # contours only, counted in the text
                return glyph, contours
            pen, contours = glyph.getPointPen(), 0
            for element in root.iterfind("outline/*"):
                if element.tag == "contour":
                    contours += 1
                elif element.tag == "component":
                    pen.addComponent(element.get("base"), tuple(
                        glif_number(element.get(key, default)) for key, default in _TRANSFORM),
                        identifier=element.get("identifier"))
        except Exception:  # noqa: BLE001 - a .glif the plain read cannot take is glifLib's to judge
            shell, pen = self._read(name, _ShellPen)  # its error names the defect
            return shell, pen.contours
        return glyph, contours


def _is_open_font(src):
    """Whether ``src`` is an open font (ufoLib2's), not a path."""
    return not isinstance(src, (str, bytes)) and not hasattr(src, "__fspath__")


_WORKER_SOURCE = {}  # (path, token) -> SkeletonSource: the one this process reads


def worker_source(path, token):
    """The :class:`SkeletonSource` of the UFO at ``path`` for the run ``token``,
    opened once in this process (a worker reads its chunks' skeletons itself); a
    new token (a new run: the UFO may have changed) opens it again."""
    source = _WORKER_SOURCE.get((path, token))
    if source is None:
        _WORKER_SOURCE.clear()
        source = _WORKER_SOURCE[path, token] = SkeletonSource(path, light=True)
    return source


def _without_outline(text):
    """(text, contours): a .glif's bytes without its outline element and the number
    of contours in it, where the outline holds no component (only contours'
    points, which the shell does not read: parsing them took 0.9 s of the 2.1 s of
    CPU of the shells of 9,574 hanzi skeletons) and nothing can hide or fake its
    tags (one ``<outline>``, no comment or CDATA section); else the text as it is
    and None.  A point that does not parse is left, as before, to the reader of
    the glyph's skeleton."""
    a = text.find(b"<outline>")
    if a < 0 or text.count(b"<outline") != 1 or b"<!--" in text or b"<![CDATA[" in text:
        return text, None
    b = text.find(b"</outline>", a)
    inner = text[a + 9:b]
    if b < 0 or b"<component" in inner:
        return text, None
    return text[:a] + text[b + 10:], len(_CONTOUR_TAG.findall(inner))


#: the start of a contour element (``<contour>``, ``<contour/>``, with attributes)
_CONTOUR_TAG = re.compile(rb"<contour[\s/>]")


def _glyph_from_tree(root, text, glyph):
    """glifLib's reading of a .glif's data but its outline into ``glyph``, from the
    XML tree ``root`` already parsed (glifLib's reader of a tree; where this
    fontTools lacks it, from the text, parsed again)."""
    try:
        from fontTools.ufoLib.glifLib import _readGlyphFromTree
    except ImportError:  # pragma: no cover - another fontTools
        from fontTools.ufoLib.glifLib import readGlyphFromString

        readGlyphFromString(text, glyph, None, validate=False)
        return
    _readGlyphFromTree(root, glyph, None, validate=False)


#: a GLIF component's transformation attributes and their defaults, in order
_TRANSFORM = (("xScale", "1"), ("xyScale", "0"), ("yxScale", "0"), ("yScale", "1"),
              ("xOffset", "0"), ("yOffset", "0"))


# =========================================================================== compiled font

def compile_stored(font, store, kind, features=None, **options):
    """The ``TTFont`` ufo2ft compiles from ``font`` (shells, see the module docstring)
    with the stored outlines ``store`` (glyph name -> :func:`compile_outline`'s
    ``(data, bounds)``, of the flavor of ``kind``: ``.otf`` CFF, ``.ttf`` glyf);
    ``features``: feaLib's tree of ``font``'s feature file, parsed already (None:
    ufo2ft parses it; :func:`morph.fonts.stored.parsed_feature_compiler`);
    ``options`` go to ufo2ft's ``compileOTF`` / ``compileTTF``."""
    import ufo2ft

    from .stored import StoredCFF, StoredGlyf, StoredPostProcessor, parsed_feature_compiler

    if features is not None and "featureCompilerClass" not in options:
        options["featureCompilerClass"] = parsed_feature_compiler(font, features)

    base = StoredCFF if kind == ".otf" else StoredGlyf
    bounds = {}
    compiler = type(base.__name__, (base,), {"store": store, "bounds": bounds})
    if kind == ".otf":
        post = type(StoredPostProcessor.__name__, (StoredPostProcessor,), {"bounds": bounds})
        return ufo2ft.compileOTF(font, outlineCompilerClass=compiler, postProcessorClass=post,
                                 **options)
    return ufo2ft.compileTTF(font, outlineCompilerClass=compiler, **options)


# =========================================================================== the store

class OutlineStore:
    """glyph name -> ``(data, bounds)`` (:func:`compile_outline`'s), kept so that the
    command's memory does not grow with the font: the bytes are appended to an
    unnamed temporary file (gone when the store is closed or the process ends), their
    offsets, lengths and bounds kept in arrays (a few dozen bytes a glyph, with the
    name's slot).  A mapping for the compilers (``in``, ``[]``, ``get``, ``len``,
    iteration over the names in the order they came); a name given again gets its
    new outline.  :meth:`read_into` appends a glyph's bytes to a buffer without
    making an object of them (the CFF table is built that way)."""

    def __init__(self):
        import tempfile
        from array import array

        self._file = tempfile.TemporaryFile(prefix="morph-outlines-")
        self._slot = {}
        self._at, self._size = array("q"), array("q")
        self._bounds = array("d")      # 4 a glyph; NaN for None
        self._end = 0
        self._reading = False

    def __setitem__(self, name, value):
        data, bounds = value
        if self._reading:
            self._file.seek(0, 2)
            self._reading = False
        self._file.write(data)
        box = (float("nan"),) * 4 if bounds is None else bounds
        k = self._slot.get(name)
        if k is None:
            self._slot[name] = len(self._at)
            self._at.append(self._end)
            self._size.append(len(data))
            self._bounds.extend(box)
        else:
            self._at[k], self._size[k] = self._end, len(data)
            self._bounds[4 * k:4 * k + 4] = type(self._bounds)("d", box)
        self._end += len(data)

    def bounds(self, name):
        """The stored bounds of glyph ``name`` (None for none)."""
        k = self._slot[name]
        box = tuple(self._bounds[4 * k:4 * k + 4])
        return None if box[0] != box[0] else box     # NaN: none

    def size(self, name):
        """The length of glyph ``name``'s stored bytes."""
        return self._size[self._slot[name]]

    def read_into(self, name, buffer):
        """Append glyph ``name``'s stored bytes to the bytearray ``buffer``."""
        k = self._slot[name]
        if not self._reading:
            self._file.flush()
            self._reading = True
        self._file.seek(self._at[k])
        buffer += self._file.read(self._size[k])

    def __getitem__(self, name):
        out = bytearray()
        self.read_into(name, out)
        return bytes(out), self.bounds(name)

    def get(self, name, default=None):
        return self[name] if name in self._slot else default

    def __contains__(self, name):
        return name in self._slot

    def __len__(self):
        return len(self._slot)

    def __iter__(self):
        return iter(self._slot)

    def keys(self):
        return self._slot.keys()

    def clear(self):
        """Forget every glyph (the file truncated)."""
        self._file.seek(0)
        self._file.truncate()
        self._slot.clear()
        del self._at[:], self._size[:], self._bounds[:]
        self._end, self._reading = 0, False

    def close(self):
        """Forget every glyph and delete the file."""
        self.clear()
        self._file.close()


def _table_writer():
    """fontTools' ``SFNTWriter`` (plain sfnt) computing a table's checksum without the
    padded copy of the table fontTools' ``calcChecksum`` makes (the same sum), and
    writing a table from chunks of its bytes (:meth:`write_chunks`)."""
    global _WRITER
    if _WRITER is None:
        from fontTools.ttLib.sfnt import SFNTWriter

        class Writer(SFNTWriter):
            def __setitem__(self, tag, data):
                if tag == "head" or self.flavor is not None or tag in self.tables:
                    return super().__setitem__(tag, data)
                return self.write_chunks(tag, [data])

            def write_chunks(self, tag, chunks):
                """Table ``tag`` of the bytes ``chunks`` (each but the last of a
                multiple of 4 bytes), as ``SFNTWriter`` writes a table."""
                entry = self.DirectoryEntry()
                entry.tag, entry.offset = tag, self.nextTableOffset
                self.file.seek(entry.offset)
                total = length = 0
                for chunk in chunks:
                    total += table_checksum(chunk)
                    length += len(chunk)
                    self.file.write(chunk)
                entry.checkSum, entry.length = total & 0xFFFFFFFF, length
                self.nextTableOffset += (length + 3) & ~3
                self.file.write(b"\0" * (self.nextTableOffset - self.file.tell()))
                self.setEntry(tag, entry)

        _WRITER = Writer
    return _WRITER


_WRITER = None


def table_checksum(data):
    """An sfnt table's checksum (the data read as big-endian 32-bit numbers, padded
    with zeros), as fontTools' ``calcChecksum``, without copying the data."""
    whole = len(data) & ~3
    total = int(np.frombuffer(data, ">u4", whole // 4).sum(dtype=np.uint64)) if whole else 0
    rest = bytes(data[whole:])
    if rest:
        total += int.from_bytes(rest.ljust(4, b"\0"), "big")
    return total & 0xFFFFFFFF


def file_table(tag, file):
    """A fontTools table ``tag`` whose bytes are the whole of the open binary file
    ``file`` (a temporary file, closed with the table): :func:`write_tables` copies
    them into the font's file a chunk at a time; anything else reading the table's
    ``data`` (fontTools' save, a decompilation) reads them."""
    global _FILE_TABLE
    if _FILE_TABLE is None:
        from fontTools.ttLib.tables.DefaultTable import DefaultTable

        class FileTable(DefaultTable):
            def __init__(self, tag, file):
                super().__init__(tag)
                self.file = file

            @property
            def data(self):
                self.file.seek(0)
                return self.file.read()

            def chunks(self, size=1 << 16):
                self.file.seek(0)
                while True:
                    chunk = self.file.read(size)
                    if not chunk:
                        return
                    yield chunk

        _FILE_TABLE = FileTable
    return _FILE_TABLE(tag, file)


_FILE_TABLE = None


def write_tables(otf, file):
    """The tables of ``otf`` (a plain sfnt) written to the open binary ``file``: each
    compiled in the order, and with the dependencies, fontTools' save compiles them,
    then written in the order its reordering pass writes them; a
    :func:`file_table` copied from its file, a chunk at a time."""
    from fontTools.ttLib.ttFont import sortedTagList

    tags = otf.keys()[1:]       # not GlyphOrder
    chunked = [t for t in tags if hasattr(otf.tables.get(t), "chunks")]
    data, done = {}, list(chunked)
    for tag in tags:
        otf._writeTable(tag, data, done)  # noqa: SLF001 - fontTools' order, dependencies first
    writer = _table_writer()(file, len(tags), otf.sfntVersion, otf.flavor, otf.flavorData)
    for tag in sortedTagList(tags):
        if tag in chunked:
            writer.write_chunks(tag, otf.tables[tag].chunks())
        else:
            writer[tag] = data.pop(tag)
    writer.close()


def save_font(otf, path):
    """``otf.save(path)`` (tables in the recommended order), the same bytes, without
    fontTools' two in-memory copies of the whole font (:func:`write_tables`).  A
    font fontTools would write otherwise (WOFF, WOFF2) is saved by fontTools."""
    if otf.flavor is not None:
        otf.save(str(path))
        return
    if otf.recalcTimestamp and "head" in otf:
        otf["head"]      # loaded, so that its compilation sets the time, as the save does
    with open(str(path), "wb") as f:
        write_tables(otf, f)


# =========================================================================== UFO output

class UfoGlyphWriter:
    """A UFO written glyph by glyph: ``font`` (the shells, every glyph's final
    advance, anchors and components) is saved to ``path`` by ufoLib2 at once; then
    :meth:`write` rewrites one glyph's ``.glif`` with its contours, which are not
    kept; :meth:`finish` writes the font info again (changed since)."""

    def __init__(self, font, path):
        from fontTools.ufoLib import UFOWriter

        font.save(str(path), overwrite=True)
        self.font = font
        self.writer = UFOWriter(str(path), validate=False)
        self.glyph_set = self.writer.getGlyphSet(validateWrite=False)

    def write(self, name, contours):
        """Glyph ``name``'s shell with integer cubic ``contours`` drawn in, as ufoLib2
        writes a glyph (contours, then components)."""
        g = self.font[name]
        draw_contours(g.getPen(), contours, False)
        try:
            self.glyph_set.writeGlyph(name, glyphObject=g, drawPointsFunc=g.drawPoints)
        finally:
            g.clearContours()

    def finish(self):
        self.writer.writeInfo(self.font.info)


def sample_font(path, text, length=15):
    """A small ufoLib2 font of the UFO at ``path`` for its sample image
    (:func:`morph.fonts.specimen.sample_text` and ``write_sample_image`` take it as
    they took the whole font, and pick the same text): the glyphs of ``text``'s
    characters and of the font's first ``length`` characters with ink (in code
    point order, as ``sample_text`` picks them), with their components' bases and
    the font info; only those glyphs are read."""
    import unicodedata

    import ufoLib2
    from fontTools.ufoLib import UFOReader

    src = ufoLib2.Font.open(str(path), lazy=True)
    codes = UFOReader(str(path), validate=False).getGlyphSet(validateRead=False).getUnicodes()
    cmap = {}
    for name in src.keys():
        for u in codes.get(name, ()):
            cmap.setdefault(u, name)
    wanted = [cmap[ord(ch)] for ch in text if ord(ch) in cmap]
    own = 0
    for code in sorted(cmap):
        if own == length:
            break
        if unicodedata.category(chr(code))[0] not in ("C", "Z") \
                and src[cmap[code]].getBounds(src) is not None:
            wanted.append(cmap[code])
            own += 1
    out = ufoLib2.Font(info=copy.deepcopy(src.info))
    while wanted:
        name = wanted.pop()
        if name in out or name not in src:
            continue
        out.layers.defaultLayer.insertGlyph(src[name], copy=True)
        wanted.extend(c.baseGlyph for c in src[name].components)
    return out
