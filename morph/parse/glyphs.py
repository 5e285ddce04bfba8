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
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from .. import piece as pc
from ..errors import ParseError
from ..region import is_zero_length, orient_region

__all__ = [
    "Glyph",
    "cubic_test_font_path",
    "default_font_path",
    "glyph_region",
    "instantiate_font",
    "load_font",
    "parse_location",
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
    """The fontTools ``TTFont`` at ``path`` (None: the bundled TrueType font), cached.

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
        font = TTFont(path)
        font.getGlyphOrder()
        font["head"]
    except Exception as exc:  # fontTools raises many types for garbage input
        raise ParseError("cannot read font %s: %s" % (path, _one_line(exc)), path) from exc
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

    loc = parse_location(location)
    label = _font_label(font)
    if "fvar" not in font:
        if loc:
            raise ParseError("font %s is not a variable font: --location %s cannot apply"
                             % (label, ",".join("%s=%g" % kv for kv in loc.items())), label)
        return font
    axes = {a.axisTag: a for a in font["fvar"].axes}
    ranges = ", ".join("%s %g..%g (default %g)" % (t, a.minValue, a.maxValue, a.defaultValue)
                       for t, a in axes.items())
    for tag, value in loc.items():
        a = axes.get(tag)
        if a is None or not a.minValue <= value <= a.maxValue:
            raise ParseError("font %s has no location %s=%g: its axes are %s"
                             % (label, tag, value, ranges), label)
    full = {t: loc.get(t, a.defaultValue) for t, a in axes.items()}
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
                         % (label, full, _one_line(exc)), label) from exc


def _font_label(font):
    path = getattr(font, "_morph_path", None)
    if path:
        return os.path.basename(path)
    try:
        return font["name"].getDebugName(4) or "font"
    except Exception:
        return "font"


@dataclass
class Glyph:
    """A glyph's outline and metrics, in font units (y up).

    ``region`` is a list of oriented loops; ``advance_width`` and ``lsb`` come from
    ``hmtx``; ``units_per_em`` from ``head``.
    """

    name: str
    region: list = field(repr=False)
    advance_width: int
    lsb: int
    units_per_em: int


_PEN_DOC = """fontTools pen protocol -> loops of pieces (a BasePen subclass, built lazily).

    Contract (BasePen): override ``_moveTo``, ``_lineTo``, ``_curveToOne`` and
    ``_qCurveToOne``; ``_closePath`` closes the contour with a line when its last
    point differs from the first; ``_endPath`` (open contour) raises ParseError unless
    the contour ends where it starts or has no extent.  BasePen splits TrueType quadratic runs at their implied
    on-curve points and decomposes components through the glyph set.
"""


def _make_pen_class():
    from fontTools.pens.basePen import BasePen

    class RegionPen(BasePen):
        __doc__ = _PEN_DOC

        def __init__(self, glyph_set, label):
            super().__init__(glyph_set)
            self.loops = []
            self.label = label
            self._pieces = None
            self._start = None

        def _moveTo(self, pt):
            if self._pieces:
                self._finish(closed=False)
            self._pieces = []
            self._start = pt

        def _add(self, points):
            arr = pc.from_points([self._getCurrentPoint()] + list(points))
            if not is_zero_length(arr):
                self._pieces.append(arr)

        def _lineTo(self, pt):
            self._add([pt])

        def _curveToOne(self, pt1, pt2, pt3):
            self._add([pt1, pt2, pt3])

        def _qCurveToOne(self, pt1, pt2):
            self._add([pt1, pt2])

        def _closePath(self):
            self._finish(closed=True)

        def _endPath(self):
            self._finish(closed=False)

        def _finish(self, closed):
            pieces, start = self._pieces or [], self._start
            self._pieces, self._start = None, None
            if not pieces:
                return
            cur = pc.end(pieces[-1])
            if not np.array_equal(cur, np.asarray(start, float)):
                if not closed:
                    raise ParseError("%s has an open contour" % self.label, self.label)
                pieces.append(pc.line(cur, start))
            self.loops.append(pieces)

    return RegionPen


_PEN_CLASS = None


def glyph_region(char_or_name, font=None, location=None):
    """Outline of one glyph as a :class:`Glyph` (region in font units, y up).

    A single character is looked up in the font's cmap; a longer string is taken as
    a glyph name (``"g"`` is the character, ``"ampersand"`` a glyph name).  ``font``
    is a path, a ``TTFont``, or None for the bundled TrueType font; ``location``
    picks an instance of a variable font (:func:`load_font`).

    Raises:
        ParseError: unreadable font; no glyph for the character or name; a glyph
            without contours (e.g. space); an open contour.
    """
    global _PEN_CLASS
    font = load_font(font, location)
    label = _font_label(font)
    if not isinstance(char_or_name, str) or not char_or_name:
        raise ParseError("a glyph is named by a character or a glyph name, got %r"
                         % (char_or_name,), char_or_name)
    if len(char_or_name) == 1:
        name = (font.getBestCmap() or {}).get(ord(char_or_name))
    else:
        name = char_or_name if char_or_name in set(font.getGlyphOrder()) else None
    if name is None:
        raise ParseError("font %s has no glyph for %r" % (label, char_or_name), char_or_name)
    if _PEN_CLASS is None:
        _PEN_CLASS = _make_pen_class()
    glyph_set = font.getGlyphSet()
    pen = _PEN_CLASS(glyph_set, "glyph %r of font %s" % (name, label))
    try:
        glyph_set[name].draw(pen)
    except ParseError:
        raise
    except Exception as exc:
        raise ParseError("cannot draw glyph %r of font %s: %s" % (name, label, _one_line(exc)),
                         char_or_name) from exc
    loops = orient_region(pen.loops, "nonzero")
    if not loops:
        raise ParseError("glyph %r of font %s is empty (no contours)" % (name, label),
                         char_or_name)
    advance, lsb = font["hmtx"][name]
    return Glyph(name, loops, advance, lsb, font["head"].unitsPerEm)


# =========================================================================== helpers

def _one_line(exc):
    return " ".join(str(exc).split()) or type(exc).__name__

