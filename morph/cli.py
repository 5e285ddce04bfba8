"""The ``morph`` command line: one click group, shared options, thin commands.

Adding a command (for other engineers)::

    @main.command()
    @shape_argument("shape")            # a glyph or an .svg file, loaded with --font
    @common_options                     # --font --tol -o/--output --force --size
    def mycommand(shape, font, tol, output, force, size):
        out = resolve_output(output, "mycommand-%s.png" % shape.slug, force)
        write_image(out, [shape.loops], size=size, tol=shape.tolerance(tol))

``common_options`` adds ``--font``, ``--tol``, ``-o/--output``, ``--force`` and
``--size``; ``shape_argument`` converts an argument with :func:`morph.parse.load_shape`
into a :class:`Shape`.  Errors: raise :class:`morph.errors.MorphError` (or a click
usage error) and :func:`main` prints one line ``morph: error: ...`` and exits 2;
anything else is an internal error, exit 1 (``MORPH_DEBUG=1`` shows the traceback).
"""

import os
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

import click
import numpy as np

from . import __version__
from .errors import MorphError

__all__ = ["main", "Shape", "ShapeParam", "shape_argument", "common_options",
           "font_option", "tol_option", "output_option", "force_option", "size_option",
           "resolve_output", "resolve_output_dir", "write_image", "InputError"]

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 1
DEFAULT_TOL = 1e-4
IMAGE_SUFFIXES = (".png", ".svg")


_NO_ARGS_IS_HELP = getattr(click.exceptions, "NoArgsIsHelpError", ())


class InputError(click.ClickException):
    """Bad input found by a command (e.g. an output that exists): one line, exit 2."""

    exit_code = EXIT_BAD_INPUT


def _error_line(message):
    text = " ".join(str(message).split())
    click.echo("morph: error: %s" % text, err=True)


# =========================================================================== group

class MorphGroup(click.Group):
    """click Group whose ``main`` turns every failure into one stderr line.

    Exit status: 0 success; 2 bad input or usage (MorphError, click usage errors,
    unwritable output); 1 unexpected internal error (re-raised with MORPH_DEBUG=1).
    """

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True,
             **extra):
        debug = os.environ.get("MORPH_DEBUG", "") not in ("", "0")
        code = 0
        try:
            rv = super().main(args=args, prog_name=prog_name or "morph",
                              complete_var=complete_var, standalone_mode=False, **extra)
            if isinstance(rv, int) and not isinstance(rv, bool):
                code = rv
        except click.exceptions.Abort:
            _error_line("aborted")
            code = EXIT_INTERNAL
        except _NO_ARGS_IS_HELP as exc:  # bare "morph": the manual, not an error
            click.echo(exc.format_message())
            code = 0
        except click.ClickException as exc:
            msg = exc.format_message()
            ctx = getattr(exc, "ctx", None)
            if isinstance(exc, click.UsageError) and ctx is not None:
                msg += " (see '%s --help')" % ctx.command_path
            _error_line(msg)
            code = EXIT_BAD_INPUT
        except MorphError as exc:
            if debug:
                raise
            _error_line(exc)
            code = EXIT_BAD_INPUT
        except Exception as exc:  # internal error: one line, not a traceback
            if debug:
                raise
            _error_line("internal error: %s: %s (set MORPH_DEBUG=1 for a traceback)"
                        % (type(exc).__name__, exc))
            code = EXIT_INTERNAL
        if standalone_mode:
            sys.exit(code)
        return code


@click.group(cls=MorphGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="morph",
                      message="%(prog)s %(version)s")
def main():
    """Minkowski sums of curved planar shapes (glyphs, SVG paths) as exact curves.

    Shapes are glyphs of a font (a single character such as g, or a glyph name
    such as ampersand) or SVG files (an argument ending in .svg).  Glyphs are read
    in font units and SVG in user units, both with the y axis up.

    \b
    Examples:
      morph outline g -o g.png
      morph outline B --font MyFont.otf -o B.svg
      morph outline drawing.svg --size 800
    """


