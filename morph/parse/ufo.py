"""Reading skeleton glyphs from UFO sources (ufoLib2) -> paths of pieces.

A *skeleton* is a pen's centre line: open contours are native to UFO (a contour whose
first point has type ``move``), closed ones are allowed too.  A glyph's contours
become a list of paths ``(pieces, closed)`` in font units (y up): ``pieces`` is a list
of polynomial pieces (:func:`morph.piece.line`, :func:`~morph.piece.quadratic`,
:func:`~morph.piece.cubic`; TrueType quadratic runs split at their implied on-curve
points, cubic runs with more than two off-curves split as fontTools does) joined end
to start; ``closed`` says whether the last piece returns to the first one's start (a
closing line is added when a closed contour's last point differs from its first).

Zero-length pieces are dropped; a contour of one point, or one whose pieces all have
zero length (a dot drawn as a single pen touch), becomes ``([line(p, p)], False)``: a
zero-length open path, whose stroke is the nib itself.

Components are *not* decomposed here (:func:`glyph_paths` reads contours only);
:func:`component_paths` decomposes a component with its transformation when a caller
needs that.  Every bad input raises :class:`morph.errors.ParseError` naming it.
"""

import os

import numpy as np

from .. import piece as pc
from ..errors import ParseError, one_line
from .pens import closing_line, record_contours

__all__ = ["load_ufo", "glyph_paths", "component_paths", "contour_paths", "decomposed_paths",
           "transform_paths", "glyph_names_for"]


def load_ufo(path, lazy=True):
    """The ``ufoLib2.Font`` at ``path`` (a ``.ufo`` folder); ``lazy``: glyphs read on
    first access (ufoLib2's lazy loading) instead of all at once.

    Raises:
        ParseError: missing path, not a folder, or not a UFO ufoLib2 can read.
    """
    import ufoLib2

    text = os.fspath(path)
    if not os.path.exists(text):
        raise ParseError("cannot read UFO %s: no such folder" % text, text)
    if not os.path.isdir(text):
        raise ParseError("cannot read UFO %s: it is not a folder" % text, text)
    try:
        font = ufoLib2.Font.open(text, lazy=lazy)
    except Exception as exc:  # fontTools.ufoLib raises several types for bad input
        raise ParseError("cannot read UFO %s: %s" % (text, one_line(exc)), text) from exc
    upm = font.info.unitsPerEm
    if upm is not None and not 0 < upm < float("inf"):
        raise ParseError("UFO %s has unitsPerEm %r: it must be positive" % (text, upm), text)
    return font


def component_cycle(font, names):
    """A component cycle reachable from the glyphs ``names`` of a ufoLib2 font, as a
    list of glyph names from a glyph back to itself (``["b", "b"]``), or None.
    Missing base glyphs are not followed (they are reported where they are used)."""
    state = {}  # 1: on the current path, 2: done
    for root in names:
        if root in state or root not in font:
            continue
        path, stack = [root], [iter(c.baseGlyph for c in font[root].components)]
        state[root] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            elif nxt not in state and nxt in font:
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(c.baseGlyph for c in font[nxt].components))
    return None


def _zero_length(piece):
    pts = pc.cartesian(piece)
    return bool(np.all(pts == pts[0]))


def _skeleton_path(contour):
    """A skeleton contour (:class:`.pens.RawContour`) as a path ``(pieces, closed)``:
    a closing line added to a closed one that ends away from its start, zero-length
    pieces dropped, a single point or a dot of zero-length pieces as
    ``([line(p, p)], False)``."""
    pieces = closing_line(contour) if contour.closed else list(contour.pieces)
    kept = [p for p in pieces if not _zero_length(p)]
    if not kept:
        return [pc.line(contour.start, contour.start)], False
    return kept, contour.closed


def contour_paths(contours, label="contours"):
    """Paths ``(pieces, closed)`` of an iterable of ufoLib2 contours (see module doc).

    Raises:
        ParseError: a contour fontTools cannot draw (bad point types, a contour that
            ends with off-curve points while open) or a non-finite coordinate.
    """
    def draw(pen):
        for contour in contours:
            try:
                contour.draw(pen)
            except ParseError:
                raise
            except Exception as exc:
                raise ParseError("%s: cannot read a contour: %s" % (label, one_line(exc)),
                                 label) from exc

    return [_skeleton_path(c) for c in record_contours(draw, label)]


def glyph_paths(glyph):
    """Paths ``(pieces, closed)`` of a ufoLib2 glyph's own contours (components not
    included), in font units.  Raises ParseError as :func:`contour_paths`."""
    return contour_paths(glyph.contours, "glyph %r" % glyph.name)


def transform_paths(paths, transformation):
    """Paths mapped by an affine ``(xx, xy, yx, yy, dx, dy)`` transformation (fontTools
    order: x' = xx x + yx y + dx, y' = xy x + yy y + dy)."""
    xx, xy, yx, yy, dx, dy = (float(v) for v in transformation)
    m = [[xx, yx, dx], [xy, yy, dy]]
    return [([pc.transform(p, m) for p in pieces], closed) for pieces, closed in paths]


def component_paths(font, component, _depth=0):
    """Paths of a component, decomposed recursively and placed by its transformation.

    Raises:
        ParseError: the base glyph is missing, or components nest deeper than 32
            (a cycle).
    """
    if _depth > 32:
        raise ParseError("components nest deeper than 32 levels at %r (a cycle?)"
                         % component.baseGlyph, component.baseGlyph)
    if component.baseGlyph not in font:
        raise ParseError("component base glyph %r is missing" % component.baseGlyph,
                         component.baseGlyph)
    paths, subs = _base_outline(font, component.baseGlyph)
    for sub in subs:
        paths.extend(component_paths(font, sub, _depth + 1))
    return transform_paths(paths, tuple(component.transformation))


def _base_outline(font, name):
    """(paths, components) of glyph ``name``: from its ``.glif`` bytes where ``font``
    reads them (:meth:`morph.fonts.stream.SkeletonSource.skeleton_outlines` of a UFO
    on disk: no ufoLib2 glyph is made; a base is read once for the run), else from
    the font's glyph."""
    read = getattr(font, "skeleton_outlines", None)
    if read is not None:
        outline = read([name], keep=True)[0]
        if outline is not None:
            return outline
    base = font[name]
    return glyph_paths(base), base.components


def decomposed_paths(font, name):
    """Paths of the glyph ``name`` of a ufoLib2 font: its own contours, then every
    component decomposed (:func:`component_paths`), in the glyph's coordinates.

    Raises:
        ParseError: as :func:`glyph_paths` and :func:`component_paths`.
    """
    glyph = font[name]
    paths = glyph_paths(glyph)
    for component in glyph.components:
        paths.extend(component_paths(font, component))
    return paths


def glyph_names_for(font, items):
    """Glyph names of a UFO for a list of characters (looked up by unicode) and glyph
    names, in order, without repeats.  A one-character item that is also a glyph name
    but has no unicode mapping is taken as the name.

    Raises:
        ParseError: an item names no glyph of the font.
    """
    cmap = {}
    for g in font:
        for u in g.unicodes:
            cmap.setdefault(u, g.name)
    out = []
    for item in items:
        name = None
        if len(item) == 1:
            name = cmap.get(ord(item))
        if name is None and item in font:
            name = item
        if name is None:
            raise ParseError("the UFO has no glyph for %r" % item, item)
        if name not in out:
            out.append(name)
    return out
