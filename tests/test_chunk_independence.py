"""A glyph's outline does not depend on the glyphs computed in its chunk.

The font commands stroke (and brush) glyphs in chunks: one packed sum, one batch of
curve conversions (morph.fonts.jobs.glyph_chunks).  A glyph stroked alone and the
same glyph at several places of chunks of other glyphs must come out alike: the
same loops of the same pieces (every decision of the sum made on the glyph's own
data), their control points equal up to the rounding of the packed coordinates
(the glyph is moved by a whole number of grid units into its cell and back), and
the same integer contours as the font writes them.  The glyphs are those whose
outline did depend on the chunk: a different grid phase, a different pairing of
touching convolution ends, Newton placing a junction of coincident pieces anywhere
along them (Relief 'I', 'j', 'seven', 'b', 'three')."""

from pathlib import Path

import numpy as np
import pytest

from morph import piece as pc
from morph.fonts.brush import ellipse_nib
from morph.fonts.tables import contours_from_regions
from morph.minkowski import minkowski_sums
from morph.parse.ufo import decomposed_paths, load_ufo
from morph.stroke import stroke_many

RELIEF = Path(__file__).parent / "data" / "relief" / "Relief-SingleLine-subset.ufo"
NIB, TOL = ellipse_nib(90, 20, 30), 0.5
#: (glyph, a chunk holding it) pairs whose glyph's outline came out other than
#: alone, first (I), last (j, seven), in the middle (b), twice (three)
CASES = [("I", "I A o m eight g"), ("j", "x zero A M k comma g j"),
         ("seven", "W A g k o m eight seven"), ("b", "k g eight e b W M x m zero"),
         ("three", "three A three")]
#: the control points of a glyph summed alone and moved into a cell of a packed sum
#: and back: equal up to the rounding of coordinates a few thousand units from the
#: origin (ulp 1e-12), through the convolution's arithmetic
ROUNDING = 1e-8


@pytest.fixture(scope="module")
def relief():
    font = load_ufo(RELIEF, lazy=False)
    return {n: decomposed_paths(font, n) for _, chunk in CASES for n in chunk.split()}


def _shape(region):
    return [[np.shape(p) for p in loop] for loop in region]


def _moved_by(alone, got):
    """The largest distance between matching control points of two regions of one shape."""
    return max((np.abs(pc.cartesian(a) - pc.cartesian(b)).max()
                for la, lb in zip(alone, got) for a, b in zip(la, lb)), default=0.0)


def _contours(regions):
    """The regions' integer cubic contours, converted in one batch as a chunk is."""
    return [[[np.asarray(seg).tolist() for seg in contour] for contour in outline]
            for outline in contours_from_regions(regions, 0.5 * TOL, False, reverse=False)]


@pytest.mark.parametrize("target, chunk", CASES)
def test_a_stroked_glyph_is_the_same_alone_and_in_a_chunk(relief, target, chunk):
    alone = stroke_many([relief[target]], NIB, TOL)[0]
    chunk = chunk.split()
    regions = stroke_many([relief[n] for n in chunk], NIB, TOL)
    contours = _contours(regions + [alone])
    for k in [k for k, n in enumerate(chunk) if n == target]:
        assert _shape(regions[k]) == _shape(alone), k
        assert _moved_by(alone, regions[k]) <= ROUNDING, k
        assert contours[k] == contours[-1], k


def test_the_check_sees_a_glyph_moved_by_twice_tol(relief):
    """The comparison fails for an outline moved by 2 tol."""
    alone = stroke_many([relief["I"]], NIB, TOL)[0]
    moved = [[pc.translate(p, (2.0 * TOL, 0.0)) for p in loop] for loop in alone]
    assert _shape(moved) == _shape(alone)
    assert _moved_by(alone, moved) > ROUNDING
    assert _contours([moved]) != _contours([alone])


def test_a_brushed_glyph_is_the_same_alone_and_in_a_batch():
    """Filled glyphs of the bundled font with a round nib (morph brush's sums)."""
    from morph import parse

    font = parse.cubic_test_font_path()
    regions = {c: parse.glyph_region(c, font).region for c in "aQ&gS"}
    nib, tol = ellipse_nib(40, 40, 0), 0.5
    alone = {c: minkowski_sums([regions[c]], nib, tol)[0] for c in "aQ"}
    for batch in ["aQ&gS", "S&Qga", "QgSa"]:
        sums = minkowski_sums([regions[c] for c in batch], nib, tol)
        for c in "aQ":
            got = sums[batch.index(c)]
            assert _shape(got) == _shape(alone[c]), batch
            assert _moved_by(alone[c], got) <= ROUNDING, batch


def test_the_first_round_gives_the_whole_budget_only_to_the_rows_that_fail(monkeypatch):
    """A pair that cannot be subdivided to FIRST_SHARE of the budget gets the whole
    budget; the other rows (other glyphs of the packed sum) keep their share."""
    from morph import minkowski as mk
    from morph.errors import ToleranceNotMetError

    tol, n = 0.5, 6
    budget = mk.CONV_SHARE * tol
    monkeypatch.setattr(mk, "crossing_rows", lambda pair, tol: np.ones(n, bool))

    def convolution(a, b, row_tol, **kw):
        bad = np.flatnonzero(row_tol[[1, 4]] < budget)
        if len(bad):
            raise ToleranceNotMetError("not met", rows=np.array([1, 4])[bad[:1]])
        return "pieces"

    monkeypatch.setattr(mk, "convolution", convolution)
    conv, row_tol = mk._first_round(None, None, tol, "qac", None)
    assert conv == "pieces"
    assert row_tol.tolist() == [budget if k in (1, 4) else mk.FIRST_SHARE * budget
                                for k in range(n)]


def test_a_pair_that_cannot_refine_ends_the_corner_pass_of_its_slot_only():
    """Its slot's rows keep their tolerances (its corners their error, as summed
    alone); the other slots' rows are approximated again."""
    from morph import minkowski as mk
    from morph.errors import ToleranceNotMetError

    row_tol = np.full(6, 0.25)
    row_slot = np.array([0, 0, 1, 1, 2, 2])

    def convolve(rows, tols):
        if 3 in rows.tolist():
            raise ToleranceNotMetError("not met", rows=np.array([3]))
        return rows.tolist()

    got, rows, stopped = mk._refined_rows(convolve, np.array([0, 2, 3, 5]), [0.1] * 4,
                                          row_tol, row_slot, np.zeros(0, np.int64))
    assert got == [0, 5] and rows.tolist() == [0, 5] and stopped.tolist() == [1]
    assert row_tol.tolist() == [0.1, 0.25, 0.25, 0.25, 0.25, 0.1]
