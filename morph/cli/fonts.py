"""Font commands: brush (filled glyphs swept by a nib), stroke (skeletons stroked by a nib)."""

import math
import re
from pathlib import Path

import click

from .group import main
from .options import (DEFAULT_TOL, EXIT_INTERNAL, FONT_TOL, LOCATION_HELP, InputError,
                      check_nib_tol, count, progress_bar, report_written, resolve_output,
                      tol_option, write_image)


#: --vary-nib's help texts; the variable branches (:mod:`.variable`) are imported
#: when they run: ``morph stroke`` of a static font does not load them
VARY_NIB_HELP = ("Make a variable font with a nib axis from the --nib nib (its minimum, "
                 "the default) to this one (its maximum), ellipse:W,H,ANGLE. The output "
                 "(.ttf: glyf/gvar, .otf: CFF2) keeps the untrimmed convolution as "
                 "overlapping contours (filled nonzero, overlap flags set); OUT.designspace "
                 "and the master UFOs in OUT-masters/ are written next to it. The axis is "
                 "NIBW (the nib width in font units) when the width grows, else NIBP (0 to "
                 "100 percent of the way). Intermediate masters are added where an "
                 "instance would miss the exact sum by more than its share of --tol (a "
                 "nib that turns or changes aspect; a skeleton designspace whose "
                 "interpolation turns the strokes); a nib that only grows needs none. "
                 "Explicit feature-file anchors become variable anchors. Static outputs "
                 "(no --vary-nib) are trimmed and free of overlaps.")


BRUSH_VARY_NIB_HELP = ("Make a variable font with a nib axis from the --nib nib (its "
                       "default) to this one, ellipse:W,H,ANGLE, for a static FONT too (a "
                       "variable FONT keeps its axes and gets this one after them). Two "
                       "disks, the second larger, make the registered grade axis GRAD "
                       "(user value: the diameter's growth in units per 1000 em; the "
                       "advances stay those of the --nib disk, so no text reflows); "
                       "other nibs NIBW (the nib width) or NIBP (percent of the way). The "
                       "output keeps overlapping contours: TrueType (.ttf, .woff2, .woff: "
                       "glyf/gvar, overlap flags set) or CFF2 (.otf). Intermediate masters "
                       "are added where an instance would miss the exact sum by more than "
                       "its share of --tol (a nib that turns or changes aspect; a variable "
                       "FONT whose interpolation turns the outlines).")


def _variable():
    """The variable branches of the font commands (:mod:`.variable`), imported when
    one may run."""
    from . import variable

    return variable


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
    if not all(math.isfinite(v) for v in (w, h, a)) or w <= 0 or h <= 0:
        raise InputError("--nib width and height must be positive and finite, the angle "
                         "finite: got %r" % spec)
    if max(w, h) > 1e6 * min(w, h):
        raise InputError("--nib %r is more than 1e6 times longer than wide: a nib that thin "
                         "is not supported" % spec)
    return w, h, a


@main.command()
@click.argument("font_file", metavar="FONT", required=False, default="default")
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="Output font: .ttf, .otf, .woff2 or .woff (the outline format is the "
                   "source's, a variable output's TrueType; the suffix picks the "
                   "container). Also written next to it: "
                   "OUTPUT.png (sample image) and OUTPUT.html (specimen), e.g. X.ttf.png "
                   "and X.ttf.html for -o X.ttf.")
@click.option("--nib", default="ellipse:80,30,30", show_default=True,
              help="Elliptical nib: width, height in font units and angle in degrees.")
@click.option("--nib-svg", type=click.Path(dir_okay=False), default=None,
              help="A convex SVG shape as the nib (user units = font units; its origin "
                   "is the pen point). Overrides --nib.")
@click.option("--glyphs", default="all", show_default=True,
              help="Characters, ranges (a-z) and glyph names, comma separated; 'all': "
                   "every glyph drawn by its own contours (composites follow).")
@click.option("--sample", default="Hamburgefonstiv", show_default=True,
              help="Text of the sample image and the specimen. A font that does not draw "
                   "every character of it gets a sample of its own characters (cmap "
                   "order), with a note.")
@click.option("--family", default=None, help="New family name (default: FAMILY Brush).")
@tol_option(default=FONT_TOL, what="outlines (sum and curve conversion together)",
            note="5e-4 em = 0.5 font units at 1000 units per em; the outlines are then "
                 "rounded to integer coordinates (<= 0.71 unit more).")
