"""morph.cli.options: the options every command shares (one --tol convention, the shape
argument and common options)."""

import pytest

from morph import cli
from morph.cli import main


@pytest.mark.parametrize("command", ["outline", "sum", "glyph", "svg", "offset", "cspace",
                                     "brush", "stroke"])
def test_every_command_states_one_tol_convention(runner, command):
    """--tol means one thing everywhere: absolute, em for glyphs and fonts, user units
    for SVG; every --help says so in the same words, and nan/inf/0 are refused."""
    from morph.cli.options import TOL_UNITS

    result = runner.invoke(main, [command, "--help"])
    assert result.exit_code == 0
    assert TOL_UNITS in " ".join(result.output.split())
    for bad in ("nan", "inf", "0"):
        result = runner.invoke(main, [command, "x", "--tol", bad])
        assert result.exit_code == 2 and "--tol" in result.output


def test_shared_options_for_new_commands(runner, tmp_path):
    """Other commands reuse shape_argument + common_options; check the plumbing."""
    import click

    @click.command()
    @cli.shape_argument("shape")
    @cli.common_options
    def probe(shape, font, tol, output, force, size):
        click.echo("%s %s %r %s" % (shape.name, shape.units_per_em,
                                    cli.shape_tolerance(shape, tol), len(shape.region)))

    from morph.parse import cubic_test_font_path
    # --font after the shape still applies: it is eager
    result = runner.invoke(probe, ["g", "--font", cubic_test_font_path(), "--tol", "0.001"])
    assert result.exit_code == 0, result.output
    assert result.output.split() == ["g", "1000", "1.0", "2"]

