"""UFO-side tables of a font written from a UFO source (``morph stroke``): the font
info renamed (:func:`rename_ufo_family`), the OS/2 win metrics grown to cover the
new outlines (:func:`outline_extent`, :func:`grow_win_metrics`), an in-memory copy of
the source (:func:`copy_font`).  The compiled-font (``TTFont``) counterparts are in
:mod:`morph.fonts.tables`.
"""

import re

import numpy as np

__all__ = ["DROP_INFO", "rename_ufo_family", "copy_font", "outline_extent", "grow_win_metrics"]

#: font info that named or hinted the skeleton's outlines: dropped from the new font
DROP_INFO = ("postscriptBlueValues", "postscriptOtherBlues", "postscriptFamilyBlues",
              "postscriptFamilyOtherBlues", "postscriptStemSnapH", "postscriptStemSnapV",
              "postscriptBlueFuzz", "postscriptBlueShift", "postscriptBlueScale",
              "postscriptForceBold", "openTypeNameUniqueID", "postscriptUniqueID",
              "postscriptFullName", "openTypeNameCompatibleFullName", "macintoshFONDName",
              "openTypeNameWWSFamilyName", "openTypeNameWWSSubfamilyName")


def rename_ufo_family(info, family):
    """The UFO font info renamed to ``family``: family names (and the style-map and
    typographic family where the source had them) and a PostScript name
    "Family-Style"; the values that named or hinted the old outlines
    (:data:`DROP_INFO`: unique IDs, full names, blue zones and stems) dropped."""
    style = info.styleName or "Regular"
    ps = re.sub(r"[^A-Za-z0-9-]", "", family.replace(" ", "")) + "-" + \
        re.sub(r"[^A-Za-z0-9]", "", style)
    info.familyName = family
    if info.styleMapFamilyName:
        info.styleMapFamilyName = family
    if info.openTypeNamePreferredFamilyName:
        info.openTypeNamePreferredFamilyName = family
    info.postscriptFontName = ps
    for key in DROP_INFO:
        if getattr(info, key, None) is not None:
            setattr(info, key, None)


def copy_font(font):
    """A full in-memory copy of a ufoLib2 font (the source is never modified)."""
    import copy

    font.unlazify()
    return copy.deepcopy(font)


def outline_extent(boxes):
    """[bottom, top] of glyph boxes (xMin, yMin, xMax, yMax; None: empty), [None,
    None] for none: the y range :func:`grow_win_metrics` covers."""
    ys = [(b[1], b[3]) for b in boxes if b is not None]
    if not ys:
        return [None, None]
    return [min(y[0] for y in ys), max(y[1] for y in ys)]


def grow_win_metrics(font, bottom, top):
    """OS/2 win ascent / descent grown to cover the stroked outlines (no clipping):
    ``bottom`` and ``top`` are the extent of the written glyphs
    (:func:`outline_extent`; None: nothing stroked).  A value the source leaves
    unset is grown from the one ufo2ft would compile (from the ascender and
    descender), and then set."""
    if top is None:
        return
    from .fontinfo import info_value  # ufo2ft's fallbacks, without importing ufo2ft

    info = font.info
    ascent = info_value(info, "openTypeOS2WinAscent")
    descent = info_value(info, "openTypeOS2WinDescent")
    if max(ascent, int(np.ceil(top))) != ascent or info.openTypeOS2WinAscent is not None:
        info.openTypeOS2WinAscent = max(ascent, int(np.ceil(top)))
    if max(descent, int(np.ceil(-bottom))) != descent or info.openTypeOS2WinDescent is not None:
        info.openTypeOS2WinDescent = max(descent, int(np.ceil(-bottom)))
