"""Shared vocabulary of the commands: shape arguments, options, output paths."""

from pathlib import Path

import click

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 1
#: --tol of every command is absolute: in em for glyphs and fonts (font units divided
#: by units per em), in user units for SVG; it bounds the written curves' distance
#: from the exact result (computation and export together).  Defaults: images 1e-4
#: em for glyphs and 1e-4 of the drawing's size for SVG
#: (:meth:`morph.parse.Shape.tolerance`), fonts 5e-4 em (their outlines are then
#: rounded to integer units, <= 0.71 unit more).  The library's ``tol`` is in the
#: shapes' own units: :meth:`morph.parse.Shape.em_to_units` converts.
DEFAULT_TOL = 1e-4
FONT_TOL = 5e-4
TOL_UNITS = ("absolute, in em for glyphs and fonts (1e-4 em = 0.1 unit at 1000 units per "
             "em), in user units for SVG (the library's tol is in the shapes' units: "
             "em x units per em, morph.parse.em_to_units)")
TOL_DEFAULT_NOTE = ("Default: 1e-4 em for glyphs, 1e-4 of the drawing's size (the larger "
                    "side of the shapes' bounding boxes) for SVG.")
IMAGE_SUFFIXES = (".png", ".svg")


class InputError(click.ClickException):
    """Bad input found by a command (e.g. an output that exists): one line, exit 2."""

    exit_code = EXIT_BAD_INPUT


# =========================================================================== shapes

def shape_tolerance(shape, tol, *others, check=True, share=1.0):
    """--tol in the shape's units: em -> font units for glyphs, as is for SVG; no
    --tol (None): the default relative to the size (:meth:`morph.parse.Shape.tolerance`).

    With ``check`` the tolerance is checked against this shape and the ``others``
    (regions summed with it, e.g. the other operand or the offset disk) by
    :func:`morph.limits.check_tolerance`: finer than the coordinates resolve or
    than 1e-12 of the size, larger than the shapes, beyond the point budget:
    LimitError, one line naming a tolerance that works, exit 2.  ``share``: the part
    of --tol the computation runs at (:func:`morph.budget.plan`); the
    check is made at it and its message names --tol values.
    """
    t = shape.tolerance(tol, *others)  # None: the default, relative to the size
    if check:
        from ..limits import check_tolerance

        upm = shape.units_per_em
        what = ("glyph %r" % shape.name) if upm else ("SVG %s" % shape.name)
        check_tolerance(t * share, shape.region, *others, operation=what,
                        unit=(upm or 1.0) * share, unit_name="em" if upm else "user units")
    return t



def writer_budget(shape, tol, *others):
    """--tol of a command that computes a shape and writes it: in the shape's units,
    checked at the geometry's share (:func:`shape_tolerance`), split by
    :func:`morph.budget.plan` (the geometry's share; ``.after(bound)`` the export's)."""
    from ..budget import SUM_SHARE, plan

    return plan(shape_tolerance(shape, tol, *others, share=SUM_SHARE))

class ShapeParam(click.ParamType):
    """Click type: a glyph character/name or an .svg path -> :class:`morph.parse.Shape`.

    Loads with the ``--font`` value (``--font`` is eager, so it is known first).
    Parse errors propagate as MorphError (one clean line, exit 2).
    """

    name = "SHAPE"

    def convert(self, value, param, ctx):
        from ..parse import Shape, load_shape

        if isinstance(value, Shape):
            return value
        font = ctx.params.get("font") if ctx is not None else None
        location = ctx.meta.get("morph.location") if ctx is not None else None
        shape = load_shape(value, font, location)
        LOADED_SHAPES.append(shape)  # saved by MORPH_DEBUG=1 on an internal failure
        return shape


SHAPE = ShapeParam()
LOADED_SHAPES = []


def shape_argument(name="shape", **kwargs):
    """Decorator: a positional shape argument converted to a :class:`morph.parse.Shape`."""
    return click.argument(name, type=SHAPE, metavar=name.upper(), **kwargs)


# =========================================================================== options

LOCATION_HELP = ("Instance of a variable font, e.g. wght=700,wdth=90 (fontTools instancer; "
                 "axes not given take their default). Default: the default instance.")


def _remember_location(ctx, param, value):
    from ..parse import parse_location

    ctx.meta["morph.location"] = parse_location(value)  # ParseError: one line, exit 2
    return value


def font_option(f):
    """--font and --location (eager: known before the shape arguments are loaded)."""
    f = click.option("--location", default=None, is_eager=True, expose_value=False,
                     callback=_remember_location, metavar="TAG=VALUE,...",
                     help=LOCATION_HELP)(f)
    return click.option(
        "--font", type=click.Path(dir_okay=False), default=None, is_eager=True,
        help="Font file (TrueType/OpenType) for glyph shapes. Default: the bundled "
             "Noto Sans Regular (TrueType).")(f)


class PositiveFinite(click.FloatRange):
    """Click type: a float > 0 that is not inf or nan."""

    def __init__(self):
        super().__init__(min=0.0, min_open=True)

    def convert(self, value, param, ctx):
        rv = super().convert(value, param, ctx)
        if rv != rv or rv in (float("inf"), float("-inf")):
            self.fail("%r is not a finite number" % (value,), param, ctx)
        return rv