@click.option("--composites", type=click.Choice(["follow", "sweep"]), default="follow",
              show_default=True,
              help="Composite glyphs using a swept glyph but not chosen (e.g. eacute when e "
                   "is swept): follow (stay composites, widened by the nib) or sweep "
                   "(decomposed and swept too).")
@click.option("--location", default=None, metavar="TAG=VALUE,...", help=LOCATION_HELP)
@click.option("--jobs", type=click.IntRange(min=1), default=None,
              help="Processes computing the glyphs (default: the number of CPUs). The "
                   "font does not depend on it.")
@click.option("--vary-nib", default=None, metavar="ellipse:W,H,ANGLE",
              help=BRUSH_VARY_NIB_HELP)
@click.option("--force", is_flag=True, default=False, help="Overwrite existing outputs.")
def brush(font_file, output, nib, nib_svg, glyphs, sample, family, tol, composites, location,
          jobs, vary_nib, force):
    """Sweep the glyphs of FONT with a fixed calligraphic nib (Fig. 5).

    Every chosen glyph is replaced by glyph ⊕ nib (the nib keeps its orientation),
    converted to the font's curve type within --tol em (TrueType: quadratics,
    CFF/.otf: cubics), with the advance width grown by the nib width (zero-width
    marks stay so).  GPOS mark anchors move with their glyphs, vertical metrics grow
    by the nib, names and OS/2 widths are updated.  FONT is a .ttf/.otf file (a
    variable font at --location gives a static instance), or omitted / "default"
    for the bundled Noto Sans.  The nib must be convex.  Also writes OUTPUT.png (the sample text set
    in the new font with Pillow) and OUTPUT.html (a specimen: waterfall and all
    characters, source and result side by side).

    A variable FONT (glyf/gvar or CFF2) without --location keeps every axis:
    each master's glyphs are brushed as untrimmed, overlapping contours
    compatible across the masters, its layout kept; the output is TrueType
    (.ttf, .woff2, .woff: overlap flags set) or CFF2 (.otf).  --vary-nib adds a nib axis, to a
    static FONT (or FONT at --location) too.  Static outputs are trimmed: one
    outline, free of overlaps.

    A glyph whose sum fails is computed again at --tol/8, then with the nib turned
    by a tiny angle (within --tol); if that fails too it is written by a polygon
    fallback (Clipper sum of the flattened glyph and nib,
    within --tol but made of lines), or left as in the source if that fails
    too.  The font is written anyway; the glyphs that fell
    back are then named on one line and the exit status is 1.

    \b
    Examples:
      morph brush -o NotoBrush.ttf
      morph brush MyFont.otf -o Brushed.woff2 --nib ellipse:120,20,-30 --glyphs a-z
      morph brush Variable.ttf --location wght=700 -o BoldBrush.ttf --jobs 4
      morph brush Variable.ttf -o VariableBrush.ttf --nib ellipse:60,15,30
      morph brush MyFont.otf -o Graded.ttf --nib ellipse:20,20 --vary-nib ellipse:50,50
    """
    from ..fonts.tables import FONT_SUFFIXES
    from ..nib import ellipse_nib

    src = _brush_source(font_file)
    out = resolve_output(output, "brush.ttf", force, suffixes=FONT_SUFFIXES)
    png, page = _companions(out, force)
    nib_region = _checked_nib(lambda: _svg_nib(nib_svg) if nib_svg
                              else ellipse_nib(*_parse_nib(nib)))
    items = _glyph_items(glyphs, everything="all")
    variable = _variable()
    if vary_nib is not None or (location is None and variable.is_variable_truetype(src)):
        return variable.brush_variable_cli(src, out, nib, nib_svg, items, tol, family, jobs,
                                           sample, png, page, _parse_nib, vary_nib, location)
    return _brush_static(src, location, out, nib_region, items, tol, family, composites,
                         jobs, sample, png, page)


