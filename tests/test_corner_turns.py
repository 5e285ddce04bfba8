"""The turn of the corner a junction stands for (morph.tips.corner_turns), as the
corner pass (morph.minkowski._tip_tolerances) counts it: a junction the trimming
left off its pieces at a cusp of the convolution (the Relief glyphs with the broad
nib at tol 1.25: spikes turning by nearly pi) takes the turn of the pieces' crossing
next to it, and the glyphs are trimmed once and still within tol of the Clipper
reference; a junction that is a crossing of its pieces keeps its own turn."""

from pathlib import Path

import numpy as np
import pyclipper
import pytest
import shapely
from shapely.geometry import Polygon

from morph import minkowski as mk
from morph import moments as mo
from morph import piece as pc
from morph import polyline as pl
from morph import tips
from morph.nib import ellipse_nib
from morph.parse.ufo import decomposed_paths, load_ufo
from morph.stroke import stroke_many

UFO = Path(__file__).parent / "data" / "relief" / "Relief-SingleLine-subset.ufo"
NAMES = [chr(c) for c in range(65, 91)] + [chr(c) for c in range(97, 123)] + \
    ["zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine"]
NIB = (90.0, 20.0, 30.0)
SCALE = 1e3


def _stroked(monkeypatch, tol):
    """(path sets, results, [(own, returned, pts, corner, piece, conv)] of every
    corner_turns call, trimming rounds, the packing) of the subset stroked at
    ``tol``."""
    font = load_ufo(UFO, lazy=False)
    sets = [decomposed_paths(font, n) for n in NAMES]
    calls, trims, layouts = [], [], []
    turns, trimmed, packing = mk.corner_turns, mk._trimmed, mk.Packing

    def spy(pts, cos_half, corner, piece, conv, tol_):
        got = turns(pts, cos_half, corner, piece, conv, tol_)
        calls.append((np.array(cos_half), got, pts, corner, piece, conv))
        return got

    def count(*a, **k):
        trims.append(1)
        return trimmed(*a, **k)

    def packed(*a, **k):
        layouts.append(packing(*a, **k))
        return layouts[-1]

    monkeypatch.setattr(mk, "corner_turns", spy)
    monkeypatch.setattr(mk, "_trimmed", count)
    monkeypatch.setattr(mk, "Packing", packed)
    out = stroke_many(sets, ellipse_nib(*NIB), tol)
    assert len(layouts) == 1                   # one packed sum: slots are glyphs
    return sets, out, calls, len(trims), layouts[0]


def _off_pieces(pts, corner, piece, conv):
    """Each junction's distance to the nearest of its pieces, on 20001 samples."""
    t = np.linspace(0.0, 1.0, 20001)
    rows = conv.pieces.take(piece).rows()
    d = np.full(len(pts), np.inf)
    for c, p in zip(corner.tolist(), rows):
        d[c] = min(d[c], np.hypot(*(pc.evaluate(p, t) - pts[c]).T).min())
    return d


