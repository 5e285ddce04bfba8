"""TrueType simple glyphs decoded from their ``glyf`` bytes straight into pieces.

The pieces are those :func:`morph.parse.glyphs.read_glyphs` gets by drawing the
glyph on a pen (fontTools' ``Glyph.draw`` on a ``BasePen``, then its contours closed,
:func:`morph.parse.glyphs._filled_loops`), value for value and in the same order:
each contour from its first on-curve point; a line between two on-curve points; a
quadratic per off-curve point, from the previous on-curve point or the implied one
halfway to the previous off-curve point (``0.5 * (a + b)``, fontTools' arithmetic)
to the next on-curve or implied point; the closing line back to the start where the
contour ends elsewhere; pieces of zero length dropped, then contours left empty.
The points are decoded for all glyphs at once (flags by a short loop per glyph,
coordinates by array calls), and the pieces of all glyphs built at once.

A glyph this module does not decode is left to the pen (None): a composite, a
glyph that is not in the table, a contour without an on-curve point or with cubic
flags, a glyph whose stored bytes do not hold its points.
"""

import numpy as np

from .pens import glyph_loops

__all__ = ["simple_glyph_loops"]

_ON, _X_SHORT, _Y_SHORT, _REPEAT, _X_SAME, _Y_SAME, _CUBIC = 1, 2, 4, 8, 16, 32, 0x80


def simple_glyph_loops(font, names):
    """Per name: the closed loops (lists of pieces, weights 1) of a simple glyph of
    the static TrueType ``font`` as :func:`morph.parse.glyphs.read_glyphs` draws
    them, [] for a glyph without contours, or None for a glyph left to the pen
    (see the module docstring)."""
    glyf, hmtx = font["glyf"], font["hmtx"]
    glyphs = getattr(glyf, "glyphs", None) or {}
    heads = [_head(glyphs.get(name)) for name in names]
    stored = [k for k, h in enumerate(heads) if isinstance(h, tuple) and len(h) == 5]
    points = [h if h is None or isinstance(h, list) or len(h) != 5 else None for h in heads]
    for k, decoded in zip(stored, _decode_many([heads[k] for k in stored])):
        points[k] = decoded
    out = [None] * len(names)
    done = []
    for k, (name, p) in enumerate(zip(names, points)):
        if p == []:
            out[k] = []
            continue
        if p is None:
            continue
        pts, flags, ends, x_min = p
        if (flags & _CUBIC).any() or ends[-1] + 1 != len(pts):
            continue
        offset = hmtx[name][1] - x_min
        points[k] = (pts + [offset, 0] if offset else pts, (flags & _ON).astype(bool), ends)
        done.append(k)
    if done:
        for k, loops in zip(done, _loops([points[k] for k in done])):
            out[k] = loops
    return out


def _head(g):
    """What a glyph's points are read from: [] for a glyph without contours, None
    for one left to the pen, (points, flags, ends, xMin) of an expanded simple
    glyph, or (data, ends, xMin, first flag byte, point count) of a stored one."""
    if g is None:
        return None
    data = getattr(g, "data", None)
    if data is None:
        n = getattr(g, "numberOfContours", -1)
        if n <= 0:
            return [] if n == 0 else None
        return (np.array(g.coordinates, float).reshape(-1, 2),
                np.frombuffer(bytes(g.flags), np.uint8),
                np.asarray(g.endPtsOfContours, np.int64), g.xMin)
    n = int.from_bytes(data[:2], "big", signed=True)
    if n == 0:
        return []
    if n < 0 or len(data) < 12 + 2 * n:
        return None
    ends = np.frombuffer(data, ">u2", n, 10).astype(np.int64)
    at = 12 + 2 * n + int.from_bytes(data[10 + 2 * n:12 + 2 * n], "big")
    return data, ends, int.from_bytes(data[2:4], "big", signed=True), at, int(ends[-1]) + 1


