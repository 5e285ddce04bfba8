"""Fixtures shared by the font tests."""

import pytest

from morph.fonts import stream


@pytest.fixture
def saved(tmp_path):
    """``save(font, name)``: the ufoLib2 font saved as ``name.ufo`` in the test's
    folder; its path."""
    def save(font, name="s"):
        path = tmp_path / ("%s.ufo" % name)
        font.save(path)
        return path
    return save


@pytest.fixture
def ufo2ft_calls(monkeypatch):
    """The fonts ufo2ft compiles (their types' names), as they are compiled."""
    calls = []
    real = stream.compile_stored

    def spy(font, *args, **kwargs):
        calls.append(type(font).__name__)
        return real(font, *args, **kwargs)

    monkeypatch.setattr(stream, "compile_stored", spy)
    return calls
