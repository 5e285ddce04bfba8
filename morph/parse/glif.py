"""Skeleton outlines read straight from ``.glif`` data, a chunk of glyphs at once.

The reader of :mod:`.ufo` goes through ufoLib2 and fontTools' pens: glifLib turns
every point into a dict and a ufoLib2 point, ``PointToSegmentPen`` into segments,
and :mod:`.pens` into one small array per piece; for a skeleton font that is most
of a glyph's parse time (a CJK skeleton of 60 points: about 4 ms).  Here the GLIF
XML is parsed once (lxml, as glifLib parses it), each contour's points are split
into segments in one pass over its point types, and the pieces of all the glyphs
of a chunk are built by degree in a few array operations; a glyph's paths are
row views of those stacks.

Only the plain structures are read here, where the pens' meaning is simple:
format-2 GLIF whose outline holds contours and components only; an open contour is
a ``move`` point then on-curve points each preceded by the off-curve points of its
type (``line`` none, ``curve`` two, ``qcurve`` one); a closed contour (no ``move``)
the same read cyclically from its first on-curve point (``PointToSegmentPen``'s
rotation); a contour of one point is a dot.  The paths are the same arrays, to the
bit, as :func:`morph.parse.ufo.glyph_paths` of the glyph read by ufoLib2 (zero-length
pieces dropped, the closing segment of a closed contour kept, a contour of
zero-length pieces a dot).  Anything else (TrueType runs of off-curve points, cubic
runs of more than two, ``curve`` / ``qcurve`` without their off-curves, a ``move``
inside a contour, a non-finite or too large coordinate, XML glifLib would read
otherwise, format 1) makes :func:`skeleton_outlines` decline the glyph: the caller
reads it the ufoLib2 way, which gives the same result or names the defect.
"""

from collections import namedtuple

import numpy as np

from .. import piece as pc
from ..limits import MAX_COORDINATE
from ._glif_scan import scan_outlines  # the workers use it: imported before they fork
from .glif_xml import glif_number as _number
from .glif_xml import parse_glif

__all__ = ["Component", "glif_outline", "skeleton_outlines"]

#: A component of a glyph read here: its base glyph's name and its affine
#: transformation (xx, xy, yx, yy, dx, dy) in fontTools order, as numbers
#: (what :func:`morph.parse.ufo.component_paths` and ``keep_component`` read of a
#: ufoLib2 component).
Component = namedtuple("Component", "baseGlyph transformation")

#: off-curve points before each on-curve point type
_OFFS = {"line": 0, "curve": 2, "qcurve": 1}
#: glifLib's component transformation attributes and defaults
_TRANSFORM = (("xScale", "1"), ("xyScale", "0"), ("yxScale", "0"), ("yScale", "1"),
              ("xOffset", "0"), ("yOffset", "0"))



class _Decline(Exception):
    """The fast reader does not read this glyph (see the module docstring)."""


def glif_outline(data):
    """``(contours, components)`` of GLIF ``data`` (bytes), or None where the fast
    reader declines (module docstring).

    ``contours``: per contour ``(points, segments, start, closed)``: the points
    [(x, y)] (glifLib's numbers as floats, as the pens' arrays hold them), the segments as tuples of point indices
    (the segment's start point first), the index of the start point; ``components``:
    :class:`Component` list in file order."""
    try:
        return _outline(parse_glif(data))
    except Exception:  # noqa: BLE001 - anything unusual is the ufoLib2 reader's to judge
        return None


def _outline(root):
    if root.tag != "glyph" or root.get("format") != "2" or (root.text and root.text.strip()):
        raise _Decline
    outlines = [el for el in root if el.tag == "outline"]
    if len(outlines) > 1:
        raise _Decline
    contours, components = [], []
    for el in (outlines[0] if outlines else ()):
        if el.tag == "contour":
            c = _contour(el)
            if c is not None:
                contours.append(c)
        elif el.tag == "component":
            if len(el):
                raise _Decline
            components.append(component(el.get))
        else:
            raise _Decline
    return contours, components


def component(get):
    """The :class:`Component` of a component element whose attributes ``get`` gives
    (``dict.get``); raises where the fast reader declines (no base, a number
    glifLib does not read)."""
    base = get("base")
    if base is None:
        raise _Decline
    return Component(base, tuple(_number(get(a) or d) for a, d in _TRANSFORM))


def _contour(el):
    """(points, segments, start, closed) of a contour element, None for an empty
    contour (no segment pen call: no path).  ``segments`` is None for an open
    contour of lines only (each point joined to the next: most skeletons)."""
    pts = list(el)
    n = len(pts)
    if n == 0:
        return None
    for p in pts:
        if p.tag != "point":
            raise _Decline
    # float(text) is float(glifLib's int-or-float of it): both round the decimal
    # number once to the nearest double; text glifLib refuses float refuses too
    points = [(float(p.get("x")), float(p.get("y"))) for p in pts]
    types = [p.get("type") for p in pts]
    if n == 1:
        return points, [], 0, False
    if types[0] == "move":
        if types.count("line") == n - 1:
            return points, None, 0, False
        start, order, closed = 0, range(1, n), False
    else:
        start = next((i for i, t in enumerate(types) if t is not None and t != "offcurve"),
                     None)
        if start is None:
            raise _Decline
        order, closed = list(range(start + 1, n)) + list(range(start + 1)), True
    segments, offs, prev = [], [], start
    for i in order:
        t = types[i]
        if t is None or t == "offcurve":
            offs.append(i)
            continue
        if _OFFS.get(t) != len(offs):
            raise _Decline
        segments.append((prev, *offs, i))
        offs, prev = [], i
    if offs:
        raise _Decline
    return points, segments, start, closed


