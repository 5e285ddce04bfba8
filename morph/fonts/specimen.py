"""HTML specimen of a written font next to its source (brush, stroke), and the sample
image (:func:`write_sample_image`) written beside it.

:func:`write_specimen` writes ``OUT.ttf.html`` beside a font ``OUT.ttf`` (any
suffix; :func:`specimen_path`; the sample image is ``OUT.ttf.png``,
:func:`sample_path`: side outputs are named after the whole output name, so that
``OUT.ttf`` and ``OUT.woff2`` and their side outputs live side by side): the new font loaded by ``@font-face`` from its file (relative URL, so
the page shows the file actually written), the source font embedded as a WOFF
data URL (zlib: a fifteenth of the time of WOFF2's Brotli and transformed glyf, for
about a third more bytes; a variable source is embedded at the instance that was
brushed), then

- a sample line at 96 px in the new font at a fixed place (``#sample``: 24 px from
  the top-left corner of the page, line height 1, nothing else within 72 px below
  its line box; tests compare its pixels with
  Pillow's rendering of the same text, see ``tests/fonts/test_specimen.py``);
- a waterfall 12-96 px, source and result side by side;
- a grid of every encoded character (cmap), each cell with the source glyph, the
  result glyph and the glyph name.

The page needs no network.  A variable font gets one slider per axis (its fvar
axes, from minimum to maximum, at the default), which set the CSS
``font-variation-settings`` of the sample and of every result glyph; the page's
address may set them too (``OUT.ttf.html#NIBW=80,wdth=110``).  Static fonts get no
script.
"""

import base64
import unicodedata
from functools import partial
from pathlib import Path

__all__ = ["write_specimen", "write_sample_image", "save_png", "sample_locations",
           "specimen_path", "sample_path", "sample_text", "WATERFALL", "SAMPLE_POS",
           "SAMPLE_PX", "SAMPLE_MARGIN"]

WATERFALL = (12, 16, 20, 24, 32, 48, 64, 96)
SAMPLE_PX = 96
SAMPLE_POS = (24, 24)  # CSS px from the page's top-left corner
SAMPLE_MARGIN = 72  # CSS px kept free below the sample line (descenders)
#: the sample's ink and paper as RGB tuples: Pillow reads a colour name through its
#: "#rrggbb" form, compiling its colour patterns as it does (the same pixels)
_BLACK, _WHITE = (0, 0, 0), (255, 255, 255)


def _escape(text, quote=True):
    """``text`` for HTML text and attribute values: ``&``, ``<``, ``>`` and (with
    ``quote``) both quotes as entities, what ``html.escape`` does, without importing
    the ``html`` package and its table of entities."""
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return text.replace('"', "&quot;").replace("'", "&#x27;") if quote else text


def save_png(img, png):
    """Write a Pillow RGB image as an 8-bit PNG file, grayscale when every pixel is
    gray (the samples are black text on white) and RGB otherwise: the pixels read
    back are the image's.  The rows are stored unfiltered and deflated by zlib;
    Pillow's own PNG writer (its plugin import and adaptive filters) takes several
    times as long for the samples' few hundred kilobytes."""
    import struct
    import zlib

    if img.mode != "RGB":
        raise ValueError("save_png writes RGB images, not %s" % img.mode)
    width, height = img.size
    data, color, row = img.tobytes(), 2, 3 * width
    gray = data[0::3]
    if data[1::3] == gray and data[2::3] == gray:
        data, color, row = gray, 0, width
    rows = b"".join(b"\0" + data[y * row:(y + 1) * row] for y in range(height))

    def chunk(tag, body):
        return (struct.pack(">I", len(body)) + tag + body
                + struct.pack(">I", zlib.crc32(tag + body)))

    Path(png).write_bytes(b"\x89PNG\r\n\x1a\n"
                          + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, color,
                                                       0, 0, 0))
                          + chunk(b"IDAT", zlib.compress(rows, 6)) + chunk(b"IEND", b""))


