"""Reading font glyphs (fontTools pens) -> regions.

Every reader returns a region (list of closed loops of pieces, see :mod:`morph.region`)
normalised by :func:`morph.region.orient_region`: outer loops counter-clockwise,
holes clockwise, **y axis up**.

Glyphs are read in font units (y up already).  TrueType quadratics become degree-2
pieces (implied on-curve points made explicit), CFF cubics degree-3 pieces; composite
glyphs are decomposed.  Orientation uses the nonzero rule.

Every bad input raises :class:`morph.errors.ParseError` naming the input.
"""

import os
import re
from functools import lru_cache
from pathlib import Path

import numpy as np

from .. import piece as pc
from ..errors import ParseError, one_line
from ..region import orient_regions, without_zero_length, zero_length_mask
from ..trim import fill_region
from .pens import RawContour, closing_line, record_segments
from .shape import Shape

__all__ = [
    "cubic_test_font_path",
    "default_font_path",
    "font_display_name",
    "full_location",
    "glyph_name",
    "glyph_region",
    "instantiate_font",
    "load_font",
    "parse_location",
    "read_glyph",
    "read_glyphs",
]

_FONT_DIR = Path(__file__).resolve().parent.parent / "fonts" / "data"


# =========================================================================== fonts

def default_font_path():
    """Path of the bundled default font (Noto Sans Regular, TrueType, quadratic)."""
    return str(_FONT_DIR / "NotoSans-Regular.ttf")


def cubic_test_font_path():
    """Path of the bundled CFF (cubic) version of Noto Sans Regular."""
    return str(_FONT_DIR / "NotoSans-Regular.otf")


def load_font(path=None, location=None):
    """The fontTools ``TTFont`` at ``path`` (None: the bundled TrueType font; a font
    collection, .ttc/.otc: its first font), cached.

    ``location``: design-space coordinates of a variable font, a dict such as
    ``{"wght": 700}`` or a string ``"wght=700,wdth=90"`` (:func:`parse_location`);
    the font is then a static instance made by :func:`instantiate_font`.  None or
    empty: the font as stored (for a variable font its outlines are the default
    instance).

    Raises:
        ParseError: the file is missing or is not a font fontTools can read
            (``.source`` is the path); a bad location (see :func:`instantiate_font`).
    """
    if path is None:
        path = default_font_path()
    loc = tuple(sorted(parse_location(location).items()))
    if hasattr(path, "getGlyphSet"):  # already a TTFont
        return instantiate_font(path, dict(loc)) if loc else path
    if not str(os.fspath(path)).strip():
        raise ParseError("empty font path", path)
    if os.path.isdir(path):
        raise ParseError("cannot read font %s: it is a folder" % path, path)
    return _load_font_cached(os.path.abspath(os.fspath(path)), loc)


@lru_cache(maxsize=16)
def _load_font_cached(path, loc=()):
    from fontTools.ttLib import TTFont

    if loc:
        font = instantiate_font(_load_font_cached(path), dict(loc))
        font._morph_path = path
        return font
    if not os.path.isfile(path):
        raise ParseError("cannot read font %s: no such file" % path, path)
    try:
        font = TTFont(path, fontNumber=0)  # a collection (.ttc/.otc): its first font
        font.getGlyphOrder()
        font["head"]
    except Exception as exc:  # fontTools raises many types for garbage input
        raise ParseError("cannot read font %s: %s" % (path, one_line(exc)), path) from exc
    font._morph_path = path
    return font


def parse_location(spec):
    """``"wght=700,wdth=90"`` (or a dict, or None) -> ``{"wght": 700.0, "wdth": 90.0}``.

    Raises:
        ParseError: not ``TAG=NUMBER`` items separated by commas.
    """
    if not spec:
        return {}
    if isinstance(spec, dict):
        return {str(k): float(v) for k, v in spec.items()}
    out = {}
    for item in str(spec).split(","):
        m = re.fullmatch(r"\s*([A-Za-z0-9 ]{1,4}?)\s*=\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*",
                         item)
        if not m:
            raise ParseError("location must look like wght=700,wdth=90, got %r" % spec, spec)
        try:
            out[m.group(1)] = float(m.group(2))
        except ValueError:
            raise ParseError("location value not understood: %r" % item, spec) from None
    return out


