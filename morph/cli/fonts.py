"""Font commands: brush (filled glyphs swept by a nib)."""

import re
import sys
from pathlib import Path

import click

from . import main
from .options import InputError, resolve_output


def _parse_nib(spec):
    m = re.fullmatch(r"\s*ellipse\s*:\s*([^,]+),([^,]+)(?:,([^,]+))?\s*", spec or "")
    if not m:
        raise InputError("--nib must look like ellipse:W,H,ANGLE (font units, degrees), "
                         "got %r" % spec)
    try:
        w, h = float(m.group(1)), float(m.group(2))
        a = float(m.group(3)) if m.group(3) else 0.0
    except ValueError:
        raise InputError("--nib numbers not understood: %r" % spec) from None
    return w, h, a


@main.command()
@click.argument("font_file", metavar="FONT", required=False, default="default")
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="Output font (.ttf or .otf); a sample image OUTPUT.png is written "
                   "next to it (OUTPUT with .png suffix).")
@click.option("--nib", default="ellipse:80,30,30", show_default=True,
              help="Elliptical nib: width, height in font units and angle in degrees.")
@click.option("--nib-svg", type=click.Path(dir_okay=False), default=None,
              help="A convex SVG shape as the nib (user units = font units; its origin "
                   "is the pen point). Overrides --nib.")
@click.option("--glyphs", default="A-Z,a-z", show_default=True,
              help="Characters, ranges (a-z) and glyph names, comma separated.")
@click.option("--sample", default="Hamburgefonstiv", show_default=True,
              help="Text of the sample image.")
@click.option("--family", default=None, help="New family name (default: FAMILY Brush).")
@click.option("--tol", type=click.FloatRange(min=0.0, min_open=True), default=0.5,
              show_default=True,
              help="Outline tolerance in font units (sum and curve conversion together).")
@click.option("--composites", type=click.Choice(["follow", "sweep"]), default="follow",
              show_default=True,
              help="Composite glyphs using a swept glyph but not chosen (e.g. eacute when e "
                   "is swept): follow (stay composites, widened by the nib) or sweep "
                   "(decomposed and swept too).")
@click.option("--force", is_flag=True, default=False, help="Overwrite existing outputs.")
def brush(font_file, output, nib, nib_svg, glyphs, sample, family, tol, composites, force):
    """Sweep the glyphs of FONT with a fixed calligraphic nib (Fig. 5).

    Every chosen glyph is replaced by glyph ⊕ nib (the nib keeps its orientation),
    converted to the font's curve type within --tol font units (TrueType:
    quadratics, CFF/.otf: cubics), with the advance width grown by the nib width.
    FONT is a .ttf/.otf file, or omitted / "default" for the bundled Noto Sans.
    The nib must be convex.  Also writes OUTPUT.png: the sample text set in the
    new font with Pillow.

    \b
    Examples:
      morph brush -o NotoBrush.ttf
      morph brush MyFont.otf -o Brushed.otf --nib ellipse:120,20,-30 --glyphs a-z
    """
    from ..fonts.brush import brush_font, ellipse_nib, parse_glyph_spec
    from ..parse import default_font_path, svg_region

    src = default_font_path() if font_file in (None, "default") else font_file
    if not Path(src).is_file():
        raise InputError("font %s does not exist" % src)
    out = resolve_output(output, "brush.ttf", force, suffixes=(".ttf", ".otf"))
    png = out.with_suffix(".png")
    if png.exists() and not force:
        raise InputError("sample %s exists; use --force to overwrite it" % png)
    if nib_svg:
        nib_region = svg_region(nib_svg)
    else:
        nib_region = ellipse_nib(*_parse_nib(nib))
    items = parse_glyph_spec(glyphs)
    if not items:
        raise InputError("--glyphs selects no glyph")
    import time

    t0 = time.perf_counter()
    with click.progressbar(length=len(items), label="glyphs", file=sys.stderr) as bar:
        stats = brush_font(src, out, nib_region, items, tol=tol, family_name=family,
                           progress=lambda name: bar.update(1), composites=composites)
    seconds = time.perf_counter() - t0
    _font_sample(out, sample, png)
    click.echo("wrote %s (%d glyphs, %d contours, %.1f s) and sample %s"
               % (out, stats["glyphs"], stats["contours"], seconds, png))


def _font_sample(font_path, text, png, px=96):
    from PIL import Image, ImageDraw, ImageFont

    fnt = ImageFont.truetype(str(font_path), px)
    left, top, right, bottom = fnt.getbbox(text)
    pad = px // 4
    img = Image.new("RGB", (right - left + 2 * pad, bottom - top + 2 * pad), "white")
    ImageDraw.Draw(img).text((pad - left, pad - top), text, font=fnt, fill="black")
    img.save(str(png))
    return img