def tol_option(f=None, default=DEFAULT_TOL, what="curve output", note=""):
    """--tol, stated the same way by every command (:data:`TOL_UNITS`): a decorator,
    or ``tol_option(default=..., what=..., note=...)`` for one (``default`` None: the
    command picks it, ``note`` says how)."""
    def deco(f):
        return click.option(
            "--tol", type=PositiveFinite(), default=default, show_default=default is not None,
            help="Tolerance of the %s: %s.%s" % (what, TOL_UNITS, " " + note if note else ""))(f)
    return deco(f) if f is not None else deco


def output_option(f):
    return click.option(
        "-o", "--output", type=click.Path(dir_okay=True), default=None,
        help="Output file; the format follows the suffix (.png or .svg). For frame "
             "sequences, a folder. Default: a name derived from the command and "
             "shape in the current directory.")(f)


def force_option(f):
    return click.option("--force", is_flag=True, default=False,
                        help="Overwrite an existing output file (for frames: replace the "
                             "frames and animation morph wrote in the folder before).")(f)


def size_option(f):
    return click.option("--size", type=click.IntRange(min=8, max=8192), default=512,
                        show_default=True,
                        help="Longer side of the image in pixels.")(f)


def _default_tol_option(f):
    return tol_option(f, default=None, note=TOL_DEFAULT_NOTE)


def common_options(f):
    """--font, --tol, -o/--output, --force, --size: the shared vocabulary; the shape
    arguments are checked against them (:func:`check_shape_units`).  --tol is None
    when not given (:func:`shape_tolerance` takes the default)."""
    import functools

    @functools.wraps(f)
    def checked(*args, **kwargs):
        check_shape_units(kwargs.get("font"),
                          [v for v in kwargs.values() if hasattr(v, "units_per_em")])
        return f(*args, **kwargs)

    for deco in (size_option, force_option, output_option, _default_tol_option, font_option):
        checked = deco(checked)
    return checked


def check_shape_units(font, shapes):
    """The shapes of one command and --font agree: --font given while every shape is
    an SVG file is bad input (InputError: it would be ignored); SVG shapes (user
    units) combined with glyphs (font units) are summed as 1 user unit = 1 font unit,
    which a MorphWarning says."""
    import warnings

    from ..errors import MorphWarning

    kinds = {s.kind for s in shapes}
    if font is not None and shapes and kinds == {"svg"}:
        raise InputError("--font %s applies to glyph shapes, and %s %s SVG file%s"
                         % (font, " and ".join(s.name for s in shapes),
                            "is an" if len(shapes) == 1 else "are",
                            "" if len(shapes) == 1 else "s"))
    if kinds == {"svg", "glyph"}:
        svg = [s.name for s in shapes if s.kind == "svg"]
        glyph = [s.name for s in shapes if s.kind == "glyph"]
        warnings.warn(MorphWarning(
            "%s in SVG user units and glyph %s in font units are combined as 1 user unit "
            "= 1 font unit (--tol in the units of the first shape, %s)"
            % (", ".join(svg), ", ".join(glyph),
               "user units" if shapes[0].kind == "svg" else "em")))


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

    An existing non-empty folder needs ``force`` (the command then removes the
    frames it wrote before and does not write again, see
    :func:`morph.render.figures.stale_frame_files`; other files are kept).  Raises
    InputError.
    """
    path = Path(output) if output is not None else Path.cwd() / default_name
    if path.exists() and not path.is_dir():
        raise InputError("output %s exists and is not a folder" % path)
    if path.is_dir() and any(path.iterdir()) and not force:
        raise InputError("output folder %s is not empty (frames of an earlier run?); use "
                         "--force to replace the frames morph wrote there (other files "
                         "are kept)" % path)
    if not path.parent.is_dir():
        raise InputError("output folder %s does not exist" % path.parent)
    path.mkdir(exist_ok=True)
    return path


def write_image(path, shapes, size=512, tol=None, **style):
    """Write shapes to ``path`` as PNG or SVG by suffix (``tol`` in shape units)."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".svg":  # Pillow is not loaded for SVG output
            from ..render import write_svg

            write_svg(str(path), shapes, size=size, tol=tol, **style)
        else:
            from ..render import write_png

            write_png(str(path), shapes, size=size, **style)
    except OSError as exc:
        raise click.FileError(str(path), hint=exc.strerror or str(exc)) from exc
    return path


def count(n, word):
    """``1 loop``, ``2 loops``: a count with its noun."""
    return "%d %s%s" % (n, word, "" if n == 1 else "s")


def report_written(path, loops):
    """The one line a command prints after writing a region: the file, its loops
    and pieces."""
    click.echo("wrote %s (%s, %s)" % (path, count(len(loops), "loop"),
                                      count(sum(map(len, loops)), "piece")))


#: seconds between the status lines of a run whose stderr is not a terminal
STATUS_SECONDS = 5.0
#: seconds between redraws of the progress line on a terminal
REDRAW_SECONDS = 0.5


