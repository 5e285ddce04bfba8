"""The first try of a segment after an accepted one (morph/export/greedy.py,
``next_width``), against a scalar oracle written from its documentation: the width
of the last segment scaled by (AIM tol / bound)^(1 / NEXT_POWER), within NEXT_STEP
times it, then cut at the chain's end (to the end when less than REACH_END of the
width would be left).  The machine is driven by a made-up fitter (bound c width^5,
twenty times more past a join of pieces, where the machine ends segments well below
tol; certified); a rule that keeps the last width fails the oracle, and every
segment the machine accepts is a certified try within tol."""

import numpy as np
import pytest

from morph.export import greedy


def _first_try(t0, w, bound, top, tol):
    """The oracle: the end of the first try after a segment of width w ending at t0."""
    if bound > 0:
        ratio = (greedy.AIM * tol / bound) ** (1.0 / greedy.NEXT_POWER)
    else:
        ratio = greedy.NEXT_STEP[1]
    width = w * min(max(ratio, greedy.NEXT_STEP[0]), greedy.NEXT_STEP[1])
    t1 = min(top, t0 + width)
    return top if top - t1 < greedy.REACH_END * (t1 - t0) else t1


def _run(tol, top, scale):
    """Drive the machine; returns the accepted segments (row, t0, t1, bound) with the
    next try each row asked after it (None where its search ended), and the tries
    asked (row, t0, t1, bound, certified)."""
    n = len(top)
    g = greedy.Greedy(top, np.zeros((n, 2)), tol, 2.0 ** -16, _fail, width=np.full(n, 0.5))
    accepted, pending, asked = [], {}, []
    while g.active.any():
        rows, t0, t1, _, need = g.requests()
        for r, a, b in zip(rows.tolist(), t0.tolist(), t1.tolist()):
            if r in pending:
                accepted.append(pending.pop(r) + ((a, b),))
        jump = np.where(np.floor(t0 + 1e-9) + 1.0 < t1 - 1e-9, 20.0, 1.0)
        bound = scale[rows] * (t1 - t0) ** 5 * jump
        cert = np.ones(len(rows), bool)
        asked += list(zip(rows.tolist(), t0.tolist(), t1.tolist(), bound.tolist()))
        at = np.zeros((len(rows), 2), int)
        out = g.update(rows, np.zeros((len(rows), 2)), (np.zeros((len(rows), 4, 2)), bound,
                                                        cert), at)
        for r, a, b, e in zip(out[0].tolist(), out[1].tolist(), out[2].tolist(),
                              out[4].tolist()):
            pending[r] = (r, a, b, e)
    accepted += [p + (None,) for p in pending.values()]
    return accepted, asked


def _fail(*args):
    raise AssertionError("no interval certified: %r" % (args,))


def _check(accepted, asked, top, tol):
    """The oracle over a run: each accepted segment a try asked, within tol; after
    one that does not end its row, the row's next try the documented one.  Returns
    how many next tries were checked."""
    tries = {(r, a, b): e for r, a, b, e in asked}
    checked = 0
    for r, a, b, bound, nxt in accepted:
        assert tries[r, a, b] == bound and bound <= tol
        if nxt is None:
            assert b == top[r]
            continue
        assert nxt[0] == b
        assert nxt[1] == pytest.approx(_first_try(b, b - a, bound, top[r], tol), rel=1e-12)
        checked += 1
    return checked


def test_the_next_first_try_is_the_documented_width(monkeypatch):
    """Sixty rows of 4 to 20 pieces: after every accepted segment that does not end
    the row, the row's next try is the oracle's; every accepted segment is a try the
    machine asked, within tol; the rows end at their ends.  The last width kept as it
    was (the rule broken) fails the oracle."""
    rng = np.random.default_rng(21)
    tol = 1e-3
    top = rng.integers(4, 21, 60).astype(float)
    scale = np.exp(rng.uniform(-1.0, 2.0, len(top))) * tol
    accepted, asked = _run(tol, top, scale)
    assert _check(accepted, asked, top, tol) > 100
    monkeypatch.setattr(greedy, "next_width", lambda w, bound, tol: w)
    accepted, asked = _run(tol, top, scale)
    with pytest.raises(AssertionError):
        _check(accepted, asked, top, tol)


def test_next_width_bounds():
    """The step stays within NEXT_STEP: a bound of 0 gives the largest, a bound far
    above tol the smallest, AIM tol the same width."""
    tol = 1e-3
    w = np.array([1.0, 1.0, 1.0, 2.0])
    got = greedy.next_width(w, np.array([0.0, 1e3 * tol, greedy.AIM * tol, 1e-9 * tol]), tol)
    assert got.tolist() == pytest.approx([greedy.NEXT_STEP[1], greedy.NEXT_STEP[0], 1.0,
                                          2.0 * greedy.NEXT_STEP[1]], rel=1e-12)
