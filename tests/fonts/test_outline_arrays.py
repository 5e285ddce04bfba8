"""Integer outlines as arrays (morph.fonts.tables.integer_outlines, Outline) and their
compilation without pens (morph.fonts.stream.compile_outlines).

The references are the per-contour code they replace, kept as it was:
``clean_contour`` contour by contour for the rounding and cleaning, and fontTools'
pens (``T2CharStringPen`` unspecialized + ``BoundsPen``; ``ReverseContourPen`` +
``TTGlyphPen`` + ``Glyph.compile``) for the bytes and boxes.  The inputs are random
closed chains built to hit every clean-up rule (joins within float noise, zero-length
segments, retracted handles, collinear runs through and away from the start, spikes,
splines whose rounded points repeat), and real strokes of random polylines.
"""

import numpy as np
import pytest

from morph import bernstein as bz
from morph.fonts.stream import _compile_with_pens, compile_outline, compile_outlines
from morph.fonts.tables import clean_contour, integer_outlines
from morph.outline import Outline


def _chain(rng, quadratic, splines):
    """A closed chain of segments (float arrays) with defects on purpose."""
    n = int(rng.integers(2, 12))
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    scale = 10 ** rng.uniform(0.3, 2.5)
    joins = np.column_stack([np.cos(ang), np.sin(ang)]) * scale + rng.uniform(-50, 50, 2)
    if rng.random() < 0.3:
        joins = np.round(joins) + 0.5           # half integers: rounding from two sides
    segs = []
    for k in range(n):
        a, b = joins[k], joins[(k + 1) % n]
        kind = rng.choice(["line", "line", "collinear", "curve", "zero", "retracted",
                           "spike"])
        if kind == "collinear":                 # a line cut in two or three
            cuts = np.sort(rng.uniform(0, 1, int(rng.integers(1, 3))))
            pts = [a] + [a + (b - a) * t for t in np.round(cuts * 8) / 8] + [b]
            segs += [np.array([p, q]) for p, q in zip(pts, pts[1:]) if not np.array_equal(p, q)]
            continue
        if kind == "zero":
            segs.append(np.array([a, a + rng.normal(0, 0.1, 2)]))
        elif kind == "spike":                   # a short there-and-back
            tip = a + rng.normal(0, 1.5, 2)
            segs += [np.array([a, tip]), np.array([tip, a])]
        if kind == "line" or kind in ("zero", "spike"):
            segs.append(np.array([a, b]))
            continue
        m = (3 if rng.random() < 0.5 else int(rng.integers(4, 8))) if quadratic else 4
        if not splines and quadratic:
            m = 3
        inner = [a + (b - a) * t + rng.normal(0, scale / 5, 2)
                 for t in np.linspace(0, 1, m)[1:-1]]
        seg = np.array([a] + inner + [b])
        if kind == "retracted":
            seg[1] = seg[0] + rng.normal(0, 0.2, 2)
            if rng.random() < 0.5:
                seg[-2] = seg[-1] + rng.normal(0, 0.2, 2)
        segs.append(seg)
    for s in segs:
        s[0] += rng.choice([-1e-12, 0.0, 1e-12], 2)  # joins within float noise
    if not quadratic:
        segs = [bz.to_degree(s, 3) if len(s) == 3 else s for s in segs]
    return segs


def _glyphs(rng, quadratic, splines, n=12):
    loops, counts, offsets = [], [], []
    for _ in range(n):
        k = int(rng.integers(0, 4))
        counts.append(k)
        offsets.append((float(rng.integers(-40, 40)), 0.0))
        loops += [_chain(rng, quadratic, splines) for _ in range(k)]
    return loops, counts, offsets


def _reference(loops, counts, offsets, splines):
    out, it = [], iter(loops)
    for k, off in zip(counts, offsets):
        contours = []
        for _ in range(k):
            c = clean_contour([s + np.asarray(off) for s in next(it)], splines=splines)
            if c:
                contours.append(c)
        out.append(contours)
    return out


def _same_contours(a, b):
    return len(a) == len(b) and all(
        len(p) == len(q) and all(np.array_equal(s, t) for s, t in zip(p, q))
        for p, q in zip(a, b))