def _sfnt_file(font):
    """Something Pillow's FreeType reads: a path or file object of a TrueType/OpenType
    font as it is; a .woff/.woff2 file, a ``TTFont`` (any flavor) or a ufoLib2 font
    (compiled to CFF by ufo2ft) as the bytes of a plain OpenType font."""
    import io

    from fontTools.ttLib import TTFont

    from .tables import font_bytes

    if hasattr(font, "layers"):  # ufoLib2.Font (its class method Font.read is no file)
        import ufo2ft

        font = ufo2ft.compileOTF(font)
    elif hasattr(font, "read"):
        return font
    elif not hasattr(font, "getGlyphSet"):
        if Path(font).suffix.lower() not in (".woff", ".woff2"):
            return str(font)
        font = TTFont(str(font))
    return io.BytesIO(font_bytes(font))


#: characters in a sample of the font's own characters (:func:`sample_text`)
OWN_SAMPLE_LENGTH = 15


def _ink_test(font):
    """(cmap {code point: glyph name}, has_ink(glyph name)) of a ``TTFont``, a font
    file's path or a ufoLib2 font."""
    if hasattr(font, "layers"):  # ufoLib2.Font
        cmap = {}
        for g in font:
            for u in g.unicodes:
                cmap.setdefault(u, g.name)
        return cmap, lambda name: font[name].getBounds(font) is not None
    from fontTools.ttLib import TTFont

    if not hasattr(font, "getGlyphSet"):
        font = TTFont(str(font), lazy=True)
    return font.getBestCmap() or {}, partial(_has_ink, font, font.getGlyphSet())


#: Type 2 operators that start a contour
_MOVETOS = {"rmoveto", "hmoveto", "vmoveto"}


def _has_ink(font, glyph_set, name):
    """Whether glyph ``name`` of a ``TTFont`` draws anything (its control box is
    not empty), told from its data where the data says it: a glyf glyph by its
    number of contours (a composite by its components'), a CFF charstring by a
    moveto among its operators (none, and no subroutine call: nothing drawn);
    otherwise drawn into a control-box pen."""
    if "glyf" in font:
        glyf = font["glyf"]
        glyph = glyf.glyphs[name] if name in getattr(glyf, "glyphs", {}) else glyf[name]
        data = getattr(glyph, "data", None)   # not expanded: its header says
        contours = (int.from_bytes(data[:2], "big", signed=True) if data else 0
                    ) if data is not None else glyph.numberOfContours
        if contours > 0:
            return True
        if contours == 0:
            return False
        return any(_has_ink(font, glyph_set, c.glyphName) for c in glyf[name].components)
    if "CFF " in font:
        cs = font["CFF "].cff.topDictIndex[0].CharStrings[name]
        cs.decompile()
        ops = {t for t in cs.program if isinstance(t, str)}
        if ops & _MOVETOS:
            return True
        if not ops & {"callsubr", "callgsubr"}:
            return False
    from fontTools.pens.boundsPen import ControlBoundsPen

    pen = ControlBoundsPen(glyph_set)
    glyph_set[name].draw(pen)
    return pen.bounds is not None


def sample_text(font, text, length=OWN_SAMPLE_LENGTH, ink=None):
    """``(text, changed)``: the sample ``text`` when the font draws every character
    of it (a space needs a glyph, others ink too), else the font's own characters
    that have ink, in cmap order, at most ``length`` of them (``changed`` True): a
    CJK skeleton font gets a sample of its own ideographs, not 15 .notdef boxes;
    private use characters come after the others (an icon font's are all it has).
    ``font``: a ``TTFont``, a font file's path or a ufoLib2 font.  ``ink``: ``(cmap
    {code point: glyph name}, has_ink(glyph name))`` where the caller knows them (the
    writer of the font), else None: read from the font (its cmap and outlines)."""
    cmap, has_ink = _ink_test(font) if ink is None else ink

    def covered(ch):
        name = cmap.get(ord(ch))
        return name is not None and (ch.isspace() or has_ink(name))

    if text and all(covered(ch) for ch in text):
        return text, False
    own, private = [], []      # private use characters only where too few others
    for code in sorted(cmap):
        ch = chr(code)
        kind = unicodedata.category(ch)
        if (kind[0] not in ("C", "Z") or kind == "Co" and len(private) < length) \
                and has_ink(cmap[code]):
            (private if kind == "Co" else own).append(ch)
            if len(own) == length:
                break
    return "".join(own + private[:length - len(own)]), True


