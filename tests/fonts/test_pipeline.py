"""The font writers' one pipeline (morph.fonts.jobs): one job runner, one fallback
ladder that moves on a MorphError only, so that a programming error surfaces as an
internal error (exit 1, traceback under MORPH_DEBUG) instead of a fallback glyph."""

import pytest

from morph.errors import MorphError, TopologyError
from morph.fonts.jobs import fallback_ladder, glyph_chunks, run_glyph_jobs


def _boom(exc):
    def f():
        raise exc
    return f


def test_fallback_ladder_moves_on_morph_errors_only():
    assert fallback_ladder([("a", lambda: 1)]) == ("a", 1, None)
    kind, value, error = fallback_ladder([("a", _boom(TopologyError("open chain"))),
                                          ("b", lambda: 2)])
    assert (kind, value) == ("b", 2) and error == "TopologyError: open chain"
    kind, value, error = fallback_ladder([("a", _boom(MorphError("x"))),
                                          ("b", _boom(MorphError("y")))])
    assert kind is None and error == "MorphError: x; b fallback: MorphError: y"
    with pytest.raises(ZeroDivisionError):
        fallback_ladder([("a", _boom(ZeroDivisionError("bug"))), ("b", lambda: 2)])


def _double_all(chunk):
    return [2 * x for x in chunk]


@pytest.mark.parametrize("jobs", [1, 2])
def test_run_glyph_jobs_in_order_each_result_once(jobs):
    seen = []
    assert run_glyph_jobs(_double_all, list(range(250)), jobs=jobs, each=seen.append) == \
        [2 * x for x in range(250)]
    assert sorted(seen) == [2 * x for x in range(250)]
    assert run_glyph_jobs(_double_all, list(range(5)), jobs=jobs, keep=False) is None
    assert [len(c) for c in glyph_chunks(list(range(250)))] == [83, 84, 83]


def test_a_programming_error_is_not_a_fallback(runner, tmp_path, monkeypatch):
    """brush: a TopologyError of the sum falls back (named, exit 1, the font written);
    a bug (here a ZeroDivisionError in the sum) is an internal error naming it, with
    the traceback under MORPH_DEBUG."""
    from morph import minkowski
    from morph.cli import main

    def fail_with(exc):
        def sums(*args, **kwargs):
            raise exc
        monkeypatch.setattr(minkowski, "minkowski_sums", sums)
        monkeypatch.setattr(minkowski, "minkowski_sum", sums)

    fail_with(TopologyError("open convolution chain"))
    res = runner.invoke(main, ["brush", "-o", str(tmp_path / "a.ttf"), "--glyphs", "o",
                               "--jobs", "1"])
    assert res.exit_code == 1 and (tmp_path / "a.ttf").is_file()
    assert "fell back" in res.stderr and "polygon" in res.stderr
    fail_with(ZeroDivisionError("a bug"))
    monkeypatch.setenv("MORPH_DEBUG", "1")
    monkeypatch.chdir(tmp_path)
    res = runner.invoke(main, ["brush", "-o", str(tmp_path / "b.ttf"), "--glyphs", "o",
                               "--jobs", "1"])
    assert res.exit_code == 1 and not (tmp_path / "b.ttf").exists()
    assert "internal error in morph brush: ZeroDivisionError: a bug" in res.stderr
    assert "Traceback" in res.stderr
