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
import sys

import click

from .. import __version__
from ..errors import MorphError
from .options import (EXIT_BAD_INPUT, EXIT_INTERNAL, InputError, Shape, ShapeParam,  # noqa: F401 (re-exported)
                      common_options, font_option, force_option, output_option,
                      resolve_output, resolve_output_dir, shape_argument, size_option,
                      tol_option, write_image)

__all__ = ["main", "Shape", "ShapeParam", "shape_argument", "common_options",
           "font_option", "tol_option", "output_option", "force_option", "size_option",
           "resolve_output", "resolve_output_dir", "write_image", "InputError"]

_NO_ARGS_IS_HELP = getattr(click.exceptions, "NoArgsIsHelpError", ())


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


# one module per command family; importing registers the commands on ``main``
from . import shapes, apps, fonts  # noqa: E402,F401

if __name__ == "__main__":  # pragma: no cover
    main()
