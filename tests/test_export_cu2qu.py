"""TrueType quadratics of a batch of cubics on arrays (morph.export.cu2qu).

Oracles: fontTools' ``curve_to_quadratic(cubic, tol, all_quadratic=True)`` cubic by
cubic (same number of quadratics, same points up to float rounding, the same
cubics failing), on every cubic a brushed and a stroked TrueType font convert and
on thousands of random and degenerate cubics; and an independent distance check of
the written quadratics against their cubics (dense samples at the same parameter,
within tol; a spline displaced by 2 tol fails it).
"""

import numpy as np
import pytest
from fontTools.cu2qu import curve_to_quadratic
from fontTools.cu2qu.errors import Error as Cu2QuError

import morph.export as export
from morph.export import quadratic as quad_mod
from morph.export.cu2qu import MAX_N, cubic_splines, find_splines, spline_quadratics
from morph.errors import ToleranceNotMetError
from morph.export.loops import loops_to_beziers
from morph.budget import QUADRATIC_CUBIC_SHARE
from morph.fonts.brush import brush_font, ellipse_nib
from morph.fonts.stroke import stroke_ufo
from morph.parse import default_font_path
from tests.fontfixtures import hershey_like

#: float rounding allowed between the array arithmetic and fontTools' (the same
#: operations in the same order: equal on this machine; a compiler that fuses
#: multiply-adds in fontTools' build may round differently), relative to the
#: cubic's size.
RTOL = 1e-9


def _reference(cubics, tol):
    """fontTools' splines of every cubic, None where it finds none."""
    out = []
    for c in np.asarray(cubics, float).tolist():
        try:
            out.append(np.array(curve_to_quadratic(c, tol, all_quadratic=True)))
        except Cu2QuError:
            out.append(None)
    return out


def _splines(cubics, tol):
    """find_splines' spline of every cubic in order, None where it finds none."""
    counts, blocks = find_splines(cubics, tol)
    out = [None] * len(counts)
    for index, splines in blocks:
        for i, s in zip(index.tolist(), splines):
            out[i] = s
    assert [0 if s is None else len(s) - 2 for s in out] == counts.tolist()
    return out


def _assert_cu2qu(cubics, tol):
    """The splines equal fontTools' cubic by cubic; the number that fontTools fails."""
    cubics = np.asarray(cubics, float).reshape(-1, 4, 2)
    ref, got = _reference(cubics, tol), _splines(cubics, tol)
    assert [r is None for r in ref] == [g is None for g in got]
    assert [len(r) for r in ref if r is not None] == [len(g) for g in got if g is not None]
    found = [i for i, r in enumerate(ref) if r is not None]
    if found:
        size = np.abs(cubics).max(axis=(1, 2)) + tol
        atol = np.concatenate([np.full((len(ref[i]), 1), RTOL * size[i]) for i in found])
        diff = np.concatenate([got[i] - ref[i] for i in found])
        assert np.all(np.abs(diff) <= atol)
    return len(ref) - len(found)