def instantiate_font(font, location=None):
    """A static instance of a variable ``TTFont`` (fontTools.varLib.instancer).

    Axes missing from ``location`` (dict or string, see :func:`parse_location`) take
    their default value, so ``location=None`` gives the default instance.  A static
    font is returned as it is when ``location`` is empty.  The instance is a new
    ``TTFont`` (``font`` is not changed); its outlines keep their overlaps
    (``OverlapMode.KEEP_AND_SET_FLAGS``); its names are the instance's (e.g. "Bold",
    from the STAT table) where the font has one.

    Raises:
        ParseError: a location for a static font, an axis the font does not have,
            or a value outside the axis range (the message lists the axes).
    """
    from fontTools.varLib import instancer

    full = full_location(font, location)
    if full is None:
        return font
    label = _font_label(font)
    try:
        if "STAT" in font:  # names of the instance (e.g. "Bold") from the STAT table
            try:
                return instancer.instantiateVariableFont(font, full, inplace=False,
                                                         updateFontNames=True)
            except Exception:  # STAT without the axis values names need
                pass
        return instancer.instantiateVariableFont(font, full, inplace=False)
    except Exception as exc:  # fontTools raises many types for broken variation data
        raise ParseError("cannot instantiate font %s at %s: %s"
                         % (label, full, one_line(exc)), label) from exc


def font_display_name(font, default="font"):
    """The name a person reads for an open ``TTFont``: its full name (name ID 4),
    else its family and style (IDs 16 and 17, else 1 and 2), else its PostScript
    name (ID 6), else ``default``.  Real fonts lack some of these records; none is
    required."""
    from .names import name_table

    try:
        name = name_table(font)   # its stored records, where they can be read so
    except Exception:  # an unreadable name table
        return default
    if name is None:
        return default
    full = name.getDebugName(4)
    if full:
        return full
    family = name.getDebugName(16) or name.getDebugName(1)
    if family:
        style = name.getDebugName(17) or name.getDebugName(2)
        return "%s %s" % (family, style) if style else family
    return name.getDebugName(6) or default


def full_location(font, location):
    """The user-space location of every axis of a variable ``TTFont`` (axes not in
    ``location`` at their default), checked; None for a static font and no location.

    Raises:
        ParseError: a location for a static font, an axis the font does not have,
            or a value outside the axis range (the message lists the axes).
    """
    loc = parse_location(location)
    label = _font_label(font)
    if "fvar" not in font:
        if loc:
            raise ParseError("font %s is not a variable font: --location %s cannot apply"
                             % (label, ",".join("%s=%g" % kv for kv in loc.items())), label)
        return None
    axes = {a.axisTag: a for a in font["fvar"].axes}
    ranges = ", ".join("%s %g..%g (default %g)" % (t, a.minValue, a.maxValue, a.defaultValue)
                       for t, a in axes.items())
    for tag, value in loc.items():
        a = axes.get(tag)
        if a is None or not a.minValue <= value <= a.maxValue:
            raise ParseError("font %s has no location %s=%g: its axes are %s"
                             % (label, tag, value, ranges), label)
    return {t: loc.get(t, a.defaultValue) for t, a in axes.items()}


def _font_label(font):
    path = getattr(font, "_morph_path", None)
    if path:
        return os.path.basename(path)
    return font_display_name(font)


def _filled_loop(contour, label):
    """A glyph contour (:class:`.pens.RawContour`) as a loop: zero-length pieces
    dropped, closed by a line when it ends away from its start; None when nothing of
    positive length is left.  An open contour (``endPath``) must end where it starts.

    Raises:
        ParseError: an open contour that does not end at its start.
    """
    pieces = without_zero_length(contour.pieces)
    if not pieces:
        return None
    if not contour.closed and not np.array_equal(pc.end(pieces[-1]), contour.start):
        raise ParseError("%s has an open contour" % label, label)
    return closing_line(RawContour(pieces, contour.start, True))


