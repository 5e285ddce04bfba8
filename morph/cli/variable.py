"""The variable-font branches of the font commands (``--vary-nib``): a nib axis from
``--nib`` to ``--vary-nib`` (morph.fonts.variable)."""

from pathlib import Path

import click

from .options import InputError, check_nib_tol, count, progress_bar

def parse_vary_nib(spec, parse_nib):
    """(width, height, angle) of --vary-nib; InputError (exit 2) for a bad one."""
    try:
        return parse_nib(spec)
    except InputError as exc:
        raise InputError(str(exc).replace("--nib", "--vary-nib")) from None


def stroke_variable_cli(src, output, nib, vary_nib, glyphs, tol, sample, family, jobs, force,
                        parse_nib, default_nib, glyph_items):
    """``morph stroke SKELETON.ufo -o OUT.ttf --vary-nib ...``: the variable font, its
    designspace and masters, the sample image and the specimen."""
    import logging
    import time

    from ..errors import MorphError
    from ..fonts.jobs import default_jobs
    from ..fonts.specimen import sample_path, specimen_path, write_sample_image, write_specimen
    from ..fonts.variable import read_skeleton, stroke_variable, variable_outputs

    out = Path(output)
    if out.suffix.lower() not in (".ttf", ".otf"):
        raise InputError("a variable font (--vary-nib or a designspace skeleton) is a .ttf "
                         "(glyf/gvar) or .otf (CFF2): the output must end in .ttf or .otf, "
                         "got %s" % out)
    if not out.parent.is_dir():
        raise InputError("output folder %s does not exist" % out.parent)
    png, page = sample_path(out), specimen_path(out)
    for p in (out, *variable_outputs(out), png, page):
        if p.exists() and not force:
            raise InputError("%s exists; use --force to overwrite it" % p)
    try:
        skel = read_skeleton(src)
    except MorphError as exc:
        raise InputError(str(exc)) from exc
    font = skel.fonts[skel.default]
    upm = float(font.info.unitsPerEm or 1000)
    lo = parse_nib(nib) if nib is not None else tuple(v * (upm / 1000.0) if k < 2 else v
                                                    for k, v in enumerate(default_nib))
    hi = None if vary_nib is None else parse_vary_nib(vary_nib, parse_nib)
    _check_nibs(tol, lo, hi, vary_nib, upm)
    items = glyph_items(glyphs)
    for name in ("ufo2ft", "fontTools"):
        logging.getLogger(name).setLevel(logging.ERROR)
    jobs = default_jobs() if jobs is None else jobs
    t0 = time.perf_counter()
    n = len(font.keys()) if items is None else len(items)
    try:
        with progress_bar(n, "glyphs") as bar:
            stats = stroke_variable(skel, out, lo, hi, items, tol=tol * upm,
                                    family_name=family, overwrite=force, jobs=jobs,
                                    progress=lambda name: bar.update(1))
    except (MorphError, ValueError) as exc:
        raise InputError("%s: %s" % (src, exc)) from exc
    seconds = time.perf_counter() - t0
    write_sample_image(out, sample, png)
    write_specimen(out, None, sample=sample)
    axes = ["%s %g..%g" % (a.tag, a.minimum, a.maximum) for a in skel.axes]
    axis = stats["axis"]
    if axis is not None:
        axes.append("%s %s %g..%g" % (axis.tag, axis.name, axis.minimum, axis.maximum))
    click.echo("wrote %s (variable, axes %s, %s, %s stroked, %.1f s, %s), "
               "designspace %s, sample %s and specimen %s"
               % (out, ", ".join(axes), count(len(stats["masters"]), "master"),
                  count(stats["glyphs"], "glyph"), seconds, count(jobs, "job"),
                  stats["designspace"], png, page))
    return 0


def _read_font(path):
    from fontTools.ttLib import TTFont

    from ..errors import ParseError, one_line

    try:
        font = TTFont(str(path))
        font["head"]
    except Exception as exc:  # fontTools raises many types for garbage input
        raise ParseError("cannot read font %s: %s" % (path, one_line(exc)), str(path)) from exc
    return font


def is_variable_truetype(path):
    """True for a font file with fvar (a variable font)."""
    from fontTools.ttLib import TTFont

    try:
        return "fvar" in TTFont(str(path), lazy=True)
    except Exception:                   # noqa: BLE001 - the static path reports it
        return False


def _check_nibs(tol, nib, nib_max, vary_nib, upm):
    """The elliptical nib (w, h, angle) and the axis' other nib (None without
    --vary-nib) checked: two different nibs, and --tol below both
    (:func:`morph.cli.options.check_nib_tol`)."""
    from ..nib import ellipse_nib

    if nib_max is not None and tuple(map(float, nib)) == tuple(map(float, nib_max)):
        raise InputError("--vary-nib %s is the --nib nib: an axis needs two nibs" % vary_nib)
    check_nib_tol(tol, [ellipse_nib(*n) for n in (nib, nib_max) if n is not None], upm)


def brush_variable_cli(src, out, nib, nib_svg, items, tol, family, jobs, sample, png, page,
                       parse_nib, vary_nib=None, location=None):
    """``morph brush VARIABLE.ttf -o OUT.ttf`` (no --location): every axis kept;
    ``--vary-nib``: a nib axis added (to FONT at --location for a variable FONT with
    a location)."""
    import time

    from ..errors import MorphError
    from ..fonts.brush import open_source
    from ..fonts.jobs import default_jobs
    from ..fonts.specimen import write_sample_image, write_specimen
    from ..fonts.variable_brush import brush_variable
    from ..parse.glyphs import glyph_name

    if nib_svg:
        raise InputError("a variable brushed font (a variable FONT keeping its axes, or "
                         "--vary-nib) needs an elliptical --nib, not --nib-svg (give "
                         "--location for a static instance)")
    nib = parse_nib(nib)
    nib_max = None if vary_nib is None else parse_vary_nib(vary_nib, parse_nib)
    try:       # a variable FONT at --location: its static instance gets the nib axis
        font = open_source(src, location) if location else _read_font(src)
    except MorphError as exc:
        raise InputError(str(exc)) from exc
    names = None
    if items is not None:
        try:
            names = [glyph_name(font, it) for it in items]
        except MorphError as exc:
            raise InputError(str(exc)) from exc
    upm = font["head"].unitsPerEm
    _check_nibs(tol, nib, nib_max, vary_nib, upm)
    jobs = default_jobs() if jobs is None else jobs
    t0 = time.perf_counter()
    try:
        stats = brush_variable(font, out, nib, names, tol=tol * upm, family_name=family,
                               jobs=jobs, nib_max=nib_max)
    except (MorphError, ValueError) as exc:
        raise InputError("%s: %s" % (src, exc)) from exc
    write_sample_image(out, sample, png)
    write_specimen(out, None, sample=sample)
    axes = ["%s %g..%g" % (a.axisTag, a.minValue, a.maxValue)
            for a in stats["font"]["fvar"].axes]
    rep = stats["refinement"]
    added = "" if not rep or not rep["added"] else \
        " (%s)" % count(rep["added"], "intermediate source master")
    click.echo("wrote %s (variable, axes %s, %s%s, %s brushed, %.1f s), sample %s and "
               "specimen %s" % (out, ", ".join(axes), count(len(stats["masters"]), "master"),
                                added, count(stats["glyphs"], "glyph"),
                                time.perf_counter() - t0, png, page))
    return 0
