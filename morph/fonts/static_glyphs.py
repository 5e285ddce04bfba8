"""The glyphs the static compiler (:mod:`morph.fonts.tables_static`) writes beside
the stored outlines, as ufo2ft writes them: the ``.notdef`` stub ufo2ft adds
(:class:`_Notdef`, for CFF and glyf), composites decomposed into CFF programs from
the stored outlines (:class:`_Decomposer`, :func:`_placed`), and the font's Type 2
programs in glyph order with their advances (:class:`_Programs`), which the CFF
table is written from.

It stands above the streaming compiler (:mod:`morph.fonts.stream`, imported where a
composite is decomposed) and the font info values (:mod:`morph.fonts.fontinfo`),
below the compiler that uses them.
"""

from .cff_encoding import _NO_WIDTHS, bounded_t2_pen
from .fontinfo import _ot_round, info_value


def _closed(pen, corners):
    """A closed polygon through ``corners``, its start repeated as ufo2ft draws it."""
    pen.moveTo(corners[0])
    for p in corners[1:] + corners[:1]:
        pen.lineTo(p)
    pen.closePath()


class _Notdef:
    """ufo2ft's ``.notdef`` stub: two rectangles (the em box's width half the em,
    between descender and ascender, a twentieth of the em thick)."""

    def __init__(self, info, reverse):
        self.name = ".notdef"
        upm = _ot_round(info_value(info, "unitsPerEm"))
        self.upm, self.reverse = upm, reverse
        self.ascender = _ot_round(info_value(info, "ascender"))
        self.descender = _ot_round(info_value(info, "descender"))
        self.width = _ot_round(upm * 0.5)
        self.unicodes, self.components, self.anchors, self.lib = [], [], [], {}

    @property
    def height(self):
        return self.ascender - self.descender

    def draw(self, pen):
        if self.reverse:
            from fontTools.pens.reverseContourPen import ReverseContourPen

            pen = ReverseContourPen(pen)
        width = _ot_round(self.upm * 0.5)
        stroke = _ot_round(self.upm * 0.05)
        x0, x1, y0, y1 = stroke, width - stroke, self.descender, self.ascender
        _closed(pen, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
        x0, x1, y1, y0 = x0 + stroke, x1 - stroke, y1 - stroke, y0 + stroke
        _closed(pen, [(x0, y0), (x0, y1), (x1, y1), (x1, y0)])

    def drawPoints(self, pen):
        from fontTools.pens.pointPen import SegmentToPointPen

        self.draw(SegmentToPointPen(pen, guessSmooth=False))

    def charstring(self, prefix):
        """(Type 2 program, bounds) of :meth:`draw` (CFF: not reversed), one
        ``rmoveto`` / ``rlineto`` a segment, after ``prefix`` (the advance)."""
        from fontTools.misc.psCharStrings import encodeIntT2

        class Pen:
            def __init__(self):
                self.code, self.at, self.points = [prefix], (0, 0), []

            def _to(self, p, op):
                self.code += [encodeIntT2(p[0] - self.at[0]), encodeIntT2(p[1] - self.at[1]),
                              bytes([op])]
                self.at = p
                self.points.append(p)

            def moveTo(self, p):
                self._to(p, _RMOVETO)

            def lineTo(self, p):
                self._to(p, _RLINETO)

            def closePath(self):
                pass

        pen = Pen()
        self.draw(pen)
        xs, ys = [p[0] for p in pen.points], [p[1] for p in pen.points]
        return b"".join(pen.code) + bytes([_ENDCHAR]), (min(xs), min(ys), max(xs), max(ys))


#: Type 2 operators
_RMOVETO, _RLINETO, _ENDCHAR = 21, 5, 14


class _Decomposer:
    """CFF programs of glyphs with components, decomposed from the stored outlines
    as ufo2ft's outline compiler of a streamed font draws them
    (:class:`morph.fonts.stored.StoredCFF`): the glyph's own stored contours, then
    each component's base (its own contours, then its components, recursively)
    through the component's transformation (applied innermost first, each in
    floating point as fontTools' ``TransformPointPen`` applies it), every point
    rounded as ``T2CharStringPen`` rounds it (``otRound``).  The outlines are
    arrays: each stored base read once from its charstring
    (:func:`morph.parse.charstrings.charstring_outlines`), the decomposed glyphs
    transformed and compiled together (:func:`morph.fonts.stream.compile_outlines`:
    unspecialized, as the stored glyphs are; the subroutinizer rewrites every
    charstring from its path); a glyph the arrays do not take is drawn with the
    pens.  ``shells``: every glyph of the font (those not exported too: their
    outlines are drawn into the glyphs that use them)."""

    def __init__(self, shells, store):
        self.shells, self.store, self.drawn = shells, store, {}
        self.read = {}      # stored glyph name -> its Outline (None: not read)

    def many(self, names, prefixes):
        """[(program, bounds)] of the glyphs ``names``, each program its advance's
        ``prefix`` (:func:`morph.fonts.stream.width_prefix`) then its outline."""
        if not names:   # no composite glyph: fontTools' charstring module not loaded
            return []
        from .stream import compile_outlines

        parts = [self._parts(name, ()) for name in names]
        self._read_stored({base for glyph in parts for base, _ in glyph})
        outlines = _placed(parts, self.read)
        done = compile_outlines([o for o in outlines if o is not None], "cff")[::-1]
        out = []
        for name, prefix, outline in zip(names, prefixes, outlines):
            if outline is None:
                out.append(self._drawn_program(name, prefix))
            else:
                data, bounds = done.pop()
                out.append((prefix + data, bounds))
        return out

    def _parts(self, name, chain):
        """[(stored glyph name, transformations innermost first)] that make glyph
        ``name`` drawn through ``chain``, in drawing order."""
        out = [(name, chain)] if name in self.store else []
        for c in self.shells[name].components:
            if c.baseGlyph in self.shells:
                out += self._parts(c.baseGlyph, (tuple(c.transformation),) + chain)
        return out

    def _read_stored(self, names):
        from fontTools.misc.psCharStrings import T2CharString

        from ..parse.charstrings import charstring_outlines

        names = sorted(n for n in names if n not in self.read)
        charstrings = [T2CharString(bytecode=self.store[n][0], private=_NO_WIDTHS,
                                    globalSubrs=[]) for n in names]
        self.read.update(zip(names, charstring_outlines(charstrings)))

    def _drawn_program(self, name, prefix):
        """(program, bounds) of glyph ``name`` drawn with fontTools' pens
        (unspecialized, its advance written by ``prefix``)."""
        from fontTools.pens.pointPen import PointToSegmentPen

        pen = bounded_t2_pen(None, None, roundTolerance=0.5)
        self._decomposed(name, PointToSegmentPen(pen))
        cs = pen.getCharString(None, None, optimize=False)
        cs.compile()
        return prefix + bytes(cs.bytecode), pen.bounds.bounds

    def _own(self, name, pen):
        """``name``'s stored contours, decoded once (a base is drawn into every
        glyph that uses it)."""
        rec = self.drawn.get(name)
        if rec is None:
            from fontTools.misc.psCharStrings import T2CharString
            from fontTools.pens.pointPen import SegmentToPointPen
            from fontTools.pens.recordingPen import RecordingPointPen

            rec = self.drawn[name] = RecordingPointPen()
            if name in self.store:
                T2CharString(bytecode=self.store[name][0], private=_NO_WIDTHS,
                             globalSubrs=[]).draw(SegmentToPointPen(rec))
        rec.replay(pen)

    def _decomposed(self, name, pen):
        from fontTools.pens.transformPen import TransformPointPen

        self._own(name, pen)
        for c in self.shells[name].components:
            if c.baseGlyph in self.shells:
                self._decomposed(c.baseGlyph, TransformPointPen(pen, tuple(c.transformation)))


def _placed(parts, read):
    """Per glyph (its :meth:`_Decomposer._parts`) its outline: the stored outlines
    ``read`` concatenated in order, each through its transformations (all parts'
    points at once, one level of nesting at a time), rounded; None for a glyph with
    a part not read."""
    import numpy as np

    from ..outline import Outline

    ok = [all(read.get(base) is not None for base, _ in glyph) for glyph in parts]
    flat = [(g, read[base], chain) for g, glyph in enumerate(parts) if ok[g]
            for base, chain in glyph]
    if not flat:
        return [None] * len(parts)
    n_points = np.array([len(o.points) for _, o, _ in flat], np.int64)
    pts = np.concatenate([o.points for _, o, _ in flat])
    depth = max(len(chain) for _, _, chain in flat)
    for level in range(depth):
        t = np.array([chain[level] if len(chain) > level else (1, 0, 0, 1, 0, 0)
                      for _, _, chain in flat], float)
        moved = np.repeat(np.array([len(chain) > level for _, _, chain in flat]), n_points)
        tp = np.repeat(t, n_points, axis=0)[moved]
        x, y = pts[moved, 0], pts[moved, 1]
        pts[moved] = np.stack([tp[:, 0] * x + tp[:, 2] * y + tp[:, 4],
                               tp[:, 1] * x + tp[:, 3] * y + tp[:, 5]], axis=1)
    pts = np.floor(pts + 0.5)              # otRound, as T2CharStringPen rounds
    at = np.concatenate([[0], np.cumsum(n_points)]).tolist()
    by_glyph = [[] for _ in parts]
    for k, (g, o, _) in enumerate(flat):
        by_glyph[g].append((pts[at[k]:at[k + 1]], o.sizes, o.counts))
    return [Outline(np.concatenate([p for p, _, _ in rows]),
                    np.concatenate([s for _, s, _ in rows]),
                    np.concatenate([c for _, _, c in rows])) if ok[g] and rows else None
            for g, rows in enumerate(by_glyph)]


class _Programs:
    """The Type 2 programs of a font's glyphs in glyph order (``k``: a glyph's
    place), each its advance's prefix then its outline, held as little as the store
    allows: a stored glyph's outline stays in the store (an
    :class:`morph.fonts.stream.OutlineStore` writes it to the table's buffer when the
    table is written, a plain mapping gives its bytes); the few others (decomposed,
    ``.notdef``, empty) are kept whole.  Their sizes and bounds are arrays."""

    def __init__(self, store, n):
        import numpy as np

        self.store, self.n = store, n
        self.sizes = np.zeros(n, np.int64)
        self.prefix_sizes = np.zeros(n, np.int64)
        self.boxes = np.full((n, 4), np.nan)     # the stored glyphs' bounds
        self.names = [None] * n      # a stored glyph's name
        self.prefixes = [None] * n   # the same prefix object for the same advance
        self.own_programs, self.own_bounds = {}, {}
        self._shared = {}

    def _prefix(self, k, prefix):
        prefix = self.prefixes[k] = self._shared.setdefault(prefix, prefix)
        self.prefix_sizes[k] = len(prefix)

    def stored(self, k, prefix, name):
        """Glyph ``k``: ``prefix``, then the stored outline of glyph ``name``."""
        self._prefix(k, prefix)
        self.names[k] = name
        if hasattr(self.store, "read_into"):
            size, bounds = self.store.size(name), self.store.bounds(name)
        else:
            data, bounds = self.store[name]
            size = len(data)
        self.sizes[k] = len(prefix) + size
        if bounds is not None:
            self.boxes[k] = bounds

    def own(self, k, prefix, program, bounds):
        """Glyph ``k``: the whole ``program`` (its advance written by ``prefix``,
        unless the pen wrote it otherwise) and its ``bounds``."""
        self._prefix(k, prefix)
        self.own_programs[k], self.own_bounds[k] = bytes(program), bounds
        self.sizes[k] = len(program)

    def bounds_list(self):
        """Every glyph's bounds (None for none), in glyph order."""
        rows = self.boxes.tolist()
        return [self.own_bounds[k] if k in self.own_bounds else
                None if rows[k][0] != rows[k][0] else tuple(rows[k]) for k in range(self.n)]

    def write_to(self, k, out):
        """Append glyph ``k``'s program to the bytearray ``out``."""
        if k in self.own_programs:
            out += self.own_programs[k]
            return
        out += self.prefixes[k]
        if hasattr(self.store, "read_into"):
            self.store.read_into(self.names[k], out)
        else:
            out += self.store[self.names[k]][0]

    def __len__(self):
        return self.n

    def __getitem__(self, k):
        out = bytearray()
        self.write_to(k, out)
        return bytes(out)

    # what morph.fonts.subrs.font_subroutines reads
    def prefix(self, k):
        return self.prefixes[k]

    def prefixed(self):
        return all(self.own_programs[k].startswith(self.prefixes[k]) for k in self.own_programs)

    def body_sizes(self):
        return self.sizes - self.prefix_sizes

    def bodies(self, a, b):
        return [self[k][self.prefix_sizes[k]:] for k in range(a, b)]