def skeleton_outlines(datas, plain=None):
    """Paths and components of GLIF ``datas`` (a chunk's glyphs), the pieces of all
    built together: per glyph ``(paths, components)`` as :func:`morph.parse.ufo.
    glyph_paths` and the glyph's components (:class:`Component`), or None where
    the fast reader declines (the caller reads that glyph the ufoLib2 way).

    The outlines of plain files are scanned from their bytes, all at once
    (:mod:`._glif_scan`; ``plain``: per datum whether its markup but the outline is
    known to be a plain GLIF 2 glyph's, :func:`._glif_scan.scan_outlines`); a file
    the scan leaves is parsed as XML (:func:`glif_outline`)."""
    out, left = scan_outlines(datas, plain)
    if left:
        for i, o in zip(left, _tree_outlines([datas[i] for i in left])):
            out[i] = o
    return out


def _tree_outlines(datas):
    """:func:`skeleton_outlines` of ``datas`` parsed as XML trees (:func:`glif_outline`)."""
    outlines = [glif_outline(d) if d is not None else None for d in datas]
    # every point of every read glyph; each segment as its global point indices,
    # by number of points (lines of line-only contours as index ranges)
    xy, base, starts, nsegs = [], [], [], []
    segs = {2: []}
    line_runs = []           # (first segment id, first point, count) of line-only runs
    order = []               # (number of points, position in that group) per segment
    for o in outlines:
        if o is None:
            continue
        for points, segments, start, _ in o[0]:
            b = len(xy)
            xy += points
            base.append(b)
            starts.append(b + start)
            if segments is None:
                m = len(points) - 1
                line_runs.append((len(order), b, m))
                order += [None] * m
            else:
                for sg in segments:
                    lst = segs.setdefault(len(sg), [])
                    order.append((len(sg), len(lst)))
                    lst.append(tuple(b + i for i in sg))
                m = len(segments)
            nsegs.append(m)
    pts = np.array(xy, float).reshape(-1, 2)
    bad = ~np.isfinite(pts).all(axis=1) | (np.abs(pts).max(axis=1, initial=0.0)
                                           > MAX_COORDINATE)
    piece = [None] * len(order)
    zero = np.zeros(len(order), bool)
    # line-only runs: point i to i + 1
    if line_runs:
        s, b, m = np.array(line_runs, np.int64).reshape(-1, 3).T
        step = np.arange(m.sum()) - np.repeat(np.cumsum(m) - m, m)   # 0..m-1 per run
        sid, first = np.repeat(s, m) + step, np.repeat(b, m) + step
        _stack(pts, np.stack([first, first + 1], axis=1), sid, piece, zero)
    for m, lst in segs.items():
        if lst:
            sid = np.array([k for k, o in enumerate(order) if o is not None and o[0] == m],
                           np.int64)
            _stack(pts, np.array(lst, np.int64).reshape(-1, m), sid, piece, zero)
    return _glyph_paths(outlines, pts, bad, base, starts, nsegs, piece, zero)


def _glyph_paths(outlines, pts, bad, base, starts, nsegs, piece, zero):
    """Per glyph of :func:`skeleton_outlines` its ``(paths, components)`` from the
    pieces built for all (``piece``, in segment order; zero-length ones, ``zero``,
    dropped; a contour left empty is one zero-length open line at its start), or
    None where the fast reader declined or a point is ``bad``."""
    out, c, f = [], 0, 0
    # each contour's points follow the previous contour's: one reduction flags them
    bad = np.logical_or.reduceat(bad, base).tolist() if base else []
    zero = zero.tolist()
    for o in outlines:
        if o is None:
            out.append(None)
            continue
        paths, broken = [], False
        for _, _, _, closed in o[0]:
            m = nsegs[c]
            broken |= bad[c]
            kept = [p for p, z in zip(piece[f:f + m], zero[f:f + m]) if not z]
            if kept:
                paths.append((kept, closed))
            else:
                paths.append(([pc.line(pts[starts[c]], pts[starts[c]])], False))
            c += 1
            f += m
        out.append(None if broken else (paths, list(o[1])))
    return out


def _stack(pts, idx, sid, piece, zero):
    """The polynomial pieces through the points ``idx`` (k, m) as one stack (weights
    1: :func:`morph.piece.from_points`); row r is ``piece[sid[r]]``, and
    ``zero[sid[r]]`` says whether its control points all coincide."""
    h = np.ones(idx.shape + (3,))
    h[..., :2] = pts[idx]
    zero[sid] = (h[..., :2] == h[:, :1, :2]).all(axis=(1, 2))
    for i, row in zip(sid.tolist(), h):
        piece[i] = row
