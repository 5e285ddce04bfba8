"""GLIF outlines scanned from the files' bytes, the glyphs of a chunk at once.

:mod:`.glif` parses each ``.glif`` into an XML tree and walks it point by point in
Python; for a skeleton of 60 points that is most of a glyph's reading time.  Here
the ``<outline>`` contents of all the chunk's files are joined and split once at
their quotes: attribute values and the texts between them.  A skeleton font has a
dozen distinct texts (``" y="``, ``"/>`` + new line + ``<point x="`` ...), each
classified once (:func:`_texts`: which attribute comes next, whether an element
ends, contours opened or closed); the structure of every glyph (contours of
points, a point's attributes in glifLib's order) is checked with array operations
on those classes, the coordinates read by ``float`` as :mod:`.glif` reads them, and
the contours split into segments on the points' types by array operations; the
pieces are built as :func:`.glif.skeleton_outlines` builds them, so the paths are
the same arrays, to the bit.

The rest of a file (everything but the outline element) is still parsed as XML,
with an empty ``<outline/>`` in the outline's place: it is small, and so the file is
read only if it is well-formed and the outline a child of a GLIF 2 ``glyph``, as
:func:`.glif.glif_outline` reads it.  Components in plain markup (empty elements
outside the contours, :func:`.glif_xml.plain_components`) are read from their
attributes and cut out before the scan.  A file whose outline holds anything else
(other components, comments, CDATA, references, single quotes, another attribute order,
text, bytes outside printable ASCII, markup in a value) and a glyph whose contours
:func:`.glif.glif_outline` would decline or read with non-finite or too large
coordinates are left to :func:`.glif.skeleton_outlines`'s XML reader, which reads
or declines them exactly.
"""

import re
from itertools import repeat
from operator import itemgetter

import numpy as np

from .. import piece as pc
from ..limits import MAX_COORDINATE
from .glif_xml import parse_glif, plain_components

__all__ = ["scan_outlines"]

_WS = rb"[ \t\r\n]"
#: the end of a glyph's outline content in the chunk's bytes (a byte that is not
#: valid in XML: no outline holds it)
_END = b"\x01"
#: the text between two attribute values (or before the first, after the last):
#: the next attribute of the element (``more``), or the end of the element
#: (``tail``), contours opened or closed, and the start of the next element
_TEXT = re.compile(
    b"(?:(?P<more>" + _WS + b"+)(?P<attr>[A-Za-z]+)=|(?P<tail>" + _WS + b"*/?>)?(?P<events>(?:"
    + _WS + b"|<contour" + _WS + b"*/?>|</contour" + _WS + b"*>|" + _END + b")*)(?:<(?P<kind>"
    b"point|contour)" + _WS + b"+(?P<attr2>[A-Za-z]+)=)?)")
_EVENTS = re.compile(b"(<contour" + _WS + b"*>)|(</contour" + _WS + b"*>)|(" + _END + b")")
#: characters whose meaning XML changes (references) or refuses (controls), and bytes
#: outside ASCII (read in the file's encoding): an outline holding one is not scanned
_ODD = bytes([*range(9), 11, 12, *range(14, 32), ord("&"), *range(127, 256)])
_START = re.compile(rb"<outline" + _WS + rb"*>")

#: a point's attributes, in the order the scan reads them
_ATTRS = {b"x": 0, b"y": 1, b"type": 2, b"smooth": 3, b"name": 4, b"identifier": 5}
#: point type codes: off-curve (none or "offcurve"), move, then the on-curve
#: types by their number of off-curve points before them (_NEED), other
_TYPES = {b"offcurve": 0, b"move": 1, b"line": 2, b"qcurve": 3, b"curve": 4}
_OFF, _MOVE, _OTHER = 0, 1, 5
_NEED = np.array([-1, -1, 0, 1, 2, -1])
#: element kinds
_POINT, _CONTOUR = 1, 2


def scan_outlines(datas, plain=None):
    """``(out, left)``: per datum of ``datas`` (``.glif`` bytes or None) its
    ``(paths, components)`` as :func:`.glif.skeleton_outlines`, or None; ``left``
    the indices of the data the scan leaves to the XML reader (their ``out`` None).
    ``plain``: per datum whether its markup but the outline is known to be a plain
    GLIF 2 glyph (:func:`.light_ufo.glif_shell` read it), not parsed again (None:
    none known)."""
    out = [None] * len(datas)
    take, inners = [], []
    for i, d in enumerate(datas):
        inner = _plain(d, plain is not None and plain[i]) if d is not None else None
        if inner is not None:
            take.append(i)
            inners.append(inner)
    read = _read([inner for inner, _ in inners]) if take else []
    for i, paths, (_, components) in zip(take, read, inners):
        if paths is not None:
            out[i] = (paths, components)
    return out, [i for i, d in enumerate(datas) if d is not None and out[i] is None]