def _distances(cubics, splines, samples=33):
    """Per cubic the largest distance, at the same parameter, between the cubic and
    its quadratic spline (the spline's n quadratics on equal parameter parts, the
    implied on-curve points at the midpoints), sampled densely."""
    out = []
    for c, s in zip(cubics, splines):
        n = len(s) - 2
        quads = spline_quadratics(s[None])[0]                  # (n, 3, 2)
        u = np.linspace(0.0, 1.0, samples)
        t = ((np.arange(n)[:, None] + u) / n).ravel()
        b = np.stack([(1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t ** 2 * (1 - t), t ** 3], 1)
        on_cubic = b @ c
        w = np.stack([(1 - u) ** 2, 2 * u * (1 - u), u ** 2], 1)
        on_quads = np.einsum("sk,nkd->nsd", w, quads).reshape(-1, 2)
        out.append(np.hypot(*(on_cubic - on_quads).T).max())
    return np.array(out)


def _assert_within(cubics, tol):
    """The converted splines within tol of their cubics (independent sampling), and
    the check can fail: every spline moved by 2 tol is farther than tol."""
    cubics = np.asarray(cubics, float).reshape(-1, 4, 2)
    splines = _splines(cubics, tol)
    assert all(s is not None for s in splines)
    size = np.abs(cubics).max(axis=(1, 2)) + tol
    assert np.all(_distances(cubics, splines) <= tol + RTOL * size)
    moved = [s + [2 * tol, 0.0] for s in splines]
    assert np.all(_distances(cubics, moved) > tol)


@pytest.fixture(scope="module")
def font_cubics(tmp_path_factory):
    """Every (cubics, tol) batch that a brushed (bundled Noto Sans) and a stroked
    (Hershey-like skeleton) TrueType font convert, with each batch's loops and its
    loops_to_quadratics output."""
    batches, calls = [], []
    real_splines, real_loops = quad_mod.cubic_splines, export.loops_to_quadratics

    def spy_splines(cubics, tol):
        batches.append((np.array(cubics, float), tol))
        return real_splines(cubics, tol)

    def spy_loops(loops, tol, *args, **kwargs):
        out = real_loops(loops, tol, *args, **kwargs)
        calls.append((loops, tol, args, kwargs, out))
        return out

    folder = tmp_path_factory.mktemp("cu2qu")
    mp = pytest.MonkeyPatch()
    mp.setattr(quad_mod, "cubic_splines", spy_splines)
    mp.setattr(export, "loops_to_quadratics", spy_loops)
    try:
        brush_font(default_font_path(), folder / "b.ttf", ellipse_nib(80.0, 30.0, 30.0),
                   list("oSg&"), tol=0.5)
        stroke_ufo(hershey_like(), folder / "s.ttf", ellipse_nib(60.0, 20.0, 30.0), tol=0.5)
    finally:
        mp.undo()
    assert len(calls) >= 2 and sum(len(c) for c, _ in batches) > 100
    return batches, calls


def test_font_cubics_equal_fonttools(font_cubics):
    """Every cubic of both fonts: fontTools' n and points."""
    batches, _ = font_cubics
    for cubics, tol in batches:
        assert _assert_cu2qu(cubics, tol) == 0


def test_font_quadratics_within_tol(font_cubics):
    batches, _ = font_cubics
    for cubics, tol in batches:
        _assert_within(cubics, tol)


def _per_cubic(loops, tol, *args, splines=False, **kwargs):
    """loops_to_quadratics cubic by cubic with fontTools (the reference writer)."""
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    return [_per_cubic_list(beziers, tol - cubic_tol, splines)
            for beziers in loops_to_beziers(loops, cubic_tol, *args, **kwargs)]


@pytest.mark.parametrize("splines", [False, True])
def test_font_loops_as_fonttools_cubic_by_cubic(font_cubics, splines):
    """loops_to_quadratics of the fonts' batches, TrueType splines or (3, 2)
    quadratics: the curves of fontTools cubic by cubic, in order, loop by loop."""
    _, calls = font_cubics
    for loops, tol, args, kwargs, _ in calls:
        kwargs = dict(kwargs, splines=splines)
        got, ref = export.loops_to_quadratics(loops, tol, *args, **kwargs), \
            _per_cubic(loops, tol, *args, **kwargs)
        assert [len(loop) for loop in got] == [len(loop) for loop in ref]
        for a, b in zip(sum(got, []), sum(ref, [])):
            assert a.shape == b.shape
            np.testing.assert_allclose(a, b, rtol=0, atol=RTOL * (np.abs(b).max() + 1))


def _families(rng, k):
    """(name, cubics (k, 4, 2)) of random and degenerate cubics."""
    c = rng.standard_normal((k, 4, 2))
    pairs = [(0, 1), (2, 3), (1, 2), (0, 3), (0, 2), (1, 3)]        # coincident points
    same = c.copy()
    for w, (i, j) in enumerate(pairs):
        same[w::len(pairs), j] = same[w::len(pairs), i]
    same[::17] = same[::17, :1]                                     # all four
    a, b = rng.standard_normal((2, k, 1, 2))
    t = np.sort(rng.uniform(-0.5, 1.5, (k, 4)), 1)                  # straight lines,
    t[::2, 0], t[::2, 3] = 0.0, 1.0
    t[1::4] = rng.uniform(-0.5, 1.5, (len(t[1::4]), 4))             # some going back
    shape = np.array([[0, 0], [1, 1], [0, 1], [1, 0]], float)      # cusps and loops
    noise = rng.choice([0.0, 1e-9, 1e-3, 0.3], (k, 1, 1))
    return [("normal", c), ("grid", rng.integers(-12, 13, (k, 4, 2)).astype(float)),
            ("coincident", same), ("lines", a + (b - a) * t[..., None]),
            ("cusps, loops", shape + noise * rng.standard_normal((k, 4, 2)))]


@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e7])
def test_random_and_degenerate_cubics_equal_fonttools(scale):
    """Thousands of random cubics, with coincident control points, straight lines
    (control points beyond the ends too), cusps and loops, on an integer grid
    (parallel tangents and equal points), at scales 1e-6 to 1e7 (cu2qu's absolute
    1e-15 on dot products) and tolerances from 1e-5 of the size (up to MAX_N
    quadratics, and failures) to half of it (one quadratic): fontTools' splines,
    and its failures (no spline of MAX_N quadratics) the same."""
    rng = np.random.default_rng(int(np.log10(scale)) + 10)
    failed = 0
    for name, cubics in _families(rng, 250):
        for tol in (1e-5, 1e-3, 0.05, 0.5):
            failed += _assert_cu2qu(cubics * scale, tol * scale)
    assert failed            # the failures compared too


