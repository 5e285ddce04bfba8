"""Commands on shapes: outline, sum, and the morph frame sequences (glyph, svg)."""

import click

from .group import main
from .options import (InputError, common_options, progress_bar, report_written, resolve_output,
                      resolve_output_dir, shape_argument, shape_tolerance, write_image,
                      writer_budget)


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
    write_image(out, [shape.region], size=size, tol=shape_tolerance(shape, tol))
    click.echo("wrote %s" % out)


def method_option(f):
    from ..subdivide import METHODS

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
    convolution, trimmed to the boundary).  SVG output writes cubics within --tol of
    the exact sum, export included (a quarter of --tol for the sum,
    morph.budget.plan; the cubic fit and rounding get the rest of --tol beyond the
    error the sum achieved).  Glyphs are summed in
    font units with their own origins (the result's origin is the sum of the two).

    \b
    Examples:
      morph sum T M -o tm.png
      morph sum O ellipse.svg -o o-nib.svg --tol 1e-5
    """
    from ..minkowski import minkowski_sum

    out = resolve_output(output, "sum-%s-%s.png" % (a.slug, b.slug), force)
    budget = writer_budget(a, tol, b.region)
    loops = minkowski_sum(a.region, b.region, budget.geometry, method=method)
    # the export gets what the sum left of --tol (its achieved bound, <= its share)
    write_image(out, [loops], size=size, tol=budget.after(loops.bound))
    report_written(out, loops)


def _morph_command(a, b, frames, tol, output, force, size, duration, kind, method="qac",
                   animation="gif"):
    from ..frames import frames_bbox, iter_frames
    from ..render import write_frame_stream
    from ..render.figures import stale_frame_files

    _check_animation_memory(frames, size, animation)
    outdir = resolve_output_dir(output, "%s-%s-%s" % (kind, a.slug, b.slug), force)
    budget = writer_budget(a, tol, b.region)  # each frame's sum gets budget.geometry

    def written(bar):
        # each frame's SVG export gets the rest of --tol beyond the error its sum achieved;
        # the first frame (A itself) costs nothing, so it is counted with the next one:
        # a rate measured on it would promise far too long a wait
        for i, out in enumerate(iter_frames(a.region, b.region, frames, budget.geometry,
                                            method=method)):
            yield out, budget.after(out.bound)
            if i:
                bar.update(1 + (i == 1))

    with progress_bar(frames, "frames", "morph %s" % kind) as bar:
        write_frame_stream(outdir, written(bar), frames_bbox(a.region, b.region), size=size,
                           duration=duration, animation=animation)
    for stale in stale_frame_files(outdir, frames, animation):  # of an earlier run (--force)
        stale.unlink()
    click.echo("wrote %d frames (SVG + PNG) and morph.%s to %s" % (frames, animation, outdir))


def _check_animation_memory(frames, size, animation):
    """The animation's frames stay in memory until it is written (1 byte a pixel in
    a GIF's palette, 4 in an APNG): at most a quarter of the process's memory budget,
    the rest is the sums'."""
    from ..limits import memory_budget_bytes

    need = frames * size * size * (1 if animation == "gif" else 4)
    budget = memory_budget_bytes() // 4
    if need > budget:
        raise InputError("%d frames at --size %d make a %s of %.1f GB, more than the %.1f GB "
                         "this machine allows; use fewer --frames or a smaller --size"
                         % (frames, size, animation.upper(), need / 2 ** 30, budget / 2 ** 30))


#: frames of one sequence: frame-000 ... frame-999, a 2-minute animation at 120 ms
MAX_FRAMES = 1000


def _frames_option(f):
    return click.option("--frames", type=click.IntRange(min=2, max=MAX_FRAMES), default=10,
                        show_default=True,
                        help="Number of frames, including both end shapes.")(f)


def _duration_option(f):
    return click.option("--duration", type=click.IntRange(min=10), default=120,
                        show_default=True, help="Milliseconds per frame of the animation.")(f)


def _animation_option(f):
    return click.option("--animation", type=click.Choice(["gif", "apng"]), default="gif",
                        show_default=True,
                        help="Animation written beside the frames: morph.gif (256 colours) "
                             "or morph.apng (full colour, anti-aliased edges kept).")(f)


def _morph_options(f):
    """Arguments A B and the options shared by `morph glyph` and `morph svg`."""
    for deco in reversed([shape_argument("a"), shape_argument("b"), _frames_option,
                          _duration_option, _animation_option, method_option,
                          common_options]):
        f = deco(f)
    return f


@main.command()
@_morph_options
def glyph(a, b, frames, duration, animation, method, font, tol, output, force, size):
    """Morph glyph A into glyph B: frames (1-a)·A ⊕ a·B (the paper's Fig. 6).

    Each frame is the Minkowski sum of A scaled by 1-a and B scaled by a, both
    centred on their area centroids, for a = 0 ... 1 in FRAMES steps: frame 0 is A,
    the last frame is B.  Writes frame-000.svg/.png ... and morph.gif (or
    morph.apng, --animation apng) into the output folder (default: glyph-A-B in
    the current directory; created if missing; an existing non-empty folder needs
    --force).  --tol is in em.

    \b
    Examples:
      morph glyph T M --frames 10
      morph glyph a g --frames 24 --font MyFont.otf -o ag/ --animation apng
    """
    _morph_command(a, b, frames, tol, output, force, size, duration, "glyph", method,
                   animation)


@main.command()
@_morph_options
def svg(a, b, frames, duration, animation, method, font, tol, output, force, size):
    """Morph SVG shape A into SVG shape B: frames (1-a)·A ⊕ a·B (Fig. 36).

    Like `morph glyph` for SVG files (closed paths; arcs are exact).  --tol is in the
    SVG's user units.  Writes frame SVGs and PNGs and morph.gif (or morph.apng) into
    the output folder (default: svg-A-B).

    \b
    Example:
      morph svg bird.svg butterfly.svg --frames 12 -o bird2butterfly/
    """
    _morph_command(a, b, frames, tol, output, force, size, duration, "svg", method,
                   animation)