def _reference(paths, flat):
    """Clipper's union of nib polygon ⊕ path polylines and the nib at each start."""
    nib = pl.flatten_loop(ellipse_nib(*NIB)[0], flat)
    parts = []
    for pieces, closed in paths:
        pts = np.concatenate([pl.flatten(p, flat)[0] for p in pieces])
        parts += pyclipper.MinkowskiSum(pyclipper.scale_to_clipper(nib, SCALE),
                                        pyclipper.scale_to_clipper(pts, SCALE), closed)
        parts.append(pyclipper.scale_to_clipper(nib + pts[0], SCALE))
    clip = pyclipper.Pyclipper()
    clip.AddPaths(parts, pyclipper.PT_SUBJECT, True)
    tree = clip.Execute2(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    polys, stack = [], list(tree.Childs)
    while stack:
        node = stack.pop()
        polys.append(Polygon(np.array(node.Contour) / SCALE,
                             [np.array(h.Contour) / SCALE for h in node.Childs]))
        stack.extend(g for h in node.Childs for g in h.Childs)
    return shapely.unary_union(polys)


def _drawn(loops, flat, shift=(0.0, 0.0)):
    outer = [Polygon(pl.flatten_loop(lp, flat) + shift) for lp in loops if mo.loop_area(lp) > 0]
    holes = [Polygon(pl.flatten_loop(lp, flat) + shift) for lp in loops if mo.loop_area(lp) < 0]
    return shapely.unary_union(outer).difference(shapely.unary_union(holes))


def _within_reference(sets, out, glyphs, tol):
    """The glyphs ``glyphs`` of ``out`` are within tol of the Clipper reference, and
    the check fails on them moved by 2 tol."""
    flat = tol / 20
    bound = tol + 3 * flat          # the reference's flattening, twice, and ours
    for k in glyphs:
        ref = _reference(sets[k], flat)
        assert _drawn(out[k], flat).boundary.hausdorff_distance(ref.boundary) <= bound
        moved = _drawn(out[k], flat, (2 * tol, 0.0))
        assert moved.boundary.hausdorff_distance(ref.boundary) > bound


def test_spikes_off_the_pieces_take_the_crossing_turn(monkeypatch):
    tol = 1.25
    sets, out, calls, trims, layout = _stroked(monkeypatch, tol)
    assert calls and trims == 1              # junctions looked at, no second trim
    spikes = []
    for own, got, pts, corner, piece, conv in calls:
        off = _off_pieces(pts, corner, piece, conv)
        # the spikes: nearly a reversal on the polylines, off their pieces by more
        # than the trimming's Newton tolerance, at a crossing of a few degrees
        moved = got != own
        assert (off[moved] > tips.ON_PIECE * tol).all()
        assert (own[moved] < 0.15).all() and (got[moved] > 0.99).all()
        spikes += pts[moved].tolist()
    assert len(spikes) == 2
    glyphs = sorted(set(layout.slot_of(np.array(spikes)).tolist()))
    assert [NAMES[k] for k in glyphs] == ["d", "q"]
    _within_reference(sets, out, glyphs, tol)


def test_crossings_keep_their_own_turn(monkeypatch):
    """At tol 0.45 the sharp junctions the rule looks at (in six and nine) are
    crossings of their pieces: their turns are kept.  Their pieces' bounds are
    above the corner's budget, their error along the parts there is not
    (morph.tips.local_bounds): the glyphs are trimmed once and within tol of the
    Clipper reference (which fails on them moved by 2 tol)."""
    tol = 0.45
    sets, out, calls, trims, layout = _stroked(monkeypatch, tol)
    assert calls and trims == 1
    junctions = []
    for own, got, pts, corner, piece, conv in calls:
        assert (_off_pieces(pts, corner, piece, conv) <= tips.ON_PIECE * tol).all()
        np.testing.assert_array_equal(got, own)
        want = mk.CONV_SHARE * tol * mk.TIP_MARGIN * got[corner]
        assert (conv.bound[piece] > want).any()
        reach = np.full(len(pts), tol)
        assert (tips.local_bounds(conv, pts, reach, corner, piece) <= want).all()
        junctions += pts.tolist()
    glyphs = sorted(set(layout.slot_of(np.array(junctions)).tolist()))
    assert [NAMES[k] for k in glyphs] == ["six", "nine"]
    _within_reference(sets, out, glyphs, tol)


@pytest.mark.parametrize("shift", [0.0, 3.0])
def test_corner_turns_of_two_crossing_lines(shift):
    """Two line pieces crossing at 20 degrees, and a junction on both (kept) or 0.3
    tol off both (the crossing's turn)."""
    from morph.convolve import ConvPieces

    a = pc.line((-10.0, 0.0), (10.0, 0.0))
    d = np.array([np.cos(np.radians(160.0)), np.sin(np.radians(160.0))])
    b = pc.line(tuple(-10 * d), tuple(10 * d))
    conv = ConvPieces(pc.Pieces.of([a, b]), np.zeros(2), np.array(["qac"] * 2, object),
                      np.zeros(2, int), np.arange(2), np.zeros((2, 4), int))
    tol = 1.0
    pts = np.array([[0.0, shift * 0.1]])
    got = mk.corner_turns(pts, np.array([0.5]), np.array([0, 0]), np.array([0, 1]), conv, tol)
    want = 0.5 if shift == 0.0 else np.cos(np.radians(80.0))
    assert got[0] == pytest.approx(want, rel=1e-9)
