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

from ..errors import ParseError
from . import glyphs
from .glyphs import (  # noqa: F401 - re-exported
    cubic_test_font_path, default_font_path, font_display_name, full_location, glyph_name,
    glyph_region, instantiate_font, load_font, parse_location, read_glyph, read_glyphs)
from .shape import Shape, em_to_units

#: names of :mod:`.svg` (its ``__all__``), imported on first use (PEP 562): reading a
#: glyph does not load the SVG reader and its XML parser
_SVG_NAMES = ("SvgElement", "svg_elements", "svg_paths", "svg_region", "validate_path_data")

__all__ = ["Shape", "em_to_units", "load_shape", "svg_shape"] + glyphs.__all__ + list(_SVG_NAMES)


def __getattr__(name):
    if name in _SVG_NAMES or name == "svg":
        import importlib

        svg = importlib.import_module(".svg", __name__)
        value = svg if name == "svg" else getattr(svg, name)
        globals()[name] = value
        return value
    raise AttributeError("module 'morph.parse' has no attribute %r" % (name,))


def svg_shape(source, fill_rule=None):
    """:func:`svg_region` of a file, document or path data as a :class:`Shape` (user
    units, y up; named by the file's stem, "svg" for a document, "path" for path
    data; advance and lsb from the region's bounding box).

    Raises:
        ParseError: as :func:`svg_region`.
    """
    from ..region import region_bbox
    from . import svg

    region = svg.svg_region(source, fill_rule)
    text, kind = svg._source_kind(source)
    name = {"file": Path(text).stem, "document": "svg", "path data": "path"}[kind]
    box = region_bbox(region)
    return Shape(region, name, text, None, float(box[2] - box[0]), float(box[0]))


def load_shape(arg, font=None, location=None):
    """The CLI's shape argument as a :class:`Shape`: an SVG file or a glyph of the font.

    An argument ending in ``.svg`` or ``.svgz``, or naming a file that starts as an
    XML (or gzip) document, is read with :func:`svg_shape` (user units, y flipped
    up); otherwise it is a single character or a glyph name of ``font``
    (None: bundled TrueType font) at ``location`` (a variable font's instance, see
    :func:`load_font`), read with :func:`glyph_region` (font units).  An argument
    naming a file that is not an SVG document, or looking like a path, that is no
    glyph of the font is reported as that file.

    Raises:
        ParseError: as :func:`svg_region` and :func:`glyph_region`; a file that is not
            an SVG document; a missing file.
    """
    text = os.fspath(arg)
    if text.lower().endswith((".svg", ".svgz")) or (len(text) > 1 and _svg_file(text)):
        return svg_shape(text)
    if len(text) > 1 and (os.path.exists(text) or _looks_like_path(text)):
        _check_glyph_not_file(text, load_font(font))
    return glyph_region(text, font, location)


#: suffixes of files that are not SVG documents, which a glyph name does not end in:
#: a missing ``picture.png`` is a missing file, not a glyph
_FILE_SUFFIXES = (".png", ".jpg", ".jpeg", ".gif", ".webp", ".bmp", ".tif", ".tiff", ".pdf",
                  ".eps", ".ai", ".ttf", ".otf", ".ttc", ".woff", ".woff2", ".ufo", ".txt",
                  ".json", ".glif")


def _looks_like_path(text):
    return os.sep in text or "/" in text or text.lower().endswith(_FILE_SUFFIXES)


def _check_glyph_not_file(text, font):
    """A shape argument that names a file (or looks like a path) is a glyph only when
    the font has a glyph of that name; otherwise the error is about the file.

    Raises:
        ParseError: a file that is not an SVG document, or no such file.
    """
    try:
        glyph_name(font, text)
        return
    except ParseError:
        pass
    if os.path.isdir(text):
        why = "is a folder, not an SVG file"
    elif os.path.exists(text):
        why = "is not an SVG document"
    else:
        why = "does not exist (no such file)"
    raise ParseError("%s %s; a shape is an SVG file or a glyph of the font (a character "
                     "or a glyph name)" % (text, why), text)


def _svg_file(path):
    """Is ``path`` a file whose content starts as an SVG (gzip) or XML document does?"""
    try:
        with open(path, "rb") as fh:
            head = fh.read(64)
    except OSError:
        return False
    return head[:2] == b"\x1f\x8b" or head.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<")
