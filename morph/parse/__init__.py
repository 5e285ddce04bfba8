"""Reading shapes: font glyphs (:mod:`.glyphs`, fontTools pens) and SVG documents
(:mod:`.svg`) -> regions.

Every reader returns a region (list of closed loops of pieces, see :mod:`morph.region`)
normalised by :func:`morph.region.orient_region`: outer loops counter-clockwise,
holes clockwise, **y axis up**.  Every bad input raises :class:`morph.errors.ParseError`
naming the input.
"""

import os
from pathlib import Path

from ..region import region_bbox
from . import glyphs, svg
from .glyphs import (Glyph, cubic_test_font_path, default_font_path, glyph_name,  # noqa: F401
                     glyph_region, instantiate_font, load_font, parse_location, read_glyph)
from .svg import (SvgElement, svg_elements, svg_paths, svg_region,  # noqa: F401
                  validate_path_data)

__all__ = glyphs.__all__ + svg.__all__ + ["load_shape"]


# =========================================================================== CLI

def load_shape(arg, font=None, location=None):
    """The CLI's shape argument: an SVG file or a glyph of the font.

    An argument ending in ``.svg`` is read with :func:`svg_region` (user units,
    y flipped up); otherwise it is a single character or a glyph name of ``font``
    (None: bundled TrueType font) at ``location`` (a variable font's instance, see
    :func:`load_font`), read with :func:`glyph_region` (font units).

    Returns (loops, info) with info keys ``kind`` ("glyph" or "svg"), ``name``
    (glyph name or file stem), ``source``, ``units_per_em`` (None for SVG) and
    ``advance`` (glyph advance width; for SVG the region's bounding-box width).

    Raises:
        ParseError: as :func:`svg_region` and :func:`glyph_region`.
    """
    text = os.fspath(arg)
    if text.lower().endswith(".svg"):
        loops = svg_region(text)
        box = region_bbox(loops)
        return loops, {"kind": "svg", "name": Path(text).stem, "source": text,
                       "units_per_em": None, "advance": float(box[2] - box[0])}
    glyph = glyph_region(text, font, location)
    return glyph.region, {"kind": "glyph", "name": glyph.name, "source": text,
                          "units_per_em": glyph.units_per_em,
                          "advance": glyph.advance_width}