def _brush_static(src, location, out, nib_region, items, tol, family, composites, jobs,
                  sample, png, page):
    """The static brush of ``morph brush``: the source (a variable font at
    ``location``) brushed into ``out``, its sample PNG and specimen written; the
    exit status (1 when glyphs fell back)."""
    import time

    from ..fonts.brush import brush_font, open_source, written_ink
    from ..fonts.jobs import default_jobs
    from ..fonts.specimen import write_sample_image, write_specimen
    from ..fonts.tables import outline_glyphs
    from ..parse import font_display_name

    source = open_source(src, location)  # static: a variable font at --location
    check_nib_tol(tol, [nib_region], source["head"].unitsPerEm)
    source_copy = _source_copy(src, location, source)  # as it was, for the specimen
    jobs = default_jobs() if jobs is None else jobs
    total = len(items) if items is not None else len(outline_glyphs(source))
    t0 = time.perf_counter()
    with progress_bar(total, "glyphs", "morph brush") as bar:
        stats = brush_font(source, out, nib_region, items, tol=tol * source["head"].unitsPerEm,
                           family_name=family, progress=lambda name: bar.update(1),
                           composites=composites, jobs=jobs, in_flight=bar.partial)
    seconds = time.perf_counter() - t0
    ink = written_ink(source)   # the written font, as brush_font left it
    sample = _covered_sample(out, sample, ink=ink)
    write_sample_image(out, sample, png)
    write_specimen(out, source_copy, sample=sample, cmap=ink[0],
                   display_name=font_display_name(source, out.stem))
    click.echo("wrote %s (%s, %s, %.1f s, %s), sample %s and specimen %s"
               % (out, count(stats["glyphs"], "glyph"), count(stats["contours"], "contour"),
                  seconds, count(jobs, "job"), png, page))
    return _brush_status(stats)


def _source_copy(src, location, source):
    """The source as it was, for the specimen (``brush_font`` changes ``source``): a
    static font file read again (its bytes, nothing compiled), a variable font's
    instance compiled to bytes and read back."""
    import io

    from fontTools.ttLib import TTFont

    from ..fonts.tables import font_bytes
    from ..parse import default_font_path

    if not location and not hasattr(src, "getGlyphSet"):
        copy = TTFont(io.BytesIO(Path(default_font_path() if src is None else src).read_bytes()))
        if "fvar" not in copy:
            return copy
    return TTFont(io.BytesIO(font_bytes(source)))


def _brush_status(stats):
    """Notes on the bases swept without being chosen, then the exit status
    (:func:`_fallback_status`)."""
    for base, users in stats["base_not_chosen"].items():
        click.echo("note: swept %s too (not chosen), the base of %s" % (base, ", ".join(users)),
                   err=True)
    return _fallback_status([(n, "%s: %s" % (_BRUSH_FALLBACKS[k], err))
                             for n, (k, err) in sorted(stats["fallback"].items())], "")


_BRUSH_FALLBACKS = {"retry": "exact sum at tol/8", "rotated": "exact sum, nib turned within tol",
                    "polygon": "polygon sum", "source": "left as in the source"}


def _brush_source(font_file):
    """The font file to brush: FONT, or the bundled font for none / "default"."""
    from ..parse import default_font_path

    src = default_font_path() if font_file in (None, "default") else font_file
    if Path(src).is_dir() and (Path(src) / "metainfo.plist").is_file():
        raise InputError("%s is a UFO source: morph brush reads compiled fonts (.ttf, .otf); "
                         "stroke a UFO skeleton with 'morph stroke', or compile a UFO of "
                         "filled outlines first (fontmake)" % src)
    if Path(src).is_dir():
        raise InputError("font %s is a folder, not a font file" % src)
    if not Path(src).is_file():
        raise InputError("font %s does not exist" % src)
    return src


def _companions(out, force, specimen=True):
    """(OUT.png, OUT.html or None) written next to a font OUT (e.g. X.ttf.png,
    X.ttf.html: :func:`morph.fonts.specimen.sample_path`, ``specimen_path``);
    InputError when one exists and ``force`` is not given."""
    from ..fonts.specimen import sample_path, specimen_path

    png, page = sample_path(out), specimen_path(out) if specimen else None
    for extra in (png, page):
        if extra is not None and extra.exists() and not force:
            raise InputError("%s exists; use --force to overwrite it" % extra)
    return png, page


def _covered_sample(font, sample, ink=None):
    """--sample when the written font draws it, else its own characters
    (:func:`morph.fonts.specimen.sample_text`, ``ink`` its argument), with a note on
    stderr."""
    from ..fonts.specimen import sample_text

    text, changed = sample_text(font, sample, ink=ink)
    if changed:
        click.echo("note: the font does not draw every character of the sample %r: the "
                   "sample image and specimen show its own characters %r" % (sample, text),
                   err=True)
    return text


def _checked_nib(make):
    """The nib region ``make()`` returns, checked convex; a bad nib is bad input
    (InputError, exit 2)."""
    from ..errors import MorphError
    from ..nib import check_convex_nib

    try:
        nib_region = make()
        check_convex_nib(nib_region)
    except MorphError as exc:
        raise InputError(str(exc)) from exc
    return nib_region