def test_random_quadratics_within_tol():
    rng = np.random.default_rng(1)
    for _, cubics in _families(rng, 200):
        for tol in (1e-3, 0.05):
            _assert_within(cubics, tol)


def test_no_spline_within_max_n():
    """A cubic whose tolerance no spline of MAX_N quadratics meets: fontTools fails
    and the batch raises ToleranceNotMetError on the first such cubic, whatever its
    place in the batch; the others convert."""
    good = np.array([[0, 0], [1, 2], [3, 2], [4, 0]], float)
    bad = np.array([[0, 0], [3e3, 4e3], [-1e3, 4e3], [2e3, 0]], float)
    tol = 1e-6
    with pytest.raises(Cu2QuError):
        curve_to_quadratic(bad.tolist(), tol)
    counts, _ = find_splines([good, bad, good], tol)
    assert counts[1] == 0 and counts[0] == counts[2] > 0
    for batch in ([bad], [good, bad, good, 2 * bad]):
        with pytest.raises(ToleranceNotMetError, match="cu2qu found no quadratic spline "
                           "within 1e-06") as info:
            cubic_splines(batch, tol)
        assert np.array_equal(info.value.piece, bad)
        with pytest.raises(ToleranceNotMetError, match="within 1e-06"):
            quad_mod._cubics_to_quadratics(batch, tol)
    assert 0 < find_splines([bad], 1e-2)[0][0] <= MAX_N


def test_empty_and_mixed_batches():
    """No cubic: nothing converted; lines and quadratics pass through in place."""
    counts, blocks = cubic_splines(np.zeros((0, 4, 2)), 0.1)
    assert len(counts) == 0 and blocks == []
    assert quad_mod._cubics_to_quadratics([], 0.1) == []
    line, quad = np.array([[0, 0], [1, 0]], float), np.array([[1, 0], [2, 1], [3, 0]], float)
    cubic = np.array([[3, 0], [4, 2], [6, 2], [7, 0]], float)
    for splines in (False, True):
        out, per = quad_mod._with_quadratics([line, cubic, quad, cubic], 1e-3, splines)
        ref = _per_cubic_list([line, cubic, quad, cubic], 1e-3, splines)
        assert len(out) == len(ref) == per.sum() and out[0] is line
        assert all(np.array_equal(a, b) for a, b in zip(out, ref))


def _per_cubic_list(curves, tol, splines):
    """Lines and quadratics kept, each cubic converted by fontTools."""
    out = []
    for b in curves:
        if len(b) < 4:
            out.append(b)
            continue
        s = np.array(curve_to_quadratic(np.asarray(b).tolist(), tol))
        out.extend([s] if splines else list(spline_quadratics(s[None])[0]))
    return out


def test_non_finite_cubics_get_no_spline():
    """A NaN or infinite control point: no spline (cu2qu's recursion would not end),
    the finite cubics beside it converted as alone."""
    good = np.array([[0, 0], [1, 2], [3, 2], [4, 0]], float)
    bad = [good.copy() for _ in range(3)]
    bad[0][1, 0], bad[1][2, 1], bad[2][3, 0] = np.nan, np.inf, -np.inf
    counts, _ = find_splines([good] + bad, 1e-3)
    assert counts[0] == find_splines([good], 1e-3)[0][0] > 0 and not counts[1:].any()
