"""Fixtures shared by several test files."""

import pytest
from click.testing import CliRunner

from tests import RELIEF_SUBSET


@pytest.fixture(scope="module")
def skeleton():
    """The Relief SingleLine subset read eagerly (morph.parse.ufo.load_ufo)."""
    from morph.parse.ufo import load_ufo

    return load_ufo(RELIEF_SUBSET, lazy=False)


@pytest.fixture
def runner():
    """click's CliRunner, for invoking morph's commands in-process."""
    return CliRunner()