def _glyph_items(spec, everything=None):
    """--glyphs as characters and names; None for every glyph (no spec, or the word
    ``everything``).  InputError when it selects nothing."""
    if spec is None or (everything and spec.strip().lower() == everything):
        return None
    from ..fonts.brush import parse_glyph_spec

    items = parse_glyph_spec(spec)
    if not items:
        raise InputError("--glyphs selects no glyph")
    return items


def _fallback_status(fallbacks, what):
    """Exit status of a font command: 0, or 1 after naming the glyphs that fell back
    (``fallbacks``: (glyph name, reason) pairs; ``what``: how, e.g. " to a polygon
    stroke") on one line, each reason once with the glyphs it names."""
    if not fallbacks:
        return 0
    names = {}
    for name, why in fallbacks:
        names.setdefault(str(why), []).append(name)
    click.echo("morph: error: font written, but %d glyph(s) fell back%s: %s"
               % (len(fallbacks), what, "; ".join("%s (%s)" % (", ".join(n), why)
                                                  for why, n in names.items())), err=True)
    return EXIT_INTERNAL


# =========================================================================== stroke

_STROKE_NIB = "ellipse:90,20,30"


@main.command()
@click.argument("skeleton", metavar="SKELETON")
@click.option("-o", "--output", required=True, type=click.Path(),
              help="UFO skeleton: OUT.ufo (a copy of the source, outlines replaced), "
                   "OUT.otf (CFF) or OUT.ttf (TrueType), compiled with ufo2ft, plus a "
                   "sample image OUT.png (and a specimen OUT.html for a font; e.g. "
                   "X.otf.png and X.otf.html for -o X.otf). SVG "
                   "skeleton: OUT.svg or OUT.png.")
@click.option("--nib", default=None,
              help="Elliptical nib ellipse:W,H,ANGLE: width and height in font units "
                   "(UFO) or user units (SVG), long axis ANGLE degrees counter-clockwise. "
                   "Default: %s, a broad nib at 30 degrees, for 1000 units per em "
                   "(scaled to the UFO's units per em; for an SVG, to its larger side "
                   "taken as 1000 units)." % _STROKE_NIB)
@click.option("--nib-svg", type=click.Path(dir_okay=False), default=None,
              help="A convex SVG shape as the nib (user units = font units; its origin "
                   "is the pen point). Overrides --nib.")
@click.option("--glyphs", default=None,
              help="UFO only: characters, ranges (a-z) and glyph names, comma separated. "
                   "Default: every glyph. Glyphs not chosen (nor following as composites) "
                   "are left empty with their advances, so the output compiles; a .ufo "
                   "output keeps their skeletons in its layer 'skeleton'.")
@tol_option(default=None, what="outlines (stroke and curve conversion together)",
            note="Default: %g em for a UFO (the outlines are then rounded to integer "
                 "coordinates, <= 0.71 unit more), %g of the drawing's size for an SVG, "
                 "as for images of the other commands." % (FONT_TOL, DEFAULT_TOL))
@click.option("--sample", default="Hamburgefonstiv", show_default=True,
              help="Text of the sample image (UFO skeletons). A font that does not draw "
                   "every character of it gets a sample of its own characters (cmap "
                   "order), with a note.")
@click.option("--family", default=None, help="New family name (default: FAMILY Stroke).")
@click.option("--jobs", type=click.IntRange(min=1), default=None,
              help="Processes computing the glyphs (default: the number of CPUs). The "
                   "font does not depend on it.")
@click.option("--size", type=click.IntRange(min=8, max=8192), default=512,
              show_default=True, help="SVG skeleton to PNG: longer side in pixels.")
