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


@pytest.mark.parametrize("n, size, count", [(0, 96, 0), (1, 96, 1), (2, 96, 1), (52, 96, 1),
                                            (95, 96, 1), (96, 96, 2), (150, 96, 2),
                                            (193, 96, 3), (584, 96, 7), (584, 48, 13)])
def test_glyph_chunks_equal_bounded_and_two_for_small_fonts(n, size, count):
    from morph.fonts.brush import glyph_chunks

    work = list(range(n))
    chunks = glyph_chunks(work, size)
    assert len(chunks) == count
    assert [g for c in chunks for g in c] == work
    if chunks:
        sizes = [len(c) for c in chunks]
        assert max(sizes) <= size and max(sizes) - min(sizes) <= 1


@pytest.mark.parametrize("seed", range(4))
def test_glyph_chunks_by_weight_equal_bounded_in_order(seed):
    """Weighted chunks: the glyphs in order, as many chunks as the weight needs at
    ``size`` each (two from twice MIN_SPLIT in weight on), each chunk's weight within
    one glyph's of an equal share; a glyph of weight 0 costs nothing."""
    from morph.fonts.jobs import MIN_SPLIT, glyph_chunks

    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 900))
    weights = rng.choice([0.0, 1 / 12, 2 / 12, 9 / 12, 1.0, 3.0], n)
    work = list(range(n))
    for size in (8, 96, 1000):
        chunks = glyph_chunks(work, size, weights)
        assert [g for c in chunks for g in c] == work
        total = weights.sum()
        two = 2 if total >= 2 * MIN_SPLIT else 1
        assert len(chunks) == min(n, max(1, int(np.ceil(total / size)), two))
        share, heaviest = total / len(chunks), weights.max()
        for c in chunks:
            assert c and abs(weights[c].sum() - share) <= heaviest + 1e-9


def test_glyph_chunks_by_weight_light_glyphs_share_a_chunk(monkeypatch):
    """321 light glyphs (Relief's: 534 contours, 45 glyphs' worth at a twelfth of a
    glyph a contour) are one chunk, where by their number they would be four; two
    when each half weighs MIN_SPLIT; 3000 glyphs of weight 1 are chunked as by their
    number; weights must be one per glyph, finite, >= 0."""
    from morph.fonts.jobs import glyph_chunks

    light = np.repeat([1 / 12, 2 / 12, 3 / 12], [130, 169, 22])
    work = list(range(321))
    assert [len(c) for c in glyph_chunks(work, weights=light)] == [321]
    assert [len(c) for c in glyph_chunks(work)] == [80, 80, 81, 80]
    assert [len(c) for c in glyph_chunks(work, weights=light * 3)] == [198, 123]
    # halves of 534 contours: 130 of one and 68 of two (266), the nearer edge (tie: first)
    monkeypatch.setattr("morph.fonts.jobs.MIN_SPLIT", 1)
    assert [len(c) for c in glyph_chunks(work, weights=light)] == [198, 123]
    assert [len(c) for c in glyph_chunks(list(range(3000)), weights=np.ones(3000))] == \
        [len(c) for c in glyph_chunks(list(range(3000)))]
    assert glyph_chunks([], weights=[]) == []
    assert glyph_chunks([1, 2, 3], weights=[0.0, 0.0, 0.0]) == [[1, 2, 3]]   # none lost
    for bad in ([1.0], [1.0, -1.0, 1.0], [1.0, np.nan]):
        with pytest.raises(ValueError, match="weights"):
            glyph_chunks([1, 2], weights=bad)


# ----------------------------------------------------------------- progress within a job

def _slow_chunk(chunk):
    """A fake slow job: each glyph takes 20 ms and reports itself done."""
    import time

    from morph.fonts.jobs import glyph_progress

    out = []
    for x in chunk:
        time.sleep(0.02)
        glyph_progress(1.0)
        out.append(x)
    return out


def _counts(text):
    import re

    return [int(m) for m in re.findall(r"^x: (\d+)/", text, re.M)]