@pytest.mark.parametrize("seed", range(30))
@pytest.mark.parametrize("flavor", ["cff", "ttf", "ttf-splines"])
def test_integer_outlines_clean_as_clean_contour(seed, flavor):
    rng = np.random.default_rng(seed)
    quadratic, splines = flavor != "cff", flavor == "ttf-splines"
    loops, counts, offsets = _glyphs(rng, quadratic, splines)
    got = integer_outlines(loops, counts, offsets, quadratic, splines)
    want = _reference(loops, counts, offsets, splines)
    assert len(got) == len(want)
    for g, w in zip(got, want):
        assert isinstance(g, Outline)
        assert _same_contours(list(g), w)
        assert g.point_count() == sum(len(q) - 1 for c in w for q in c)
        assert not any((q == q[0]).all() for c in w for q in c)  # no zero length
        assert not any(len(q) == 2 and (q[0] == q[1]).all() for c in w for q in c)


def test_a_curve_rounding_to_a_point_is_dropped():
    """A cubic whose ends round to one point but whose handles do not: the chord
    left by moving its handles would have zero length, so it goes."""
    segs = [np.array([[0.2, 0.1], [0.1, 0.2], [1.2, 0.1], [0.1, 0.3]]),
            np.array([[0.1, 0.3], [50.0, 0.3]]), np.array([[50.0, 0.3], [50.0, 40.0]]),
            np.array([[50.0, 40.0], [0.2, 0.1]])]
    want = clean_contour(segs)
    assert len(want) == 3 and all(len(q) == 2 for q in want)
    assert _same_contours(list(integer_outlines([segs], [1], [(0.0, 0.0)], False, False)[0]),
                          [want])


def test_integer_outlines_comparison_can_fail():
    """The reference comparison sees a point moved by one unit."""
    rng = np.random.default_rng(3)
    loops, counts, offsets = _glyphs(rng, False, False)
    got = integer_outlines(loops, counts, offsets, False, False)
    g = next(o for o in got if len(o))
    want = [[s.copy() for s in c] for c in g]
    want[0][0][-1] += 1.0
    assert not _same_contours(list(g), want)


def _outlines(rng, quadratic, splines):
    loops, counts, offsets = _glyphs(rng, quadratic, splines, n=10)
    return [list(o) for o in integer_outlines(loops, counts, offsets, quadratic, splines)]


@pytest.mark.parametrize("seed", range(20))
@pytest.mark.parametrize("flavor", ["cff", "glyf"])
def test_compiled_outlines_are_the_pens_bytes(seed, flavor):
    """Bytes and boxes equal to fontTools' pens, glyph by glyph, in one batch
    (glyphs without contours among them)."""
    rng = np.random.default_rng(100 + seed)
    glyphs = _outlines(rng, flavor == "glyf", flavor == "glyf")
    got = compile_outlines(glyphs, flavor)
    for contours, (data, box) in zip(glyphs, got):
        want_data, want_box = _compile_with_pens(contours, flavor)
        assert data == want_data
        assert box == want_box


def test_compiled_charstring_is_the_specialized_path(tmp_path):
    """The unspecialized charstring draws the same path as the specialized one
    ufo2ft's pen makes (what the subroutinizer rewrites from)."""
    from fontTools.misc.psCharStrings import T2CharString
    from fontTools.pens.recordingPen import RecordingPen

    from morph.fonts.cff_encoding import _NO_WIDTHS

    rng = np.random.default_rng(7)
    for contours in _outlines(rng, False, False):
        paths = []
        for data in (compile_outline(contours, "cff")[0],
                     _compile_with_pens(contours, "cff", optimize=True)[0]):
            rec = RecordingPen()
            T2CharString(bytecode=data, private=_NO_WIDTHS, globalSubrs=[]).draw(rec)
            paths.append(rec.value)
        assert paths[0] == paths[1]


def test_compiled_glyf_long_runs_and_wide_deltas():
    """Flag runs longer than 256 points, deltas of one and two bytes, and a glyph
    whose coordinates do not fit 16 bits (drawn by the pens, which refuse it)."""
    n = 700
    x = np.arange(n, dtype=float) * 3.0
    pts = np.column_stack([x, np.zeros(n)])
    square = np.array([[0, 0], [2000, 0], [2000, -300], [0, -300]], float)
    contour = [np.array([pts[k], pts[k + 1]]) for k in range(n - 1)]
    contour += [np.array([pts[-1], [x[-1], 500.0]]), np.array([[x[-1], 500.0], pts[0]])]
    box = [np.array([square[k], square[(k + 1) % 4]]) for k in range(4)]
    glyphs = [[contour], [box], [], [contour, box]]
    for flavor in ("cff", "glyf"):
        for contours, (data, bounds) in zip(glyphs, compile_outlines(glyphs, flavor)):
            assert (data, bounds) == _compile_with_pens(contours, flavor)
    huge = [[s * 20.0 for s in box]]
    with pytest.raises(Exception):
        _compile_with_pens(huge, "glyf")
    with pytest.raises(Exception):
        compile_outlines([[box], huge], "glyf")