def _flags_many(heads):
    """The point flags of stored simple glyphs (:func:`_head`), stored run-length
    from byte ``at`` of each on: (the flags of all glyphs one after another, each
    glyph's count of them, the byte after each glyph's flags, whether its bytes hold
    them all; a glyph whose bytes end first gets none).  All glyphs at once: a byte
    is a repeat count when the byte before it is a flag with the REPEAT bit, so in a
    run of bytes with the bit set the flags are every other byte from the run's
    start (the window's first byte or one after a byte without the bit); a glyph's
    flags lie in its first 2 ``count`` bytes (each flag gives a point at least, and
    a count byte follows a flag)."""
    base = np.cumsum([0] + [len(h[0]) for h in heads])
    buf = np.frombuffer(b"".join(h[0] for h in heads), np.uint8)
    start = base[:-1] + np.array([h[3] for h in heads], np.int64)
    count = np.array([h[4] for h in heads], np.int64)
    size = np.maximum(np.minimum(start + 2 * count, base[1:]) - start, 0)
    first = size.cumsum() - size
    glyph = np.repeat(np.arange(len(heads)), size)
    pos = np.repeat(start - first, size) + np.arange(len(glyph))   # the windows' bytes
    byte = buf[pos]
    repeat = (byte & _REPEAT) != 0
    # the last byte without the bit before each byte (its window's start - 1 if none)
    prev = np.concatenate([[-1], np.where(repeat, -1, pos)[:-1]])
    prev[first[size > 0]] = start[size > 0] - 1
    flag = (pos - 1 - np.maximum.accumulate(prev)) % 2 == 0
    counted = flag & repeat & (pos + 1 < base[1:][glyph])
    reps = np.where(flag, np.where(counted, buf[np.minimum(pos + 1, len(buf) - 1)]
                                   .astype(np.int64) + 1, 1), 0)
    done = _segment_cumsum(reps, size)      # points up to each byte, in its glyph
    # each glyph's last flag: its first byte where the points reach its count
    last = np.full(len(heads), len(pos), np.int64)
    hit = np.flatnonzero(flag & (done >= count[glyph]))
    np.minimum.at(last, glyph[hit], hit)
    ok = last < len(pos)
    use = flag & (np.arange(len(pos)) <= np.repeat(np.where(ok, last, -1), size))
    last = last[ok]
    reps[last] -= done[last] - count[ok]        # its repeats cut at the count
    after = np.zeros(len(heads), np.int64)
    after[ok] = pos[last] + 1 + counted[last] - base[:-1][ok]
    return np.repeat(byte[use], reps[use]), np.where(ok, count, 0), after, ok


def _decode_many(heads):
    """(points, flags, contour ends, xMin) of stored simple glyphs (:func:`_head`),
    the flags glyph by glyph, the coordinates of all at once (the ``glyf`` format:
    x then y deltas of 0, 1 or 2 bytes each); None for a glyph whose bytes end
    too soon."""
    if not heads:
        return []
    fl, count, x_at, ok = _flags_many(heads)
    base = np.cumsum([0] + [len(h[0]) for h in heads])
    buf = np.frombuffer(b"".join(h[0] for h in heads), np.uint8)
    glyph = np.repeat(np.arange(len(heads)), count)
    x, y_at = _deltas(buf, base[:-1] + x_at, glyph, count, fl, _X_SHORT, _X_SAME)
    y, end = _deltas(buf, y_at, glyph, count, fl, _Y_SHORT, _Y_SAME)
    ok = np.array(ok) & (end <= base[1:])
    xy = np.stack([_segment_cumsum(x, count), _segment_cumsum(y, count)], axis=1).astype(float)
    split = np.cumsum(count)[:-1]
    return [(p, f, h[1], h[2]) if good else None for p, f, h, good in
            zip(np.split(xy, split), np.split(fl, split), heads, ok.tolist())]