@click.option("--vary-nib", default=None, metavar="ellipse:W,H,ANGLE", help=VARY_NIB_HELP)
@click.option("--force", is_flag=True, default=False, help="Overwrite existing outputs.")
def stroke(skeleton, output, nib, nib_svg, glyphs, tol, sample, family, jobs, size, vary_nib,
           force):
    """Stroke a skeleton (centre lines) with a calligraphic nib (Fig. 5).

    Every path of SKELETON is swept by a convex nib held at a fixed angle: an
    open path gives its two sides, convolved with the nib, closed by the nib's
    own ends (caps); a closed path is stroked, not filled; a single point gives
    the nib.  The broad nib's thick and thin strokes come from the direction of
    travel, as with a pen.  The default nib is an ellipse 90 x 20 units with its
    long axis at 30 degrees (upm 1000).

    SKELETON is a UFO font source (.ufo folder; open contours are centre lines)
    or an SVG file (its stroked / open paths are centre lines).  For a UFO, the
    kerning, groups and features are kept, anchors move with the outlines,
    advances grow by the nib width (side bearings kept), composites stay
    composites (a scaled, mirrored or turned component is decomposed and
    stroked; a half turn is kept when the nib is centrally symmetric; so is a
    component whose stroke could meet the rest of the glyph's, which is then
    trimmed with it into one outline).
    A glyph whose exact stroke fails is written by a polygon fallback (Clipper,
    within --tol, made of lines); the font is written anyway, those glyphs are
    named on one line and the exit status is 1.

    Static outputs are trimmed: one outline, free of overlaps.  Variable
    outputs (--vary-nib, or a .designspace of compatible skeleton masters:
    every master stroked, axes and instances kept) keep the untrimmed
    convolution as overlapping contours, compatible in every master; the
    renderers fill them as the sum (nonzero, overlap flags set).

    \b
    Examples:
      morph stroke Relief-SingleLine.ufo -o ReliefStroke.otf
      morph stroke Relief-SingleLine.ufo -o ReliefNib.ttf --nib ellipse:40,10,30
            --vary-nib ellipse:120,30,30
      morph stroke Family.designspace -o FamilyStroke.ttf
      morph stroke Relief-SingleLine.ufo -o Round.ttf --nib ellipse:60,60,0
      morph stroke Sketch.ufo -o Sketch-Stroke.ufo --glyphs A-Z,a-z
      morph stroke drawing.svg -o drawing-stroke.svg --nib ellipse:8,2,30
    """
    src = Path(skeleton)
    if not src.exists():
        raise InputError("skeleton %s does not exist" % skeleton)
    if src.suffix.lower() == ".svg":
        if vary_nib is not None:
            raise InputError("--vary-nib needs a UFO skeleton (a font), not an SVG")
        return _stroke_svg(src, output, nib, nib_svg, glyphs, tol, size, force)
    elif src.is_dir() or src.suffix.lower() == ".designspace":
        tol = FONT_TOL if tol is None else tol
        if vary_nib is not None or not src.is_dir():
            if nib_svg:
                raise InputError("a variable font needs elliptical nibs (--nib), not --nib-svg")
            return _variable().stroke_variable_cli(
                src, output, nib, vary_nib, glyphs, tol, sample, family, jobs, force,
                _parse_nib, _parse_nib(_STROKE_NIB), _glyph_items)
        return _stroke_ufo_cli(src, output, nib, nib_svg, glyphs, tol, sample, family, jobs,
                               force)
    else:
        raise InputError("skeleton %s is neither a .ufo folder, a .designspace nor an .svg "
                         "file" % skeleton)


def _svg_nib(path):
    """The nib region of --nib-svg: the SVG reader and its XML parser load for it
    only."""
    from ..parse import svg_region

    return svg_region(path)


def _stroke_nib(nib, nib_svg, scale):
    """Nib region from --nib-svg, --nib, or the default scaled by ``scale``; checked
    convex (InputError otherwise)."""
    from ..nib import ellipse_nib

    def make():
        if nib_svg:
            return _svg_nib(nib_svg)
        if nib is None:
            w, h, a = _parse_nib(_STROKE_NIB)
            return ellipse_nib(w * scale, h * scale, a)
        return ellipse_nib(*_parse_nib(nib))

    return _checked_nib(make)


def _stroke_output(output, force):
    """The checked UFO-skeleton output: .ufo (a folder), .otf or .ttf (a file)."""
    out = Path(output)
    if out.suffix.lower() not in (".ufo", ".otf", ".ttf"):
        raise InputError("cannot tell the output format of %s: use a .ufo, .otf or .ttf "
                         "suffix" % out)
    if not out.parent.is_dir():
        raise InputError("output folder %s does not exist" % out.parent)
    if out.exists() and not force:
        raise InputError("output %s exists; use --force to overwrite it" % out)
    if out.exists() and out.suffix.lower() != ".ufo" and out.is_dir():
        raise InputError("output %s is a folder, expected a file" % out)
    return out