# =========================================================================== shapes

@dataclass
class Shape:
    """A loaded shape argument: its region and where it came from.

    ``info`` is the dict of :func:`morph.parse.load_shape` (kind, name, source,
    units_per_em, advance).
    """

    arg: str
    loops: list = field(repr=False)
    info: dict

    @property
    def name(self):
        return self.info["name"]

    @property
    def slug(self):
        """File-name-safe name (glyph name or SVG file stem)."""
        return re.sub(r"[^A-Za-z0-9._-]+", "_", self.name) or "shape"

    @property
    def units_per_em(self):
        return self.info.get("units_per_em")

    def tolerance(self, tol):
        """--tol in the shape's units: em -> font units for glyphs, as is for SVG."""
        upm = self.units_per_em
        return tol * upm if upm else tol


class ShapeParam(click.ParamType):
    """Click type: a glyph character/name or an .svg path -> :class:`Shape`.

    Loads with the ``--font`` value (``--font`` is eager, so it is known first).
    Parse errors propagate as MorphError (one clean line, exit 2).
    """

    name = "SHAPE"

    def convert(self, value, param, ctx):
        if isinstance(value, Shape):
            return value
        from .parse import load_shape

        font = ctx.params.get("font") if ctx is not None else None
        loops, info = load_shape(value, font)
        return Shape(value, loops, info)


SHAPE = ShapeParam()


def shape_argument(name="shape", **kwargs):
    """Decorator: a positional shape argument converted to a :class:`Shape`."""
    return click.argument(name, type=SHAPE, metavar=name.upper(), **kwargs)


# =========================================================================== options

def font_option(f):
    return click.option(
        "--font", type=click.Path(dir_okay=False), default=None, is_eager=True,
        help="Font file (TrueType/OpenType) for glyph shapes. Default: the bundled "
             "Noto Sans Regular (TrueType).")(f)


def tol_option(f):
    return click.option(
        "--tol", type=click.FloatRange(min=0.0, min_open=True), default=DEFAULT_TOL,
        show_default=True,
        help="Absolute geometric tolerance of curve output: in em for glyphs "
             "(1e-4 em = 0.1 unit at 1000 units per em), in user units for SVG.")(f)


def output_option(f):
    return click.option(
        "-o", "--output", type=click.Path(dir_okay=True), default=None,
        help="Output file; the format follows the suffix (.png or .svg). For frame "
             "sequences, a folder. Default: a name derived from the command and "
             "shape in the current directory.")(f)


def force_option(f):
    return click.option("--force", is_flag=True, default=False,
                        help="Overwrite an existing output file.")(f)


def size_option(f):
    return click.option("--size", type=click.IntRange(min=8, max=16384), default=512,
                        show_default=True,
                        help="Longer side of the image in pixels.")(f)


def common_options(f):
    """--font, --tol, -o/--output, --force, --size: the shared vocabulary."""
    for deco in (size_option, force_option, output_option, tol_option, font_option):
        f = deco(f)
    return f


# =========================================================================== output

def resolve_output(output, default_name, force, suffixes=IMAGE_SUFFIXES):
    """Checked output path: allowed suffix, parent folder exists, no overwrite.

    Raises InputError (exit 2) otherwise.
    """
    path = Path(output) if output is not None else Path.cwd() / default_name
    if path.suffix.lower() not in suffixes:
        raise InputError("cannot tell the output format of %s: use a %s suffix"
                               % (path, " or ".join(suffixes)))
    if path.is_dir():
        raise InputError("output %s is a folder, expected a file" % path)
    if not path.parent.is_dir():
        raise InputError("output folder %s does not exist" % path.parent)
    if path.exists() and not force:
        raise InputError("output %s exists; use --force to overwrite it" % path)
    return path


