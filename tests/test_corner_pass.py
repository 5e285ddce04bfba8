"""The corner pass's choice of pairs to refine (morph.minkowski._tip_tolerances, all
sharp junctions against all pieces in array blocks) against the same rule applied
junction by junction, with the junctions' turns from sampled tangents."""

import numpy as np
import pytest

from morph import minkowski as mk
from morph import parse
from morph import piece as pc

TOL = 0.1


def _junctions(loops):
    """(points, cos(phi / 2)) of every junction, tangents from samples 1e-6 apart."""
    pts, cos_half = [], []
    for loop in loops:
        for k, p in enumerate(loop):
            a = pc.evaluate(p, np.array([1.0 - 1e-6, 1.0]))
            b = pc.evaluate(loop[(k + 1) % len(loop)], np.array([0.0, 1e-6]))
            ta, tb = a[1] - a[0], b[1] - b[0]
            c = ta @ tb / (np.linalg.norm(ta) * np.linalg.norm(tb))
            pts.append(a[1])
            cos_half.append(np.sqrt(max(0.0, 0.5 * (1.0 + c))))
    return np.array(pts), np.array(cos_half)


def _one_by_one(out, conv, tol):
    """{row: tolerance} by the rule of _tip_tolerances, one junction at a time: every
    piece near a junction whose bound is above the junction's budget."""
    pts, cos_half = _junctions(out)
    bounds = np.array([c.bound for c in conv])
    boxes = np.array([[*pc.cartesian(c.piece).min(axis=0), *pc.cartesian(c.piece).max(axis=0)]
                      for c in conv])
    reach, finer = mk.TIP_REACH * tol, {}
    for (x, y), c in zip(pts, cos_half):
        want = mk.CONV_SHARE * tol * mk.TIP_MARGIN * max(c, mk.TIP_FLOOR)
        for k in range(len(conv)):
            lo_x, lo_y, hi_x, hi_y = boxes[k]
            if (lo_x - reach <= x <= hi_x + reach and lo_y - reach <= y <= hi_y + reach
                    and bounds[k] > want):
                r = int(conv[k].row)
                finer[r] = min(finer.get(r, np.inf), want)
    return finer


def _check(out, conv, tol, monkeypatch, slot_of=None, piece_slot=None):
    # the rule on the pieces' whole bounds (their bounds along the parts at the
    # corners, morph.tips.local_bounds, are tested in test_minkowski.py)
    monkeypatch.setattr(mk, "local_bounds", lambda conv, pts, reach, corner, piece:
                        conv.bound[piece])
    got = mk._tip_tolerances(out, conv, tol, slot_of, piece_slot)
    want = _one_by_one(out, conv, tol)
    assert want                                   # a case with pairs to refine
    assert sorted(got) == sorted(want)
    for r in want:
        # the turns differ only by the tangents' sampling (1e-6)
        assert got[r] == pytest.approx(want[r], rel=1e-4)


def test_tip_tolerances_match_junction_by_junction(monkeypatch):
    """S + g of the bundled CFF font, its first round at the whole budget."""
    font = parse.cubic_test_font_path()
    ra, rb = parse.glyph_region("S", font).region, parse.glyph_region("g", font).region
    monkeypatch.setattr(mk, "TIP_ROUNDS", 0)      # the first round's corners, unrefined
    monkeypatch.setattr(mk, "FIRST_SHARE", 1.0)
    out, dbg = mk.minkowski_sum_debug(ra, rb, TOL)
    _check(out, dbg["convolution"], TOL, monkeypatch)


def test_tip_tolerances_of_packed_strokes(monkeypatch):
    """Relief skeleton glyphs stroked together with the broad nib (one packed sum),
    its first round at the whole budget: the first call of the corner pass."""
    from pathlib import Path

    from morph.nib import ellipse_nib
    from morph.parse.ufo import decomposed_paths, load_ufo
    from morph.stroke import stroke_many

    ufo = Path(__file__).parent / "data" / "relief" / "Relief-SingleLine-subset.ufo"
    font = load_ufo(ufo, lazy=False)
    calls, real = [], mk._tip_tolerances

    def spy(out, conv, tol, slot_of=None, piece_slot=None):
        calls.append((list(out), conv, tol))
        calls.append((slot_of, piece_slot))
        return real(out, conv, tol, slot_of, piece_slot)

    monkeypatch.setattr(mk, "_tip_tolerances", spy)
    monkeypatch.setattr(mk, "FIRST_SHARE", 1.0)
    stroke_many([decomposed_paths(font, n) for n in "aksxyzAKMWN"],
                ellipse_nib(90.0, 20.0, 30.0), 0.2)
    assert len(set(calls[1][1].tolist())) == 11     # the glyphs' slots
    _check(*calls[0], monkeypatch, *calls[1])
