"""Fixtures shared by several test folders."""

import pytest

from tests import RELIEF_SUBSET


@pytest.fixture(scope="module")
def skeleton():
    """The Relief SingleLine subset read eagerly (morph.parse.ufo.load_ufo)."""
    from morph.parse.ufo import load_ufo

    return load_ufo(RELIEF_SUBSET, lazy=False)
