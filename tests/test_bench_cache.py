"""The bench cache of peer figures (bench/peer_cache.py) misses when its input changes.

The comparison reports take the Clipper references and FontForge's results from the
cache when the same skeletons were measured before; a glyph edited by one point must
be measured again, and the others must not.
"""

import os
import subprocess

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("pyclipper")

from bench import peer_cache  # noqa: E402 - after the optional imports are checked
from bench import stroke as bs  # noqa: E402
from bench.skeletons import write_ufo  # noqa: E402
from morph.parse.ufo import load_ufo  # noqa: E402

GLYPHS = [("a", 0x61, 500.0, [[(100.0, 0.0), (100.0, 400.0), (300.0, 500.0)]]),
          ("b", 0x62, 500.0, [[(50.0, 50.0), (400.0, 50.0)], [(200.0, 0.0), (200.0, 300.0)]])]
SPEC = ("ellipse", 90.0, 20.0, 30.0)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("MORPH_BENCH_CACHE", str(tmp_path / "cache"))
    return tmp_path


def _font(path, glyphs):
    write_ufo(path, "Cache Test", glyphs, 1000.0)
    return load_ufo(path, lazy=False)


def _edited(dy):
    """GLYPHS with the last point of b's second stroke moved up by ``dy``."""
    b = GLYPHS[1]
    strokes = [list(b[3][0]), list(b[3][1][:-1]) + [(200.0, 300.0 + dy)]]
    return [GLYPHS[0], (b[0], b[1], b[2], strokes)]


def test_digest_tells_contents_and_structures_apart():
    a = [np.array([[0.0, 1.0], [2.0, 3.0]])]
    same = [np.array([[0.0, 1.0], [2.0, 3.0]])]
    moved = [np.array([[0.0, 1.0], [2.0, 3.0001]])]
    assert peer_cache.digest(a, 0.5) == peer_cache.digest(same, 0.5)
    assert peer_cache.digest(a, 0.5) != peer_cache.digest(moved, 0.5)
    assert peer_cache.digest(a, 0.5) != peer_cache.digest(a, 0.25)
    assert peer_cache.digest([1, [2, 3]]) != peer_cache.digest([[1, 2], 3])
    assert peer_cache.digest("ab", "c") != peer_cache.digest("a", "bc")


def test_references_hit_and_an_edited_glyph_misses(cache, monkeypatch):
    made = []
    real = bs.stroke_polygon

    def counted(paths, nib, tol):
        made.append(len(paths))
        return real(paths, nib, tol)

    monkeypatch.setattr(bs, "stroke_polygon", counted)
    font = _font(cache / "one.ufo", GLYPHS)
    refs, keys, note = bs.references(font, ["a", "b"], SPEC, 0.05)
    assert len(made) == 2 and note.endswith("(all now)")
    again, keys2, note = bs.references(font, ["a", "b"], SPEC, 0.05)
    assert len(made) == 2 and keys2 == keys and note.endswith("(all from the cache)")
    assert all(again[n].equals_exact(refs[n], 0.0) for n in "ab")
    # one point of b moved by 1 unit: b misses (a new reference, 1 unit taller), a hits
    edited = _font(cache / "two.ufo", _edited(1.0))
    refs3, keys3, note = bs.references(edited, ["a", "b"], SPEC, 0.05)
    assert len(made) == 3 and note.endswith("(1 from the cache, 1 now)")
    assert keys3["a"] == keys["a"] and keys3["b"] != keys["b"]
    assert refs3["b"].bounds[3] == pytest.approx(refs["b"].bounds[3] + 1.0, abs=0.05)
    # another tolerance or nib misses too
    bs.references(font, ["a"], SPEC, 0.04)
    bs.references(font, ["a"], ("ellipse", 90.0, 20.0, 31.0), 0.05)
    assert len(made) == 5


def _has_fontforge():
    return os.path.exists(bs.SYSTEM_PYTHON) and subprocess.run(
        [bs.SYSTEM_PYTHON, "-c", "import fontforge"], capture_output=True).returncode == 0


@pytest.mark.skipif(not _has_fontforge(), reason="FontForge's Python module (Debian's "
                    "python3-fontforge) is not installed")
def test_fontforge_results_hit_and_an_edited_glyph_misses(cache):
    font = _font(cache / "one.ufo", GLYPHS)
    refs, keys, _ = bs.references(font, ["a", "b"], SPEC, 0.05)
    judge = bs._plain_judge(refs, keys)
    rows, why = bs.run_fontforge(font, ["a", "b"], SPEC, [1.0], refs, judge)
    assert not why and rows[0]["measured"].endswith("(all now)")
    again, _ = bs.run_fontforge(font, ["a", "b"], SPEC, [1.0], refs, judge)
    assert again[0]["measured"].endswith("(all from the cache)")
    assert again[0]["errs"] == rows[0]["errs"] and again[0]["ms"] == rows[0]["ms"]
    edited = _font(cache / "two.ufo", _edited(1.0))
    refs2, keys2, _ = bs.references(edited, ["a", "b"], SPEC, 0.05)
    moved, _ = bs.run_fontforge(edited, ["a", "b"], SPEC, [1.0], refs2,
                                bs._plain_judge(refs2, keys2))
    assert moved[0]["measured"].endswith("(all now)")
    # FontForge's outline of b follows the edit (its error against the new reference
    # stays within its accuracy)
    assert moved[0]["errs"][1] <= 1.0 + 0.25
