"""The ``morph`` command line: one click group, shared options, thin commands.

Adding a command (for other engineers)::

    @main.command()
    @shape_argument("shape")            # a glyph or an .svg file, loaded with --font
    @common_options                     # --font --tol -o/--output --force --size
    def mycommand(shape, font, tol, output, force, size):
        out = resolve_output(output, "mycommand-%s.png" % shape.slug, force)
        write_image(out, [shape.region], size=size, tol=shape_tolerance(shape, tol))

and name it, with its module, in ``morph.cli.group.COMMAND_MODULES`` (a command's
module is imported when the command runs).

``common_options`` adds ``--font``, ``--tol``, ``-o/--output``, ``--force`` and
``--size``; ``shape_argument`` converts an argument with :func:`morph.parse.load_shape`
into a :class:`morph.parse.Shape`; :func:`shape_tolerance` turns --tol (em for
glyphs, user units for SVG) into the shape's units.  Errors: raise
:class:`morph.errors.ParseError`, ``DegenerateCurveError``, ``LimitError``,
``NibError`` (or a click usage error) for bad input and
:func:`main` prints one line ``morph: error: ...`` and exits 2; ``TopologyError``,
``ToleranceNotMetError`` and anything else are internal failures, one line naming
the command, exit 1.  ``MORPH_DEBUG=1`` shows the traceback of an internal failure
and saves the loaded shapes to ``morph-debug-<command>.json`` in the working folder
(``MORPH_DEBUG=FOLDER``: in that folder); debug files are written nowhere else.
"""

import os

# one BLAS thread, set before numpy loads: the commands multiply small matrices only,
# and OpenBLAS starting its thread pool costs ~40-50 ms of CPU per process; a value
# the user set is kept
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# E402: imported after the BLAS setting; F401: re-exported as morph.cli's names
from .group import (  # noqa: E402,F401 - after the BLAS setting; re-exported
                    BAD_INPUT_ERRORS, COMMAND_MODULES, load_commands, main)
from .options import (  # noqa: E402,F401 - after the BLAS setting; re-exported
                      EXIT_BAD_INPUT, EXIT_INTERNAL, LOADED_SHAPES,
                      InputError, ShapeParam,
                      common_options, font_option, force_option, output_option,
                      resolve_output, resolve_output_dir, shape_argument, shape_tolerance,
                      size_option, tol_option, write_image)

__all__ = ["main", "run", "ShapeParam", "shape_argument", "shape_tolerance", "common_options",
           "font_option", "tol_option", "output_option", "force_option", "size_option",
           "resolve_output", "resolve_output_dir", "write_image", "InputError"]


def __getattr__(name):
    """The command modules (``shapes``, ``apps``, ``fonts`` and the ``variable`` part of
    ``fonts``), imported on first use as their commands are
    (:data:`.group.COMMAND_MODULES`)."""
    if name in set(COMMAND_MODULES.values()) | {"variable"}:
        import importlib

        return importlib.import_module("." + name, __name__)
    raise AttributeError("module %r has no attribute %r" % (__name__, name))


def run():
    """The ``morph`` console script: :func:`main`, then a fast exit.

    Every command has written and closed its files, and joined its worker
    processes, when main returns; the interpreter's teardown (freeing numpy's and
    fontTools' modules: ~20 ms of a 0.2 s ``morph sum O M``) is skipped with
    ``os._exit`` once the standard streams and logging are flushed.  Under coverage
    it exits normally, so that the coverage data is saved.  Other callers (tests,
    ``CliRunner``) use :func:`main`, which returns or raises SystemExit as click
    commands do.
    """
    import sys

    code = main.main(standalone_mode=False)
    if "coverage" in sys.modules:
        sys.exit(code)
    if "logging" in sys.modules:
        sys.modules["logging"].shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing left to tell
            pass
    os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    run()
