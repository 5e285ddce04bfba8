"""The ``morph`` click group: error lines and exit codes, the memory limit, debug dumps.

Command modules (:mod:`.shapes`, :mod:`.apps`, :mod:`.fonts`) register on
:data:`main`; :mod:`morph.cli` imports them after this module, so no module of the
package imports its parent.
"""

import gc
import os
import sys
import warnings

import click

from .. import __version__
from ..errors import (DegenerateCurveError, LimitError, MorphWarning, NibError, OperandError,
                      ParseError)
from ..limits import memory_budget_bytes
from .options import EXIT_BAD_INPUT, EXIT_INTERNAL, LOADED_SHAPES

_NO_ARGS_IS_HELP = getattr(click.exceptions, "NoArgsIsHelpError", ())
#: MorphErrors that mean bad input (exit 2); other MorphErrors are internal (exit 1)
BAD_INPUT_ERRORS = (ParseError, DegenerateCurveError, LimitError, NibError, OperandError)


#: Command-line advice for a library error or warning of this ``kind``
HINTS = {"stroke": "`morph stroke` sweeps a nib along centre lines"}


def _with_hint(message):
    hint = HINTS.get(getattr(message, "kind", None))
    return str(message) + ("; " + hint if hint else "")


def _error_line(message):
    text = " ".join(_with_hint(message).split())
    click.echo("morph: error: %s" % text, err=True)


def _warning_line(message, category, filename, lineno, file=None, line=None,
                  _show=warnings.showwarning):
    """``warnings.showwarning`` of the command line: a MorphWarning as one line
    ``morph: warning: ...`` on stderr, anything else as Python shows it."""
    if issubclass(category, MorphWarning):
        click.echo("morph: warning: %s" % " ".join(_with_hint(message).split()), err=True)
    else:
        _show(message, category, filename, lineno, file, line)