def _plain(data, known=False):
    """``(contours, components)`` of a file the scan reads: the outline content
    without its components, and the components (:func:`_components`); else None.
    ``known``: the markup but the outline is known to be a plain GLIF 2 glyph's (it
    parses, as the outline element's, to the tree checked here)."""
    a = data.find(b"<outline")
    start = _START.match(data, a) if a >= 0 and data.find(b"<outline", a + 1) < 0 else None
    b = data.find(b"</outline>", start.end()) if start else -1
    inner = data[start.end():b] if b >= 0 else b""
    if b < 0 or inner.count(b'"') % 2 or len(inner.translate(None, _ODD)) != len(inner):
        return None
    components = []
    if b"<component" in inner:
        components = _components(data[a:b])
        if components is None:
            return None
        inner = _COMPONENT.sub(b"", inner)
    if known:
        return inner, components
    try:
        root = parse_glif(data[:a] + b"<outline/>" + data[b + 10:])
    except (SyntaxError, ValueError):  # not well-formed (ElementTree's and lxml's parse
        return None                    # errors are SyntaxErrors): the XML reader's to decline
    outlines = [el for el in root if el.tag == "outline"]
    if root.tag != "glyph" or root.get("format") != "2" or (root.text and root.text.strip()) \
            or len(outlines) != 1 or len(outlines[0]):
        return None
    return inner, components


#: a component element in plain markup (:func:`.glif_xml.plain_components`)
_COMPONENT = re.compile(rb"<component[^>]*>")


def _components(outline):
    """The components (:func:`.glif.component`) of an outline element's bytes in
    plain markup (:func:`.glif_xml.plain_components`: contours of points, empty
    components outside them), else None (the XML reader's to read or decline)."""
    from .glif import component   # .glif imports this module

    attributes = plain_components(outline)
    try:
        return None if attributes is None else [component(a.get) for a in attributes]
    except Exception:  # noqa: BLE001 - declined, as glif_outline declines it
        return None


def _texts(texts):
    """Per distinct text of :data:`_TEXT` (``texts``, a list) a row: (valid, more,
    attribute rank, tail (0 none, 1 ``/>``, 2 ``>``), kind of the element it
    starts, contours opened, ends of outlines, depth change, valid at depth 0,
    valid at depth 1 (the depth after the tail))."""
    rows = []
    for t in texts:
        m = _TEXT.fullmatch(t)
        if m is None:   # refused; its contours and ends still counted, for the next glyphs
            events = _EVENTS.findall(t)
            rows.append((0, 0, -1, 0, 0, sum(1 for o, _, _ in events if o),
                         sum(1 for _, _, e in events if e),
                         sum(1 if o else -1 if c else 0 for o, c, _ in events), 0, 0))
            continue
        attr = m["attr"] if m["more"] else m["attr2"]
        tail = {b"": 0, b">": 2}.get((m["tail"] or b"").strip(b" \t\r\n"), 1)
        kind = {None: 0, b"point": _POINT, b"contour": _CONTOUR}[m["kind"]]
        events = [(o, c, e) for o, c, e in _EVENTS.findall(m["events"] or b"")]
        valid = []
        for depth in (0, 1):
            good = True
            for o, c, e in events:
                good &= (depth == 1) if c else (depth == 0)
                depth += 1 if o else -1 if c else 0
            valid.append(good and (kind == 0 or depth == (1 if kind == _POINT else 0)))
        rows.append((1, int(bool(m["more"])), _ATTRS.get(attr, -1) if attr else -1, tail,
                     kind, sum(1 for o, _, _ in events if o), sum(1 for _, _, e in events if e),
                     sum(1 if o else -1 if c else 0 for o, c, _ in events), *valid))
    return np.array(rows, np.int64).reshape(-1, 10)