def resolve_output_dir(output, default_name, force):
    """Checked output folder for frame sequences (created if missing).

    An existing non-empty folder needs ``force``.  Raises InputError.
    """
    path = Path(output) if output is not None else Path.cwd() / default_name
    if path.exists() and not path.is_dir():
        raise InputError("output %s exists and is not a folder" % path)
    if path.is_dir() and any(path.iterdir()) and not force:
        raise InputError("output folder %s is not empty; use --force to write "
                               "into it" % path)
    if not path.parent.is_dir():
        raise InputError("output folder %s does not exist" % path.parent)
    path.mkdir(exist_ok=True)
    return path


def write_image(path, shapes, size=512, tol=None, **style):
    """Write shapes to ``path`` as PNG or SVG by suffix (``tol`` in shape units)."""
    from .render import write_png, write_svg

    path = Path(path)
    try:
        if path.suffix.lower() == ".svg":
            write_svg(str(path), shapes, size=size, tol=tol, **style)
        else:
            write_png(str(path), shapes, size=size, **style)
    except OSError as exc:
        raise click.FileError(str(path), hint=exc.strerror or str(exc)) from exc
    return path


# =========================================================================== commands

@main.command()
@shape_argument("shape")
@common_options
def outline(shape, font, tol, output, force, size):
    """Draw a shape's outline region as a PNG or SVG image.

    SHAPE is a single character (g), a glyph name (ampersand) of the font, or an
    SVG file (drawing.svg).  The region is filled black with its holes left open,
    framed with a 5% margin.  PNG output is anti-aliased (4x4 supersampling), SIZE
    pixels on its longer side.  SVG output writes the curves themselves: lines and
    polynomial Béziers exactly, other curves as cubics within --tol.

    Without -o the image is written to outline-NAME.png in the current directory
    (NAME: glyph name or SVG file stem).  Existing files are kept unless --force.

    \b
    Examples:
      morph outline g -o g.png
      morph outline ampersand --size 1024 -o amp.png
      morph outline Q --font MyFont.otf -o Q.svg --tol 1e-5
      morph outline logo.svg
    """
    out = resolve_output(output, "outline-%s.png" % shape.slug, force)
    write_image(out, [shape.loops], size=size, tol=shape.tolerance(tol))
    click.echo("wrote %s" % out)


def _frame_bbox(regions):
    from .region import region_bbox

    boxes = np.array([region_bbox(r) for r in regions if r])
    return (boxes[:, 0].min(), boxes[:, 1].min(), boxes[:, 2].max(), boxes[:, 3].max())


def method_option(f):
    from .methods import METHODS

    return click.option(
        "--method", type=click.Choice(list(METHODS)), default="qac", show_default=True,
        help="Convolution method of the paper's Sec. 4. qac keeps exact normals and a "
             "certified error bound; the others measure their error by sampling.")(f)


@main.command("sum")
@shape_argument("a")
@shape_argument("b")
@method_option
@common_options
def sum_(a, b, method, font, tol, output, force, size):
    """Minkowski sum A ⊕ B of two shapes, as a PNG or SVG image.

    A and B are characters or glyph names of the font, or SVG files.  The result is
    the boundary of the sum as rational Bézier pieces (Lee, Kim, Elber 1998: QAC
    convolution, trimmed to the boundary), each within --tol of the exact boundary;
    SVG output converts them to cubics within --tol as well.  Glyphs are summed in
    font units with their own origins (the result's origin is the sum of the two).

    \b
    Examples:
      morph sum T M -o tm.png
      morph sum O ellipse.svg -o o-nib.svg --tol 1e-5
    """
    from .trim import minkowski_sum

    out = resolve_output(output, "sum-%s-%s.png" % (a.slug, b.slug), force)
    t = a.tolerance(tol)
    loops = minkowski_sum(a.loops, b.loops, t, method=method)
    write_image(out, [loops], size=size, tol=t)
    click.echo("wrote %s (%d loops, %d pieces)" % (out, len(loops), sum(map(len, loops))))