def glyph_name(font, char_or_name):
    """The name of the glyph of a single character (cmap) or of a glyph name in an
    open ``TTFont``.

    Raises:
        ParseError: not a non-empty string; no such glyph.
    """
    if not isinstance(char_or_name, str) or not char_or_name:
        raise ParseError("a glyph is named by a character or a glyph name, got %r"
                         % (char_or_name,), char_or_name)
    if len(char_or_name) == 1:
        name = (font.getBestCmap() or {}).get(ord(char_or_name))
    else:
        name = char_or_name if char_or_name in set(font.getGlyphOrder()) else None
    if name is None:
        raise ParseError("font %s has no glyph for %r" % (_font_label(font), char_or_name),
                         char_or_name)
    return name


def glyph_region(char_or_name, font=None, location=None):
    """Outline of one glyph as a :class:`~morph.parse.shape.Shape` (region in font units,
    y up; ``advance_width``, ``lsb`` from ``hmtx``, ``units_per_em`` from ``head``).

    A single character is looked up in the font's cmap; a longer string is taken as
    a glyph name (``"g"`` is the character, ``"ampersand"`` a glyph name).  ``font``
    is a path, a ``TTFont``, or None for the bundled TrueType font; ``location``
    picks an instance of a variable font (:func:`load_font`).

    Raises:
        ParseError: unreadable font; no glyph for the character or name; a glyph
            without contours (e.g. space); an open contour.
    """
    font = load_font(font)
    loc = full_location(font, location) if parse_location(location) else None
    return read_glyph(font, glyph_name(font, char_or_name), source=char_or_name, location=loc)


def read_glyph(font, name, source=None, location=None):
    """The glyph named ``name`` (exactly: no cmap lookup) of an open ``TTFont`` as a
    :class:`~morph.parse.shape.Shape`; ``source``: what was asked for (default:
    ``name``), also named in errors.  ``location``: a variable font's user-space
    location (every axis, :func:`full_location`): the glyph is drawn there from the
    variations directly (``TTFont.getGlyphSet(location=...)``, its advance too),
    without instancing the whole font for one glyph (5x faster for Cormorant's g).

    Raises:
        ParseError: no such glyph; a glyph without contours; an open contour.
    """
    shape = read_glyphs(font, [name], location, [source])[0]
    if isinstance(shape, ParseError):
        raise shape
    return shape


def read_glyphs(font, names, location=None, sources=None):
    """:func:`read_glyph` of each of the glyphs ``names`` of an open ``TTFont``, the
    contours of all oriented together (:func:`morph.region.orient_regions`: the
    same regions, a fraction of the time of one glyph after another).  Returns one
    item per name: its :class:`~morph.parse.shape.Shape`, or the
    :class:`~morph.errors.ParseError` that :func:`read_glyph` raises for it (no
    such glyph, no contours, an open contour), so that one glyph does not stop the
    others.  ``sources``: what was asked for, one per name (default: the names)."""
    label = _font_label(font)
    glyph_set = font.getGlyphSet(location=location) if location else font.getGlyphSet()
    sources = list(names) if sources is None else [n if s is None else s
                                                   for n, s in zip(names, sources)]
    direct = _direct_loops(font, names, location)
    out, todo, drawn = [], [], []
    for name, source, loops in zip(names, sources, direct):
        try:
            out.append(_glyph_segments(glyph_set, name, source, label) if loops is None
                       else loops)
            todo.append(len(out) - 1)
            if loops is None:
                drawn.append(len(out) - 1)
        except ParseError as exc:
            out.append(exc)
    loops = _filled_loops([out[k] for k in drawn],
                          ["glyph %r of font %s" % (names[k], label) for k in drawn])
    for k, item in zip(drawn, loops):
        out[k] = item
    todo = [k for k in todo if not isinstance(out[k], ParseError)]
    regions = orient_regions([out[k] for k in todo], "nonzero", on_crossing=fill_region)
    for k, loops in zip(todo, regions):
        name, source = names[k], sources[k]
        if not loops:
            out[k] = ParseError("glyph %r of font %s is empty (no contours)" % (name, label),
                                source)
            continue
        advance, lsb = font["hmtx"][name]
        if location:  # the advance at the location, rounded as an instance's; lsb: the outline's
            from fontTools.misc.roundTools import otRound

            from ..region import region_bbox

            advance, lsb = otRound(glyph_set[name].width), float(region_bbox(loops)[0])
        out[k] = Shape(loops, name, source, font["head"].unitsPerEm, advance, lsb)
    return out