def _stroke_ufo_cli(src, output, nib, nib_svg, glyphs, tol, sample, family, jobs, force):
    import logging
    import time

    from ..fonts.jobs import default_jobs
    from ..fonts.specimen import write_sample_image, write_specimen
    from ..fonts.stream import SkeletonSource
    from ..fonts.stroke import stroke_ufo

    out = _stroke_output(output, force)
    png, page = _companions(out, force, specimen=out.suffix.lower() != ".ufo")
    # read once: the glyphs' shells, not their outlines; without ufoLib2 for a compiled
    # font where the UFO allows it (morph.parse.light_ufo)
    source = SkeletonSource(src, light=out.suffix.lower() != ".ufo")
    font = source.shell_font()
    upm = float(font.info.unitsPerEm or 1000)
    nib_region = _stroke_nib(nib, nib_svg, upm / 1000.0)
    check_nib_tol(tol, [nib_region], upm)
    items = _glyph_items(glyphs)
    for name in ("ufo2ft", "fontTools"):  # feature-merging notes are not errors
        logging.getLogger(name).setLevel(logging.ERROR)
    jobs = default_jobs() if jobs is None else jobs
    t0 = time.perf_counter()
    with progress_bar(len(font), "glyphs", "morph stroke") as bar:
        stats = stroke_ufo(source, out, nib_region, items, tol=tol * upm, family_name=family,
                           progress=lambda name: bar.update(1), overwrite=force, jobs=jobs,
                           in_flight=bar.partial, planned=bar.set_total)
    seconds = time.perf_counter() - t0
    if page:
        shown = out
    else:  # a .ufo: the glyphs the sample may show, compiled (not the whole font)
        from ..fonts.stream import sample_font

        shown = sample_font(out, sample)
    ink = name = None
    if page and getattr(stats["font"], "light", False):
        # the written glyphs' cmap, ink and name, known (the font's outlines unread)
        from ..fonts.fontinfo import full_name

        skip = set(stats["font"].lib.get("public.skipExportGlyphs", ()))
        ink = ({u: g.name for g in stats["font"] if g.name not in skip for u in g.unicodes},
               stats["inked"].__contains__)
        name = full_name(stats["font"].info)
    sample = _covered_sample(shown, sample, ink)
    write_sample_image(shown, sample, png)
    if page:   # the glyph names as written (production names): the font's own cmap
        write_specimen(out, None, sample=sample, cmap=stats.get("cmap"), display_name=name)
    click.echo("wrote %s (%s stroked, %s kept, %s, %.1f s, %s), sample %s%s"
               % (out, count(stats["glyphs"] + stats["followed"], "glyph"),
                  count(stats["composites"], "composite"), count(stats["points"], "point"),
                  seconds, count(jobs, "job"), png,
                  " and specimen %s" % page if page else ""))
    if stats["emptied"]:
        from ..fonts.stroke import SKELETON_LAYER

        click.echo("note: %s not chosen by --glyphs left empty (advances kept)%s"
                   % (count(stats["emptied"], "glyph"),
                      "; their skeletons are in the UFO layer '%s'" % SKELETON_LAYER
                      if out.suffix.lower() == ".ufo" else ""), err=True)
    return _fallback_status(sorted(stats["fallback"].items()), " to a polygon stroke")


def _stroke_svg(src, output, nib, nib_svg, glyphs, tol, size, force):
    """``morph stroke`` of an SVG skeleton: an image of its paths ⊕ nib within ``tol``
    user units (stroke and SVG export together, as ``morph sum``)."""
    from ..errors import ParseError
    from ..budget import plan
    from ..fonts.stroke import stroke_glyph_region
    from ..limits import check_tolerance
    from ..parse.svg import svg_paths
    from ..region import region_bbox

    if glyphs is not None:
        raise InputError("--glyphs applies to UFO skeletons only")
    out = resolve_output(output, "stroke.svg", force)
    try:  # centre lines: the stroked elements, else every drawn path
        paths = svg_paths(str(src), stroked=True)
    except ParseError:
        paths = svg_paths(str(src))
    lines = [pieces for pieces, _ in paths]
    box = region_bbox(lines)
    scale = max(box[2] - box[0], box[3] - box[1], 1e-12) / 1000.0
    nib_region = _stroke_nib(nib, nib_svg, scale)
    if tol is None:  # relative to the drawing, as for the shapes of the other commands
        tol = DEFAULT_TOL * 1000.0 * scale
    check_tolerance(tol, lines, nib_region, operation="SVG %s" % src.name,
                    unit_name="user units")
    st, et = plan(tol)[:2]  # the stroke and the SVG export share --tol
    region = stroke_glyph_region(paths, nib_region, st)
    write_image(out, [(region, {"fill": "black"})], size=size, tol=et)
    report_written(out, region)