class Progress:
    """Work done, counted in items (glyphs, frames), on stderr.

    ``update(n)`` adds ``n`` items done (a batch of glyphs finishing together adds
    each).  ``partial(units)`` adds (or, negative, takes back) work in flight: the
    items' worth that unfinished batches have reported (a chunk of glyphs whose
    sums are done, :func:`morph.fonts.jobs.glyph_progress`); it is taken back as
    the batch's items are added.  The count shown is the items done plus the work
    in flight, in whole items, and never goes back.  The status says that count of
    all, the percentage, the time elapsed, and once something is done the time
    left: the time per item done so far times the items left (no estimate before
    the first item: a rate from nothing done is no rate); when everything is done
    but the command still works (writing, compiling), it says so.  On a terminal
    the line is redrawn in place, at most every :data:`REDRAW_SECONDS`; otherwise
    (a pipe, a log) a line is printed every :data:`STATUS_SECONDS`, and a last one
    at the end when any was (a short run prints nothing).  A background thread
    keeps the clock, so a long first batch still shows the time passing.
    """

    def __init__(self, total, label, command="morph", stream=None, tty=None, interval=None):
        import sys
        import threading

        self.total, self.label, self.command = int(total), label, command
        self.stream = sys.stderr if stream is None else stream
        self.tty = self.stream.isatty() if tty is None else tty
        self.interval = (interval if interval is not None
                         else REDRAW_SECONDS if self.tty else STATUS_SECONDS)
        self.done = 0
        self.flight = 0.0       # work in flight (partial), in items
        self._best = 0.0        # the most work shown so far: the count never goes back
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._tick, daemon=True)
        self._start = None
        self._shown = False
        self._drawn = float("-inf")   # when the line was last drawn (monotonic s)

    def __enter__(self):
        import time

        self._start = time.monotonic()
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()
        if self._shown:  # the last line: all done, or where it stopped
            self._show(final=True)
        return False

    def update(self, n=1):
        with self._lock:
            self.done = min(self.total, self.done + n)
        if self.tty:
            self._redraw()

    def set_total(self, total):
        """The number of items, once known (a plan made after the bar started)."""
        with self._lock:
            self.total = int(total)

    def partial(self, units):
        with self._lock:
            self.flight = max(0.0, self.flight + units)
        if self.tty and units > 0:
            self._redraw()

    def work(self):
        """Items' worth done: the items done plus the work in flight, never less
        than shown before, at most the total."""
        with self._lock:
            self._best = max(self._best, min(float(self.total), self.done + self.flight))
            return self._best

    def status(self, final=False):
        """The status text: ``3/141 glyphs (2 %), 4 s, about 180 s left``."""
        import time

        elapsed = time.monotonic() - self._start
        work, total = self.work(), max(self.total, 1)
        done = int(work + 1e-9)
        text = "%d/%d %s (%d %%), %.0f s" % (done, self.total, self.label,
                                             int(100 * work / total + 1e-9), elapsed)
        if 0 < work < self.total:
            text += ", about %.0f s left" % (elapsed / work * (self.total - work))
        elif work >= self.total and not final:
            text += ", finishing"
        return text

    def _tick(self):
        while not self._stop.wait(self.interval):
            self._show()

    def _redraw(self):
        """Draw the line on a terminal unless it was drawn less than ``interval``
        ago: a chunk of glyphs done together, or a 30,000-glyph font, is not a
        redraw per glyph."""
        import time

        if time.monotonic() - self._drawn >= self.interval:
            self._show()

    def _show(self, final=False):
        import time

        line = "%s: %s" % (self.command, self.status(final))
        with self._lock:
            self._drawn = time.monotonic()
            if self.tty:
                self.stream.write("\r\033[K" + line + ("\n" if final else ""))
            else:
                self.stream.write(line + "\n")
            self.stream.flush()
            self._shown = True


def progress_bar(length, label, command="morph"):
    """A :class:`Progress` of ``length`` items on stderr (a context manager with
    ``update(n)``): redrawn on a terminal, a status line every few seconds
    otherwise."""
    return Progress(length, label, command)


def check_nib_tol(tol, nibs, upm):
    """Refuse (InputError, exit 2) a --tol of ``tol`` em that is not below the size of
    every nib region of ``nibs`` (in font units, ``upm`` per em): a stroke or brush is
    then no thicker than the tolerance in some direction of every part the nib adds,
    and trimming drops features thinner than about the tolerance (morph.trim), so each
    stroked glyph comes out empty (a polygon fallback) and a brush is lost within the
    tolerance.  The suggestion is a tenth of the smallest nib, as
    :func:`morph.limits.check_tolerance` suggests for shapes."""
    from ..limits import region_extent

    size = min(region_extent(nib)[0] for nib in nibs)
    if tol * upm >= size:
        raise InputError("--tol %g em (%.3g units) is not below the nib's size (%.3g units, "
                         "%.3g em): the nib's shape would be lost within the tolerance; use "
                         "--tol %.2g em or less" % (tol, tol * upm, size, size / upm,
                                                    size / upm / 10))