def _read(inners):
    """Per outline content of ``inners`` its paths (:func:`.glif.skeleton_outlines`),
    or None where the XML reader must read it (see the module docstring)."""
    g = len(inners)
    blob = _END.join(inners) + _END
    parts = blob.split(b'"')
    values = parts[1::2]
    distinct = list(set(parts[0::2]))
    ids = np.array(list(map({t: k for k, t in enumerate(distinct)}.__getitem__, parts[0::2])))
    del parts      # long lists the garbage collector would walk while pieces are made
    counts = np.bincount(ids, minlength=len(distinct)).tolist()
    table = _texts(distinct)[ids]
    ok, point, cid, glyph = _structure(table, g)
    if blob.count(b"<") != sum(t.count(b"<") * c for t, c in zip(distinct, counts)):
        ends = np.cumsum(table[:, 6])        # markup in a value: not well-formed
        ok[ends[[k for k, v in enumerate(values) if b"<" in v]]] = False
    keep = ok[glyph]                  # points of glyphs still read (their contours own)
    point, cid, glyph = point[keep], cid[keep], glyph[keep]
    pts = _floats(values, point, glyph, ok)
    code = _codes(table, values, point)
    del values
    n = np.bincount(cid, minlength=int(cid.max(initial=-1)) + 1)
    cglyph = np.zeros(len(n), np.int64)
    cglyph[cid] = glyph
    pbad = ~np.isfinite(pts).all(axis=1) | (np.abs(pts).max(axis=1, initial=0.0)
                                            > MAX_COORDINATE)
    ok[glyph[pbad | (code == _OTHER)]] = False
    seg = _segments(code, cid, n, cglyph, ok)
    return _assemble(pts, n, cglyph, ok, seg, g)