def _limit_memory():
    """Set the address-space limit to the memory budget (MemoryError, not the OOM
    killer); returns a function restoring the previous limit."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not POSIX
        return lambda: None
    budget = memory_budget_bytes()
    try:
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        new = budget if hard == resource.RLIM_INFINITY else min(budget, hard)
        if soft != resource.RLIM_INFINITY and soft <= new:
            return lambda: None
        resource.setrlimit(resource.RLIMIT_AS, (new, hard))
    except (ValueError, OSError):
        return lambda: None

    def restore():
        try:
            resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
        except (ValueError, OSError):
            pass
    return restore


def _save_debug(command, argv, exc):
    """Write the loaded shapes (loops of homogeneous control points), the arguments
    and the error to morph-debug-<command>.json: in the folder MORPH_DEBUG names,
    else (MORPH_DEBUG=1) in the working folder; its path."""
    import json

    folder = os.environ.get("MORPH_DEBUG", "")
    path = os.path.abspath(os.path.join(folder if os.path.isdir(folder) else "",
                                        "morph-debug-%s.json" % command))
    data = {"argv": argv, "error": "%s: %s" % (type(exc).__name__, exc),
            "shapes": [{"arg": s.source,
                        "info": {"kind": s.kind, "name": s.name, "units_per_em": s.units_per_em,
                                 "advance": s.advance_width, "lsb": s.lsb},
                        "loops": [[p.tolist() for p in loop] for loop in s.region]}
                       for s in LOADED_SHAPES]}
    for attr in ("piece", "achieved"):
        value = getattr(exc, attr, None)
        if value is not None:
            data[attr] = value.tolist() if hasattr(value, "tolist") else repr(value)
    try:
        with open(path, "w") as fh:
            json.dump(data, fh)
    except OSError as err:
        return "nowhere (%s)" % err
    return path


def _reading_error(exc):
    """What a reader of the input failed on ("UFO", "font"), or None: fontTools'
    UFO errors (a broken .glif, a glyph its contents.plist lists but that is missing)
    and TTLibError (a truncated table, read lazily after the font opened) come from
    the input, wherever in a command they surface."""
    module = type(exc).__module__ or ""
    if module.startswith("fontTools.ufoLib"):
        return "UFO"
    if type(exc).__name__ == "TTLibError" and module.startswith("fontTools.ttLib"):
        return "font"
    return None


def _failure_line(exc, command, argv, debug):
    """Print the line of an exception no handler took; its exit status: 2 for a
    reading error of the input (:func:`_reading_error`), 1 (internal) otherwise."""
    what = _reading_error(exc)
    if what and not debug:
        _error_line("cannot read the %s: %s" % (what, exc))
        return EXIT_BAD_INPUT
    where = ""
    if debug:
        import traceback

        traceback.print_exc()
        where = "; inputs saved to %s" % _save_debug(command, argv, exc)
    _error_line("internal error in morph %s: %s: %s%s"
                % (command, type(exc).__name__, exc,
                   where or " (set MORPH_DEBUG=1 for a traceback and the inputs)"))
    return EXIT_INTERNAL


# =========================================================================== group

#: the module of morph.cli defining each command: a command's module is imported when
#: the command runs (``morph stroke`` builds neither the shape commands' options nor
#: their modules) and every one of them when the commands are listed
COMMAND_MODULES = {"outline": "shapes", "sum": "shapes", "glyph": "shapes", "svg": "shapes",
                   "offset": "apps", "cspace": "apps", "brush": "fonts", "stroke": "fonts"}


def load_commands(names=None):
    """Import the modules defining the commands ``names`` (default: all of
    :data:`COMMAND_MODULES`), which register them on :data:`main`."""
    import importlib

    for name in COMMAND_MODULES if names is None else names:
        if name in COMMAND_MODULES and name not in main.commands:
            importlib.import_module("morph.cli." + COMMAND_MODULES[name])


class MorphGroup(click.Group):
    """click Group whose ``main`` turns every failure into one stderr line (and a
    MorphWarning into one ``morph: warning:`` line).

    Exit status: 0 success; 2 bad input or usage (ParseError, DegenerateCurveError,
    LimitError, NibError, click usage errors, unwritable output); 1 internal failure
    (TopologyError, ToleranceNotMetError, any other exception, memory budget
    exceeded), naming the command; with MORPH_DEBUG=1 the traceback and the inputs
    saved as JSON.
    """

    def get_command(self, ctx, cmd_name):
        load_commands([cmd_name])
        return super().get_command(ctx, cmd_name)

    def list_commands(self, ctx):
        load_commands()
        return super().list_commands(ctx)

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True,
             **extra):
        debug = os.environ.get("MORPH_DEBUG", "") not in ("", "0")
        code = 0
        argv = list(sys.argv[1:] if args is None else args)
        command = next((a for a in argv if not a.startswith("-")), "morph")
        del LOADED_SHAPES[:]
        restore = _limit_memory()
        # what the process holds as the command starts (its imported modules: long
        # lived) is left out of the collector's full passes over the command's objects
        gc.freeze()
        filters, show = warnings.filters[:], warnings.showwarning
        if not debug:  # numpy's RuntimeWarnings would add lines before the error line
            warnings.simplefilter("ignore", RuntimeWarning)
        warnings.simplefilter("default", MorphWarning)  # once per message
        warnings.showwarning = _warning_line
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
        except BAD_INPUT_ERRORS as exc:
            _error_line(exc)
            code = EXIT_BAD_INPUT
        except MemoryError:
            _error_line("morph %s ran out of its memory budget (%.1f GB, MORPH_MEMORY_LIMIT): "
                        "use a coarser --tol (or a smaller --size)"
                        % (command, memory_budget_bytes() / 2 ** 30))
            code = EXIT_INTERNAL
        except Exception as exc:  # internal failure (MorphError or not): one line
            code = _failure_line(exc, command, argv, debug)
        finally:
            gc.unfreeze()
            restore()
            warnings.filters[:], warnings.showwarning = filters, show
        if standalone_mode:
            sys.exit(code)
        return code


@click.group(cls=MorphGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="morph",
                      message="%(prog)s %(version)s")
def main():
    """Minkowski sums of curved planar shapes (glyphs, SVG paths) as exact curves.

    Shapes are glyphs of a font (a single character such as g, or a glyph name
    such as ampersand) or SVG files (.svg, .svgz, or any file holding an SVG
    document).  Glyphs are read in font units and SVG in user units, both with the
    y axis up.

    \b
    Examples:
      morph outline g -o g.png
      morph outline B --font MyFont.otf -o B.svg
      morph outline drawing.svg --size 800
    """

