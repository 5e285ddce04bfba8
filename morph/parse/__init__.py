"""Reading shapes: font glyphs (:mod:`.glyphs`, fontTools pens), SVG documents
(:mod:`.svg`) and UFO skeletons (:mod:`.ufo`).

A region is a list of closed loops of pieces (see :mod:`morph.region`), normalised by
:func:`morph.region.orient_region`: outer loops counter-clockwise, holes clockwise,
**y axis up**.  :func:`glyph_region`, :func:`svg_shape` and :func:`load_shape` return
it as a :class:`Shape` (region, name, source, units per em, metrics);
:func:`svg_region` returns the bare region.  Every bad input raises
:class:`morph.errors.ParseError` naming the input.
"""

import os
from pathlib import Path

from ..region import region_bbox
from . import glyphs, svg
from .glyphs import (cubic_test_font_path, default_font_path, glyph_name,  # noqa: F401
                     glyph_region, instantiate_font, load_font, parse_location, read_glyph)
from .shape import Shape
from .svg import (SvgElement, svg_elements, svg_paths, svg_region,  # noqa: F401
                  validate_path_data)

__all__ = ["Shape", "load_shape", "svg_shape"] + glyphs.__all__ + svg.__all__


def svg_shape(source, fill_rule=None):
    """:func:`svg_region` of a file, document or path data as a :class:`Shape` (user
    units, y up; named by the file's stem, "svg" for a document, "path" for path
    data; advance and lsb from the region's bounding box).

    Raises:
        ParseError: as :func:`svg_region`.
    """
    region = svg_region(source, fill_rule)
    text, kind = svg._source_kind(source)
    name = {"file": Path(text).stem, "document": "svg", "path data": "path"}[kind]
    box = region_bbox(region)
    return Shape(region, name, text, None, float(box[2] - box[0]), float(box[0]))


def load_shape(arg, font=None, location=None):
    """The CLI's shape argument as a :class:`Shape`: an SVG file or a glyph of the font.

    An argument ending in ``.svg`` is read with :func:`svg_shape` (user units, y
    flipped up); otherwise it is a single character or a glyph name of ``font``
    (None: bundled TrueType font) at ``location`` (a variable font's instance, see
    :func:`load_font`), read with :func:`glyph_region` (font units).

    Raises:
        ParseError: as :func:`svg_region` and :func:`glyph_region`.
    """
    text = os.fspath(arg)
    if text.lower().endswith(".svg"):
        return svg_shape(text)
    return glyph_region(text, font, location)