def _floats(values, point, glyph, ok):
    """The (x, y) of the points whose x value is at ``point`` (y follows), as
    ``float`` reads them; a glyph with a value ``float`` refuses is no longer ``ok``
    (its points NaN: the XML reader declines it)."""
    xy = itemgetter(*np.stack([point, point + 1], axis=1).ravel().tolist())(values) \
        if len(point) else ()
    xy = xy if len(point) != 1 else [values[point[0]], values[point[0] + 1]]
    try:
        return np.array(list(map(float, xy)), np.float64).reshape(-1, 2)
    except ValueError:
        pass
    out = np.full((len(point), 2), np.nan)
    for k, v in enumerate(xy):
        try:
            out[k // 2, k % 2] = float(v)
        except ValueError:
            ok[glyph[k // 2]] = False
    return out


def _structure(table, g):
    """``(ok, point, contour, glyph)``: per glyph whether its outline content is of
    the grammar the scan reads (contours of points, attributes in glifLib's order);
    per point the index of its x value (y follows), its contour, its glyph."""
    valid, more, rank, tail, kind, opens, ends, delta, at0, at1 = table.T
    f = len(table)
    # the element each text's values belong to, and its kind
    new = kind > 0
    elem = np.maximum.accumulate(np.where(new, np.arange(f), -1))
    ekind = np.where(elem >= 0, kind[np.maximum(elem, 0)], 0)
    prev_kind = np.zeros(f, np.int64)
    prev_kind[1:] = ekind[:-1]
    tail_opens = (tail == 2) & (prev_kind == _CONTOUR)
    step = delta + tail_opens
    depth = np.cumsum(step) - step + tail_opens          # after the tail
    bad = (valid == 0) | ((depth != 0) & (depth != 1))
    bad |= np.where(depth == 0, at0, at1) == 0
    bad |= (tail == 2) & (prev_kind != _CONTOUR)
    bad[1:] |= (more[1:] == 0) & (tail[1:] == 0)              # a value, then no end
    bad[0] |= bool(more[0] or tail[0])
    bad[-1] |= bool(new[-1] or more[-1])
    # attributes: a point's x, y, then the others in order; a contour's identifier
    bad |= new & (kind == _POINT) & (rank != 0)
    bad |= new & (kind == _CONTOUR) & (rank != 5)
    bad[:-1] |= new[:-1] & (kind[:-1] == _POINT) & ((more[1:] == 0) | (rank[1:] != 1))
    bad[1:] |= (more[1:] == 1) & ((ekind[1:] != _POINT) | (rank[1:] <= rank[:-1]))
    bad |= (more == 1) & (rank < 0)
    glyph_end = np.cumsum(ends)
    glyph_start = glyph_end - ends
    ok = np.ones(g + 1, bool)
    ok[glyph_start[bad]] = False
    ok[glyph_end[bad]] = False
    point = np.flatnonzero(new & (kind == _POINT))
    cid = (np.cumsum(opens + tail_opens)[point] - 1).astype(np.int64)
    return ok[:g], point, cid, glyph_end[point]


def _codes(table, values, point):
    """Per point its type code (:data:`_TYPES`; no type: off-curve)."""
    rank = table[:, 2]
    more = table[:, 1]
    typed = np.flatnonzero((more == 1) & (rank == 2))
    elem = np.maximum.accumulate(np.where(table[:, 4] > 0, np.arange(len(table)), -1))
    code = np.zeros(len(point), np.int64)
    at = np.minimum(np.searchsorted(point, elem[typed]), max(len(point) - 1, 0))
    typed = typed[point[at] == elem[typed]] if len(point) else typed[:0]   # points read
    if len(typed):
        names = itemgetter(*typed.tolist())(values) if len(typed) > 1 else (values[typed[0]],)
        code[np.searchsorted(point, elem[typed])] = list(map(_TYPES.get, names,
                                                             repeat(_OTHER, len(names))))
    return code


def _segments(code, cid, n, cglyph, ok):
    """The segments of every contour of two points or more: ``(contour, first point,
    number of points, order key)`` arrays; ``ok`` (per glyph) cleared where a
    contour is not read as :func:`.glif._contour` reads it.  Also each contour's
    start point and closed flag."""
    cstart = np.cumsum(n) - n
    li = np.arange(len(code)) - cstart[cid]
    nn = n[cid]
    opened = np.zeros(len(n), bool)
    opened[n > 0] = code[cstart[n > 0]] == _MOVE
    on = code != _OFF
    e = np.flatnonzero(on & (nn >= 2))
    ce = cid[e]
    first = np.ones(len(e), bool)
    first[1:] = ce[1:] != ce[:-1]
    last = np.ones(len(e), bool)
    last[:-1] = first[1:]
    prev = np.empty_like(e)
    prev[1:] = e[:-1]
    prev[first] = e[last]
    dist = e - prev + np.where(first, nn[e], 0)
    ends = ~(first & opened[ce])
    wrong = ends & (dist - 1 != _NEED[code[e]])
    wrong |= (code[e] == _MOVE) & (li[e] > 0)
    wrong |= last & opened[ce] & (li[e] != nn[e] - 1)          # off-curves after the end
    closed = ~opened & (n >= 2)
    cbad = closed & (np.bincount(cid, weights=on, minlength=len(n)) == 0)
    ok[cglyph[ce[wrong]]] = False
    ok[cglyph[cbad]] = False
    start = np.zeros(len(n), np.int64)       # the first on-curve point of a closed contour
    start[ce[first]] = li[e[first]]
    start[~closed] = 0
    e, prev, dist, ce = e[ends], prev[ends], dist[ends], ce[ends]
    key = li[e] + np.where(first[ends] & closed[ce], nn[e], 0)  # the start's segment last
    return ce, li[prev], dist + 1, key, cstart, start, closed


def _assemble(pts, n, cglyph, ok, seg, g):
    """Per glyph its paths from the segments ``seg`` (:func:`_segments`) of the
    glyphs still ``ok`` (None for the others): the pieces built by number of points
    (as :func:`.glif._stack`), each contour's in order, zero-length ones dropped, a
    contour left empty a zero-length open line at its start."""
    ce, first_li, m, key, cstart, start, closed = seg
    keep = ok[cglyph[ce]]
    order = np.lexsort((key[keep], ce[keep]))
    ce, first_li, m = ce[keep][order], first_li[keep][order], m[keep][order]
    rows, pos, zero = [], np.empty(len(ce), np.int64), np.zeros(len(ce), bool)
    for k in (2, 3, 4):
        sel = np.flatnonzero(m == k)
        if len(sel):
            c = ce[sel]
            idx = cstart[c][:, None] + (first_li[sel][:, None] + np.arange(k)) % n[c][:, None]
            h = np.ones((len(sel), k, 3))
            h[..., :2] = pts[idx]
            zero[sel] = (h[..., :2] == h[:, :1, :2]).all(axis=(1, 2))
            pos[sel] = len(rows) + np.arange(len(sel))
            rows.extend(h)
    kept = pos[~zero].tolist()
    pieces = list(itemgetter(*kept)(rows)) if len(kept) > 1 else [rows[i] for i in kept]
    kc = np.bincount(ce[~zero], minlength=len(n))
    live = np.flatnonzero((n > 0) & ok[cglyph])
    ends = np.cumsum(kc)[live].tolist()
    paths = [(pieces[b - k:b], cl) if k else ([pc.line(pts[s], pts[s])], False)
             for b, k, cl, s in zip(ends, kc[live].tolist(), closed[live].tolist(),
                                    (cstart + start)[live].tolist())]
    stop = np.cumsum(np.bincount(cglyph[live], minlength=g)).tolist()
    return [paths[b - k:b] if good else None
            for b, k, good in zip(stop, np.bincount(cglyph[live], minlength=g).tolist(),
                                  ok.tolist())]
