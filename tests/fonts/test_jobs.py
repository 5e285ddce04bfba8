"""morph.fonts.jobs (the worker pool, the polygon fallback sum), checked against a
Clipper/shapely reference."""

import numpy as np
import pytest

from morph.fonts.brush import ellipse_nib
from morph.fonts.jobs import polygon_sum, run_jobs
from morph.parse import glyph_region
from tests.oracles.reference import hausdorff, polygon_minkowski_sum


@pytest.mark.parametrize("ch", ["o", "g"])
def test_polygon_fallback_against_clipper(ch):
    """The fallback sum is within tol (+ its 1/16 grid) of an independent Clipper sum."""
    pytest.importorskip("shapely")
    import shapely

    region = glyph_region(ch).region
    nib = ellipse_nib(80, 30, 30)
    got = polygon_sum(region, nib, 0.5)
    ref = polygon_minkowski_sum(region, nib, 0.25)
    assert hausdorff([np.vstack([p, p[:1]]) for p in got], ref, 0.5) <= 0.5 + 0.25 + 0.2
    # orientation: outer counter-clockwise, holes clockwise, as many as Clipper's
    signed = [shapely.Polygon(p).area * (1 if shapely.LinearRing(p).is_ccw else -1)
              for p in got]
    n_ref = len(getattr(ref, "geoms", [ref]))
    holes_ref = sum(len(g.interiors) for g in getattr(ref, "geoms", [ref]))
    assert sum(a > 0 for a in signed) == n_ref and sum(a < 0 for a in signed) == holes_ref
    assert sum(signed) == pytest.approx(ref.area, rel=2e-3)


def _square(k):
    return k * k


def test_run_jobs_order_and_progress():
    seen = []
    assert run_jobs(_square, range(7), jobs=2, progress=lambda k, r: seen.append(k)) == \
        [k * k for k in range(7)]
    assert sorted(seen) == list(range(7))
    assert run_jobs(_square, [3], jobs=4) == [9]


@pytest.mark.parametrize("jobs", [1, 2])
def test_run_jobs_streams_without_keeping_results(jobs):
    got = {}
    out = run_jobs(_square, range(5), jobs=jobs, keep=False,
                   progress=lambda k, r: got.__setitem__(k, r))
    assert out == [None] * 5  # nothing kept: memory does not grow with the jobs
    assert got == {k: k * k for k in range(5)}


@pytest.mark.parametrize("n, size, count", [(0, 96, 0), (1, 96, 1), (2, 96, 2), (52, 96, 2),
                                            (96, 96, 2), (193, 96, 3), (584, 96, 7),
                                            (584, 48, 13)])
def test_glyph_chunks_equal_bounded_and_two_for_small_fonts(n, size, count):
    from morph.fonts.brush import glyph_chunks

    work = list(range(n))
    chunks = glyph_chunks(work, size)
    assert len(chunks) == count
    assert [g for c in chunks for g in c] == work
    if chunks:
        sizes = [len(c) for c in chunks]
        assert max(sizes) <= size and max(sizes) - min(sizes) <= 1