@pytest.mark.parametrize("jobs", [1, 2])
def test_progress_moves_within_a_chunk(jobs, monkeypatch):
    """Status lines of a slow job show counts inside its chunk (the job's own
    reports), never going back, ending at the total; each chunk's reports are taken
    back as its glyphs arrive, so nothing is counted twice."""
    import io

    from morph.cli.options import Progress
    from morph.fonts.jobs import glyph_chunks, run_glyph_jobs

    monkeypatch.setattr("morph.fonts.jobs.MIN_SPLIT", 1)   # two chunks: workers for jobs=2
    work = list(range(40))
    edges = {0, 40} | {sum(map(len, glyph_chunks(work)[:k])) for k in range(3)}
    out = io.StringIO()
    flight, arrived = [], []
    with Progress(len(work), "glyphs", "x", stream=out, tty=False, interval=0.003) as bar:
        def partial(units):
            flight.append(units)
            bar.partial(units)

        def each(result):   # a chunk's glyphs counted at once: only reports fall inside
            arrived.append(result)
            if len(arrived) in edges:
                bar.update(len(arrived) - bar.done)
        got = run_glyph_jobs(_slow_chunk, work, jobs=jobs, each=each, in_flight=partial)
    assert got == work
    counts = _counts(out.getvalue())
    assert counts == sorted(counts) and counts[-1] == 40
    assert set(counts) - edges, "no count inside a chunk: %s" % sorted(set(counts))
    reported = sum(u for u in flight if u > 0)
    if jobs == 1:   # reports are calls: every one arrives before its chunk's glyphs
        assert reported == pytest.approx(40)
    else:           # a worker's report may come after its chunk's result (two pipes):
        assert 0 < reported <= 40 + 1e-9   # dropped then, never counted twice
    assert sum(flight) == pytest.approx(0.0)   # all taken back: 40 done, none in flight
    assert bar.flight == pytest.approx(0.0)


@pytest.mark.parametrize("jobs", [1, 2])
def test_stroke_jobs_report_sums_and_conversion(skeleton, tmp_path, jobs, monkeypatch):
    """The stroke's chunk jobs report their work as it is done: SUM_SHARE per glyph
    once the strokes are done, the rest as the batched conversion's searches end;
    in all each glyph's worth once, several reports per chunk, all taken back."""
    from morph.fonts import jobs as jobs_module
    from morph.fonts.jobs import SUM_SHARE
    from morph.fonts.stroke import CONTOURS_PER_GLYPH, stroke_ufo

    # two chunks (workers for jobs=2): a chunk splits from two contours' weight on
    monkeypatch.setattr("morph.fonts.jobs.MIN_SPLIT", 1 / CONTOURS_PER_GLYPH)
    chunks = []
    split = jobs_module.glyph_chunks
    monkeypatch.setattr(jobs_module, "glyph_chunks",
                        lambda *a, **k: _spied(chunks, split(*a, **k), k))
    names = ["a", "b", "c", "o", "s", "e", "n", "h"]
    flight = []
    stats = stroke_ufo(skeleton, tmp_path / "s.ufo", ellipse_nib(60, 20, 30), glyphs=names,
                       tol=1.0, jobs=jobs, in_flight=flight.append)
    n = stats["glyphs"]
    assert len(chunks) == 2 and sum(map(len, chunks)) == n   # every glyph has contours
    positive = [u for u in flight if u > 0]
    assert sum(positive) == pytest.approx(n)
    assert len(positive) > 2 * len(chunks)      # more than one report per chunk
    assert any(u == pytest.approx(SUM_SHARE * len(c)) for u in positive for c in chunks)
    assert sum(flight) == pytest.approx(0.0)


def test_progress_count_never_goes_back_and_says_finishing():
    import io

    from morph.cli.options import Progress

    with Progress(10, "glyphs", "x", stream=io.StringIO(), tty=False, interval=60) as bar:
        bar.partial(2.5)
        assert bar.status().startswith("2/10 glyphs (25 %)")
        bar.partial(-2.5)               # taken back before its glyphs are added
        assert bar.status().startswith("2/10 glyphs (25 %)")
        bar.update(3)
        assert bar.status().startswith("3/10 glyphs (30 %)")
        bar.update(7)
        assert bar.status().endswith("finishing")
        assert not bar.status(final=True).endswith("finishing")


def _spied(seen, chunks, kwargs):
    """``chunks`` (of :func:`morph.fonts.jobs.glyph_chunks`), added to ``seen`` when
    weighted: the stroke's chunks of the glyphs with contours to stroke."""
    if kwargs.get("weights") is not None:
        seen.extend(chunks)
    return chunks