def sample_locations(font_file):
    """(label, axis values in fvar order) of the rows of a variable font's sample
    image: one axis: its minimum, middle and maximum; several: the default, then
    every axis at its minimum and maximum (the others at their defaults).  None for
    a static font."""
    import io

    from fontTools.ttLib import TTFont

    data = font_file if isinstance(font_file, bytes) else Path(font_file).read_bytes()
    font = TTFont(io.BytesIO(data), lazy=True)
    if "fvar" not in font:
        return None
    axes = font["fvar"].axes
    default = [a.defaultValue for a in axes]

    def label(values):
        return ", ".join("%s %g" % (a.axisTag, round(v, 2)) for a, v in zip(axes, values))

    if len(axes) == 1:
        a = axes[0]
        spots = [[a.minValue], [0.5 * (a.minValue + a.maxValue)], [a.maxValue]]
    else:
        spots = [default]
        for k, a in enumerate(axes):
            for v in (a.minValue, a.maxValue):
                if v != a.defaultValue:
                    spots.append(default[:k] + [v] + default[k + 1:])
        corner = [a.maxValue for a in axes]
        if corner not in spots:
            spots.append(corner)
    return [(label(v), v) for v in spots]


def _variable_sample(data, text, png, px, spots):
    """The sample image of a variable font: one line per location of ``spots``
    (:func:`sample_locations`), each under a small label naming it, set by Pillow
    (FreeType's instance at that location)."""
    import io

    from .deferred import pillow

    Image, ImageDraw, ImageFont = pillow("Image", "ImageDraw", "ImageFont")

    pad = px // 4
    small = ImageFont.load_default(size=max(10, px // 6))
    rows = []
    for name, values in spots:
        fnt = ImageFont.truetype(io.BytesIO(data), px)
        fnt.set_variation_by_axes(values)
        rows.append((name, fnt, fnt.getbbox(text)))
    left = min(b[0] for _, _, b in rows)
    width = max(b[2] for _, _, b in rows) - left
    lab_h = small.getbbox("Ag")[3] + pad // 2
    heights = [b[3] - b[1] for _, _, b in rows]
    width = max(width, max(small.getbbox(n)[2] for n, _, _ in rows))
    img = Image.new("RGB", (width + 2 * pad, sum(lab_h + h + pad for h in heights) + pad),
                    _WHITE)
    draw = ImageDraw.Draw(img)
    y = pad
    for (name, fnt, box), h in zip(rows, heights):
        draw.text((pad, y), name, font=small, fill=(110, 110, 110))
        y += lab_h
        draw.text((pad - left, y - box[1]), text, font=fnt, fill=_BLACK)
        y += h + pad
    save_png(img, png)
    return img


def write_sample_image(font, text, png, px=SAMPLE_PX):
    """Set ``text`` in a font with Pillow at ``px`` pixels, black on white with a
    quarter-size margin, and save it to ``png`` (:func:`save_png`); returns the
    image.  ``font``: a path or binary file object of a font file (.ttf, .otf,
    .woff, .woff2), a fontTools ``TTFont`` or a ufoLib2 font (compiled with ufo2ft).
    A variable font is shown at a few axis positions (:func:`sample_locations`),
    one labelled line each."""
    from .deferred import pillow

    Image, ImageDraw, ImageFont = pillow("Image", "ImageDraw", "ImageFont")

    src = _sfnt_file(font)
    data = src.read() if hasattr(src, "read") else Path(src).read_bytes()
    spots = sample_locations(data)
    if spots:
        return _variable_sample(data, text, png, px, spots)
    import io

    fnt = ImageFont.truetype(io.BytesIO(data), px)
    left, top, right, bottom = fnt.getbbox(text)
    pad = px // 4
    img = Image.new("RGB", (right - left + 2 * pad, bottom - top + 2 * pad), _WHITE)
    ImageDraw.Draw(img).text((pad - left, pad - top), text, font=fnt, fill=_BLACK)
    save_png(img, png)
    return img


def _side_output(font_path, suffix):
    path = Path(font_path)
    return path.with_name(path.name + suffix)


def specimen_path(font_path):
    """``OUT.ttf.html`` for a font ``OUT.ttf``: the whole output name and ``.html``
    (so the specimens of ``OUT.ttf`` and ``OUT.woff2`` do not collide)."""
    return _side_output(font_path, ".html")


def sample_path(font_path):
    """``OUT.ttf.png``, the sample image of a font ``OUT.ttf`` (or a UFO ``OUT.ufo``):
    the whole output name and ``.png``."""
    return _side_output(font_path, ".png")


def _font_format(path):
    return {".woff2": "woff2", ".woff": "woff", ".otf": "opentype"}.get(
        Path(path).suffix.lower(), "truetype")


def _cells(font, source_font, cmap=None):
    """(char, glyph name) of every encoded character with ink in either font
    (``cmap``: the font's, where the caller knows it)."""
    cmap = (font.getBestCmap() or {}) if cmap is None else cmap
    src = (source_font.getBestCmap() or {}) if source_font is not None else {}
    out = []
    for code in sorted(set(cmap) | set(src)):
        ch = chr(code)
        if unicodedata.category(ch)[0] in ("C", "Z"):
            continue  # controls, spaces, format characters: no ink to compare
        out.append((ch, cmap.get(code) or src.get(code)))
    return out


_CSS = """
%(faces)s
body { margin: 0; padding: %(y)dpx 24px 24px 24px; background: #fff; color: #000;
       font-family: sans-serif; }
#sample { position: absolute; left: %(x)dpx; top: %(y)dpx; margin: 0; white-space: pre;
          font: %(px)dpx/1 "MorphResult"; }
#page { margin-top: %(room)dpx; }  /* room for the sample's descenders */
.src { font-family: "MorphSource"; }
.res { font-family: "MorphResult"; }
#sample, .res { font-variation-settings: var(--fvs, normal); }
table.water { border-collapse: collapse; table-layout: fixed; width: 100%%; }
table.water td { padding: 2px 12px 2px 0; white-space: pre; line-height: 1.3;
                 overflow: hidden; }
table.water td.px { font: 11px sans-serif; color: #777; width: 48px; }
.grid { display: flex; flex-wrap: wrap; gap: 4px; }
.cell { border: 1px solid #ddd; width: 128px; text-align: center; }
.cell .g { font-size: 40px; line-height: 1.4; display: inline-block; width: 60px; }
.cell .n { font: 10px monospace; color: #555; overflow: hidden; white-space: nowrap; }
h2 { font-size: 16px; margin: 24px 0 8px 0; }
"""

_PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>%(title)s</title>
<style>%(css)s</style></head>
<body>
<p id="sample">%(sample)s</p>
<div id="page">
<p>%(head)s</p>
<h2>Waterfall, 12&ndash;96 px</h2>
<table class="water">%(rows)s</table>
<h2>All encoded characters (%(count)d)</h2>
<div class="grid">%(cells)s</div>
</div>
</body></html>
"""


def _font_faces(font_path, source_font):
    """@font-face rules: MorphResult from the written file (relative URL), MorphSource
    embedded as a WOFF data URL (when there is a source)."""
    from .tables import font_bytes

    faces = ['@font-face { font-family: "MorphResult"; src: url("%s") format("%s"); }'
             % (_escape(font_path.name), _font_format(font_path))]
    if source_font is not None:
        data = base64.b64encode(font_bytes(source_font, "woff")).decode("ascii")
        faces.append('@font-face { font-family: "MorphSource"; '
                     'src: url(data:font/woff;base64,%s) format("woff"); }' % data)
    return "\n".join(faces)


def _waterfall_rows(sample, with_source):
    """Table rows of the sample at every WATERFALL size, source cell first."""
    esc = _escape
    rows = []
    for px in WATERFALL:
        src_td = ('<td class="src" style="font-size:%dpx">%s</td>' % (px, esc(sample))
                  if with_source else "")
        rows.append('<tr><td class="px">%d px</td>%s<td class="res" style="font-size:%dpx">'
                    '%s</td></tr>' % (px, src_td, px, esc(sample)))
    return rows


def _char_cells(font, source_font, cmap=None):
    """Grid cells: each encoded character in the source (if any) and the result."""
    esc = _escape
    cells = []
    for ch, name in _cells(font, source_font, cmap):
        src = ('<span class="g src">%s</span>' % esc(ch)) if source_font is not None else ""
        cells.append('<div class="cell">%s<span class="g res">%s</span>'
                     '<div class="n">%s U+%04X</div></div>'
                     % (src, esc(ch), esc(name or ""), ord(ch)))
    return cells


def write_specimen(font_path, source_font=None, sample="Hamburgefonstiv", html_path=None,
                   title=None, cmap=None, display_name=None):
    """Write the specimen of the font at ``font_path`` (see the module docstring).

    ``source_font``: the source as a ``TTFont`` (embedded as WOFF) or
    None (result only).  ``html_path``: default :func:`specimen_path`.  ``cmap``
    (the font's {code point: glyph name}) and ``display_name`` (its full name),
    where the writer knows them; None: read from the font (a CFF font's glyph
    names are in its CFF table).  Returns the path written.
    """
    from fontTools.ttLib import TTFont

    from ..parse import font_display_name

    esc = _escape
    font_path = Path(font_path)
    html_path = specimen_path(font_path) if html_path is None else Path(html_path)
    font = TTFont(str(font_path), lazy=True)
    family = display_name or font_display_name(font, font_path.stem)
    if source_font is not None:
        head = ("source: %s (left) &middot; result: %s, %s (right)"
                % (esc(font_display_name(source_font, "source")), esc(family), esc(font_path.name)))
    else:
        head = "%s, %s" % (esc(family), esc(font_path.name))
    css = _CSS % {"faces": _font_faces(font_path, source_font), "x": SAMPLE_POS[0],
                  "y": SAMPLE_POS[1], "px": SAMPLE_PX, "room": SAMPLE_PX + SAMPLE_MARGIN}
    cells = _char_cells(font, source_font, cmap)
    head += _axis_sliders(font)
    doc = _PAGE % {"title": esc(title or "%s: morph specimen" % family), "css": css,
                   "sample": esc(sample), "head": head,
                   "rows": "\n".join(_waterfall_rows(sample, source_font is not None)),
                   "count": len(cells), "cells": "\n".join(cells)}
    html_path.write_text(doc, encoding="utf-8")
    return html_path


_SLIDER_SCRIPT = """<script>
(function () {
  var inputs = document.querySelectorAll("#axes input");
  function apply() {
    var parts = [];
    inputs.forEach(function (i) {
      parts.push('"' + i.name + '" ' + i.value);
      document.getElementById("v-" + i.name).textContent = i.value;
    });
    document.documentElement.style.setProperty("--fvs", parts.join(", "));
  }
  decodeURIComponent(location.hash.slice(1)).split(",").forEach(function (kv) {
    var p = kv.split("=");
    inputs.forEach(function (i) { if (i.name === p[0] && p.length === 2) i.value = p[1]; });
  });
  inputs.forEach(function (i) { i.addEventListener("input", apply); });
  apply();
})();
</script>"""


def _axis_sliders(font):
    """The sliders of a variable font's axes (HTML and script), '' for a static one."""
    if "fvar" not in font:
        return ""
    esc = _escape
    rows = []
    for ax in font["fvar"].axes:
        name = font["name"].getDebugName(ax.axisNameID) or ax.axisTag
        step = (ax.maxValue - ax.minValue) / 1000.0
        rows.append('<label>%s (%s) <input type="range" name="%s" min="%g" max="%g" '
                    'step="%g" value="%g"> <span id="v-%s">%g</span></label><br>'
                    % (esc(name), esc(ax.axisTag), esc(ax.axisTag, quote=True), ax.minValue,
                       ax.maxValue, step, ax.defaultValue, esc(ax.axisTag, quote=True),
                       ax.defaultValue))
    return '</p><div id="axes">%s</div>%s<p>' % ("\n".join(rows), _SLIDER_SCRIPT)