def _segment_cumsum(d, count):
    """Running sums of ``d`` restarted at each of the consecutive runs ``count``."""
    c = np.cumsum(d)
    first = np.cumsum(count) - count
    before = np.where(count > 0, c[np.minimum(first, len(c) - 1)] - d[np.minimum(
        first, len(c) - 1)], 0) if len(c) else np.zeros(len(count), np.int64)
    return c - np.repeat(before, count)


def _deltas(buf, at, glyph, count, flags, short, same):
    """One coordinate's deltas of every glyph, glyph g's from byte ``at[g]`` of
    ``buf`` on: a short one is an unsigned byte (positive when ``same`` is set), a
    long one a signed 16-bit number, none 0 when ``same`` is set; (deltas, the
    byte after each glyph's)."""
    is_short, is_same = (flags & short) != 0, (flags & same) != 0
    size = np.where(is_short, 1, np.where(is_same, 0, 2))
    total = np.bincount(glyph, size, minlength=len(count)).astype(np.int64)
    start = np.repeat(at, count) + _segment_cumsum(size, count) - size
    last = max(len(buf) - 1, 0)
    lo = buf[np.minimum(start, last)].astype(np.int64)
    hi = buf[np.minimum(start + 1, last)].astype(np.int64)
    long_ = lo << 8 | hi
    long_ = np.where(long_ >= 32768, long_ - 65536, long_)
    d = np.where(is_short, np.where(is_same, lo, -lo), np.where(is_same, 0, long_))
    return d, at + total


def _loops(glyphs):
    """The loops of glyphs given as (points, on-curve, contour ends), every
    glyph's pieces built at once (see the module docstring); per glyph its
    loops, or None for a glyph with a contour without an on-curve point."""
    sizes = [len(p) for p, _, _ in glyphs]
    pts = np.concatenate([p for p, _, _ in glyphs])
    on = np.concatenate([o for _, o, _ in glyphs])
    base = np.cumsum(sizes) - sizes
    ends = np.concatenate([e + b for (_, _, e), b in zip(glyphs, base)])
    n_contours = np.array([len(e) for _, _, e in glyphs], np.int64)
    length = np.diff(np.concatenate([[-1], ends]))
    first = ends - length + 1
    contour = np.repeat(np.arange(len(ends)), length)
    rel = np.arange(len(pts)) - first[contour]
    first_on = np.minimum.reduceat(np.where(on, rel, length[contour]), first)
    bad = np.zeros(len(glyphs), bool)
    bad[np.repeat(np.arange(len(glyphs)), n_contours)[first_on >= length]] = True
    # position t = 1 .. length of each contour from its first on-curve point (t =
    # length: the start again); a quadratic per off-curve point, a line per
    # on-curve point after an on-curve point
    c_first, c_len, c_on = first[contour], length[contour], first_on[contour] % length[contour]

    def at(t):
        return c_first + (c_on + t) % c_len
    prev, cur, nxt = at(rel), at(rel + 1), at(rel + 2)
    quad = ~on[cur]
    line = on[cur] & on[prev]
    p, q, r = pts[prev], pts[cur], pts[nxt]
    start = np.where(on[prev][:, None], p, 0.5 * (p + q))
    end = np.where(on[nxt][:, None], r, 0.5 * (q + r))
    kind = np.where(quad, 1, np.where(line, 0, -1))   # -1: a point ending a quadratic
    keep = kind >= 0
    kind, owner = kind[keep], contour[keep]
    h_line = np.ones((int((kind == 0).sum()), 2, 3))
    h_line[:, 0, :2], h_line[:, 1, :2] = p[keep][kind == 0], q[keep][kind == 0]
    h_quad = np.ones((int((kind == 1).sum()), 3, 3))
    h_quad[:, 0, :2], h_quad[:, 1, :2], h_quad[:, 2, :2] = (start[keep][kind == 1],
                                                            q[keep][kind == 1],
                                                            end[keep][kind == 1])
    groups = [(np.flatnonzero(kind == 0), h_line), (np.flatnonzero(kind == 1), h_quad)]
    return glyph_loops(groups, len(kind), owner, n_contours, bad)