def _morph_command(a, b, frames, tol, output, force, size, duration, kind, method="qac"):
    from .frames import morph_frames
    from .render import render_png, save_animation, write_svg

    if frames < 2:
        raise InputError("--frames must be at least 2, got %d" % frames)
    outdir = resolve_output_dir(output, "%s-%s-%s" % (kind, a.slug, b.slug), force)
    t = a.tolerance(tol)
    with click.progressbar(length=frames, label="frames", file=sys.stderr) as bar:
        regions = morph_frames(a.loops, b.loops, frames, t, progress=lambda k: bar.update(1),
                               method=method)
    bbox = _frame_bbox(regions)
    images = []
    for k, region in enumerate(regions):
        stem = outdir / ("frame-%03d" % k)
        write_svg(str(stem) + ".svg", [region], bbox=bbox, size=size, tol=t)
        img = render_png([region], size=size, bbox=bbox)
        img.save(str(stem) + ".png")
        images.append(img)
    save_animation(images, str(outdir / "morph.gif"), duration=duration)
    click.echo("wrote %d frames (SVG + PNG) and morph.gif to %s" % (frames, outdir))


def _frames_option(f):
    return click.option("--frames", type=int, default=10, show_default=True,
                        help="Number of frames, including both end shapes.")(f)


def _duration_option(f):
    return click.option("--duration", type=click.IntRange(min=10), default=120,
                        show_default=True, help="Milliseconds per frame of the GIF.")(f)


def _morph_options(f):
    """Arguments A B and the options shared by `morph glyph` and `morph svg`."""
    for deco in reversed([shape_argument("a"), shape_argument("b"), _frames_option,
                          _duration_option, method_option, common_options]):
        f = deco(f)
    return f


@main.command()
@_morph_options
def glyph(a, b, frames, duration, method, font, tol, output, force, size):
    """Morph glyph A into glyph B: frames (1-a)·A ⊕ a·B (the paper's Fig. 6).

    Each frame is the Minkowski sum of A scaled by 1-a and B scaled by a, both
    centred on their area centroids, for a = 0 ... 1 in FRAMES steps: frame 0 is A,
    the last frame is B.  Writes frame-000.svg/.png ... and morph.gif into the
    output folder (default: glyph-A-B in the current directory; created if missing;
    an existing non-empty folder needs --force).  --tol is in em.

    \b
    Examples:
      morph glyph T M --frames 10
      morph glyph a g --frames 24 --font MyFont.otf -o ag/
    """
    _morph_command(a, b, frames, tol, output, force, size, duration, "glyph", method)


@main.command()
@_morph_options
def svg(a, b, frames, duration, method, font, tol, output, force, size):
    """Morph SVG shape A into SVG shape B: frames (1-a)·A ⊕ a·B (Fig. 36).

    Like `morph glyph` for SVG files (closed paths; arcs are exact).  --tol is in the
    SVG's user units.  Writes frame SVGs and PNGs and morph.gif into the output
    folder (default: svg-A-B).

    \b
    Example:
      morph svg bird.svg butterfly.svg --frames 12 -o bird2butterfly/
    """
    _morph_command(a, b, frames, tol, output, force, size, duration, "svg", method)


# =========================================================================== applications

def _length_in_units(shape, value):
    """A length given in em for glyphs (x units per em) or user units for SVG."""
    return shape.tolerance(value)


@main.command()
@shape_argument("shape")
@click.option("--radius", "-r", type=float, required=True,
              help="Offset radius: in em for glyphs (0.05 = 50 units at 1000 units "
                   "per em), in user units for SVG. Must be >= 0.")