def _direct_loops(font, names, location):
    """Per name the loops of a glyph of a static font decoded from its bytes (the
    pieces drawing gives, without the pen): a simple TrueType glyph
    (:func:`morph.parse.truetype.simple_glyph_loops`), a CFF charstring
    (:func:`morph.parse.charstrings.cff_glyph_loops`); else None (the glyph is
    drawn)."""
    if location or not ("glyf" in font or "CFF " in font):
        return [None] * len(names)
    if "CFF " in font:
        from .charstrings import cff_glyph_loops

        return cff_glyph_loops(font, names)
    from .truetype import simple_glyph_loops

    return simple_glyph_loops(font, names)


def _glyph_loops(glyph_set, name, source, label):
    """The closed loops of glyph ``name`` (:func:`_filled_loop` of its contours), not
    yet oriented.

    Raises:
        ParseError: no such glyph; a glyph that cannot be drawn; an open contour.
    """
    loops = _filled_loops([_glyph_segments(glyph_set, name, source, label)],
                          ["glyph %r of font %s" % (name, label)])[0]
    if isinstance(loops, ParseError):
        raise loops
    return loops


def _glyph_segments(glyph_set, name, source, label):
    """The contours of glyph ``name`` as drawn (:func:`.pens.record_segments`).

    Raises:
        ParseError: no such glyph; a glyph that cannot be drawn.
    """
    where = "glyph %r of font %s" % (name, label)
    if name not in glyph_set:
        raise ParseError("font %s has no glyph named %r" % (label, name), source)
    try:
        return record_segments(glyph_set[name].draw, where, glyph_set)
    except ParseError:
        raise
    except Exception as exc:
        raise ParseError("cannot draw glyph %r of font %s: %s" % (name, label, one_line(exc)),
                         source) from exc


def _filled_loops(glyphs, labels):
    """:func:`_filled_loop` of every contour of many glyphs (their
    :func:`.pens.record_segments`), the pieces of all built at once, one stack per
    degree (weights 1, as :func:`morph.piece.from_points` makes them; a loop's
    pieces are rows of the stacks).  Per glyph its loops (contours left empty
    dropped), or the ParseError of its first open contour (``labels[g]`` names it)."""
    contours = [c for g in glyphs for c in g]
    segments = [seg for c in contours for seg in c.pieces]
    sizes = np.array([len(c.pieces) for c in contours], np.int64)
    groups = []
    by_length = {}
    for k, seg in enumerate(segments):
        by_length.setdefault(len(seg), []).append(k)
    for m, ks in by_length.items():
        h = np.ones((len(ks), m, 3))
        h[:, :, :2] = [segments[k] for k in ks]
        groups.append((np.array(ks, np.int64), h))
    pieces = pc.Pieces(groups, len(segments))
    zero = zero_length_mask(pieces) if len(segments) else np.zeros(0, bool)
    rows = pieces.rows()
    bounds = np.concatenate([[0], np.cumsum(sizes)]).tolist()
    zero = zero.tolist()
    out, c = [], 0
    for g, glyph in enumerate(glyphs):
        loops, error = [], None
        for contour in glyph:
            a, b = bounds[c], bounds[c + 1]
            c += 1
            kept = [rows[k] for k in range(a, b) if not zero[k]]
            if not kept or error is not None:
                continue
            start = np.asarray(contour.start, float)
            if not np.array_equal(pc.end(kept[-1]), start):
                if not contour.closed:
                    error = ParseError("%s has an open contour" % labels[g], labels[g])
                    continue
                kept.append(pc.line(pc.end(kept[-1]), start))
            loops.append(kept)
        out.append(error if error is not None else loops)
    return out