@common_options
def offset(shape, radius, font, tol, output, force, size):
    """Offset a shape outward by an exact disk: SHAPE ⊕ disk(RADIUS) (Fig. 37).

    The disk is an exact rational circle, so the boundary is the QAC convolution
    with a circle trimmed to the boundary, within --tol of the exact offset curve.
    Holes shrink and close.  Negative radii (insets) are not supported: exit 2.
    The picture shows the offset region in grey with the original shape on top.

    \b
    Examples:
      morph offset o --radius 0.04 -o o-offset.png
      morph offset drawing.svg --radius 5 -o grown.svg
    """
    from .offset import offset_region

    if radius < 0:
        raise InputError("negative --radius %g: insets are not supported, only "
                         "outward offsets (radius >= 0)" % radius)
    out = resolve_output(output, "offset-%s.png" % shape.slug, force)
    t = shape.tolerance(tol)
    loops = offset_region(shape.loops, _length_in_units(shape, radius), t)
    write_image(out, [(loops, {"fill": "#9bbbd4"}), (shape.loops, {"fill": "black"})],
                size=size, tol=t)
    click.echo("wrote %s (%d loops, %d pieces)" % (out, len(loops), sum(map(len, loops))))


def cspace_figure(obstacle, robot, cspace, tol, samples=8, reference=(0.0, 0.0)):
    """Shapes for a C-space picture: C-space region (light), obstacle (dark), robot
    outlines placed at ``samples`` points spread along the C-space boundary, and a
    dot at each reference point."""
    from . import piece as pc
    from .cspace import place_robot

    shapes = [(cspace, {"fill": "#f2c894", "stroke": "#b3541e", "stroke_width": 1.5}),
              (obstacle, {"fill": "#404040"})]
    outer = max(cspace, key=lambda loop: abs(pc.loop_area(loop))) if cspace else []
    if outer and samples > 0:
        poly = np.vstack([pc.flatten_loop(outer, tol)])
        seg = np.hypot(*np.diff(np.vstack([poly, poly[:1]]), axis=0).T)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        box = _frame_bbox([cspace])
        dot = 0.012 * max(box[2] - box[0], box[3] - box[1])
        for s in np.arange(samples) * cum[-1] / samples:
            i = min(np.searchsorted(cum, s, side="right") - 1, len(poly) - 1)
            p = poly[i]
            shapes.append((place_robot(robot, p, reference),
                           {"fill": None, "stroke": "#1f5fa8", "stroke_width": 1.2}))
            shapes.append(([pc.circle(p, dot)], {"fill": "#1f5fa8"}))
    return shapes


@main.command()
@shape_argument("obstacle")
@shape_argument("robot")
@click.option("--samples", type=click.IntRange(min=0, max=200), default=8,
              show_default=True, help="Robot copies drawn along the C-space boundary.")
@click.option("--reference", type=click.Choice(["centroid", "origin"]), default="centroid",
              show_default=True,
              help="The robot's reference point: its area centroid or its origin.")
@common_options
def cspace(obstacle, robot, samples, reference, font, tol, output, force, size):
    """C-space obstacle of a translating ROBOT: OBSTACLE ⊕ (−ROBOT) (Figs. 4, 38).

    The robot's reference point is its area centroid (--reference centroid) or
    its origin (glyph origin, SVG user-space origin after the y flip).  The robot, with its reference point at p, overlaps
    the obstacle exactly when p lies in the C-space region.  The picture shows the
    C-space region (orange), the obstacle (dark grey) and the robot outline placed
    at SAMPLES points along the C-space boundary (touching the obstacle).

    \b
    Examples:
      morph cspace O v -o cspace.png
      morph cspace room.svg robot.svg --samples 12
    """
    from .cspace import cspace_obstacle
    from .region import region_centroid

    out = resolve_output(output, "cspace-%s-%s.png" % (obstacle.slug, robot.slug), force)
    t = obstacle.tolerance(tol)
    ref = region_centroid(robot.loops) if reference == "centroid" else (0.0, 0.0)
    loops = cspace_obstacle(obstacle.loops, robot.loops, t, reference=ref)
    write_image(out, cspace_figure(obstacle.loops, robot.loops, loops, t, samples, ref),
                size=size, tol=t)
    click.echo("wrote %s (%d loops, %d pieces)" % (out, len(loops), sum(map(len, loops))))


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
    from .fonts.brush import brush_font, ellipse_nib, parse_glyph_spec
    from .parse import default_font_path, svg_region

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


if __name__ == "__main__":  # pragma: no cover
    main()
