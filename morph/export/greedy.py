"""The greedy segment search of every chain of a batch as one array state machine.

Every chain's search is a row of arrays (:class:`Greedy`): where its current
segment starts (``t0``, ``start``), the end it tries (``t1``), its bracket (the
longest certified or provisional end ``good``, the shortest failed end ``bad``), the
last fit (``last_w``, ``last_b``: the error model's slope), which pass it is in and
its mode (trying ends, certifying a provisional end, halving).  A round asks one fit
of every chain still searching (:meth:`Greedy.requests`), and one numpy step per
round (:meth:`Greedy.update`) takes all their results: accept or move the bracket,
aim the next end (:func:`next_tries`, the model bound ~ width^p), start the next
segment.  No Python step runs per chain and round; what remains per segment is
writing it out (a :class:`~morph.export.certify.CubicFit`).

A chain's end ``top`` may move nearer while it searches (:meth:`Greedy.cap`: a
search of the same chain from its other end has come that far,
:func:`morph.export.search._drive`).  A chain may wait (:meth:`Greedy.wait`) while
it is tried as equal cuts, and resume (:meth:`Greedy.resume`) with a cut's fit as
its next try.

The search of one segment: the first try spans the previous segment's width
scaled by the error model from that segment's bound (:func:`next_width`; a chain's
first segment: the width its caller guessed, :func:`morph.export.search.
first_widths`; the chain's end when less than REACH_END of it would be left); a try
is accepted once it is certified with a bound of at least ACCEPT tol (or reaches the
chain's end); otherwise the next end follows the model bound ~ width^p (p from the
last two fits, within P_MIN, P_MAX), aimed at AIM tol, within the bracket, until the bracket is
narrower than BRACKET_REL of the width or MAX_TRIES fits were made; a bracket
narrower than SNAP of the failing width with a join of two pieces inside tries the
join next, certified at once, and ends there if it fits.  Tries sampled
below PROVISIONAL tol are not certified (the search extends them anyway); when the
search ends on one, it is certified, and where that fails the segment is searched
again certifying every try.  With no certified fit at all the shortest failed
interval is halved until one certifies (down to the minimal width, then
:class:`~morph.errors.ToleranceNotMetError`).

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import numpy as np

#: The search stops at a certified segment whose bound is at least this share of tol
#: (higher: longer segments, more fits).  Equal to PROVISIONAL, so that a try that is
#: certified at all ends the first pass (tries sampled below PROVISIONAL tol are not
#: certified); bench/export_profile.py counts the fits and certificates it saves.
ACCEPT = 0.7
#: A try whose sampled distance is below this share of tol is not certified (the
#: search extends it anyway); the longest such try is certified once the search
#: would end on it.
PROVISIONAL = 0.7
#: The search for a segment's end stops once the bracket (longest certified, shortest
#: failed end) is this narrow relative to the certified width.
BRACKET_REL = 0.02
#: The model of :func:`next_tries`: bound ~ width^p, p from the last two fits kept in
#: [P_MIN, P_MAX] (ERROR_POWER without them; widths closer than SAME_WIDTH relative
#: give no slope), the next width aimed at AIM tol.
ERROR_POWER = 5.0
P_MIN, P_MAX = 2.0, 8.0
SAME_WIDTH = 0.01
AIM = 0.9
#: The next width is kept within these factors of the last one; after a fit with no
#: finite bound it is SHRINK times the last.
STEP_MIN, STEP_MAX = 0.125, 4.0
SHRINK = 0.5
#: The first try of a segment runs to the chain's end when less than this share of
#: its width would be left; a pass makes at most MAX_TRIES fits.
REACH_END = 0.3
MAX_TRIES = 8
#: A bracket (longest fitting end, shortest failing one) narrower than this share of
#: the failing width with a join of two pieces inside tries the join itself next,
#: certified at once, and a join that fits ends the segment: where the error jumps
#: within a bracket it jumps at a join (the curvature of a sum jumps there: a cubic
#: spans the join of a nib's arc and a glyph's curve only with its end near it), and
#: bisecting the jump costs a round a halving.
SNAP = 0.3

#: The first try of a segment after one of width w and bound b spans w (AIM tol /
#: b)^(1 / NEXT_POWER), kept within NEXT_STEP times w: the model of
#: :func:`next_tries` with a damped exponent (the next stretch of the curve is not the
#: last one), so a segment accepted well below tol (ended at a join, a tight bracket)
#: does not make the next one start as short, nor one near tol the next start long.
NEXT_POWER = 6.0
NEXT_STEP = (0.75, 1.35)

#: Modes of a chain's search: trying ends, certifying the provisional end it ended
#: on, halving the shortest failed interval (no certified fit yet), done; waiting
#: (its chain is tried as equal cuts elsewhere, :meth:`Greedy.wait`).
TRY, CERTIFY, HALVE, DONE, WAIT = 0, 1, 2, 3, 4


def next_tries(t0, w, bound, last_w, last_b, good, bad, top, tol):
    """The next end to try of every row after a fit of width w with ``bound``
    (``last_w``, ``last_b``: the previous fit, NaN if none; ``good``: the longest
    certified end, NaN if none; ``bad``: the shortest failed end, NaN if none), NaN
    where the bracket is tight enough.  The model is bound ~ width^p with p from the
    last two fits (P_MIN <= p <= P_MAX, ERROR_POWER without them), aimed at AIM tol,
    the step kept within STEP_MIN to STEP_MAX times the width and inside the bracket
    (bisecting it otherwise)."""
    has_good, has_bad = ~np.isnan(good), ~np.isnan(bad)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        slope = (~np.isnan(last_w) & (np.abs(last_w - w) > SAME_WIDTH * w) & (last_b > 0)
                 & (bound > 0) & np.isfinite(bound) & np.isfinite(last_b))
        p = np.where(slope, np.minimum(np.maximum(np.log(bound / last_b) / np.log(w / last_w),
                                                  P_MIN), P_MAX), ERROR_POWER)
        ratio = np.where(bound > 0, (AIM * tol / bound) ** (1.0 / p), STEP_MAX)
    ratio = np.where(np.isfinite(bound), ratio, SHRINK)
    target = np.minimum(top, t0 + w * np.minimum(STEP_MAX, np.maximum(STEP_MIN, ratio)))
    lo = np.where(has_good, good, t0)
    hi = np.where(has_bad, bad, top)
    target = np.where(has_bad & ~((lo < target) & (target < hi)), 0.5 * (lo + hi), target)
    tight = has_good & ((target <= lo) | (has_bad & (hi - lo <= BRACKET_REL * (lo - t0))))
    return np.where(tight, np.nan, target)


def next_width(w, bound, tol):
    """The width of the first try of the segment after segments of widths w with
    certified ``bound`` (arrays): w (AIM tol / bound)^(1 / NEXT_POWER) within
    NEXT_STEP times w (the largest where the bound is 0)."""
    with np.errstate(divide="ignore"):
        ratio = (AIM * tol / bound) ** (1.0 / NEXT_POWER)
    return w * np.minimum(np.maximum(np.where(bound > 0, ratio, NEXT_STEP[1]), NEXT_STEP[0]),
                          NEXT_STEP[1])


class Greedy:
    """The greedy search of every chain as arrays (see the module docstring).

    ``top``: each chain's parameter length K; ``first``: its start point; ``width``:
    the width of its first try (two pieces when None);
    ``min_width``: the narrowest interval tried; ``fail(row, t0, width, bound)``:
    raises the error of a chain where no interval certifies.  :meth:`requests`
    gives the fits of a round, :meth:`update` takes their results and returns the
    segments accepted in the round; :attr:`active` says which chains still search
    (``active``: which start searching; :meth:`activate` starts the others;
    :meth:`cap` moves a chain's end nearer, where a search from the other end has
    come).  The fit (and end point) a chain keeps as ``good`` is referred to by ``good_at``
    (round, request): its panels are made only for the segments written."""

    def __init__(self, top, first, tol, min_width, fail, active=True, width=None):
        n = len(top)
        self.top, self.tol, self.min_width, self.fail = np.array(top, float), tol, min_width, fail
        self.t0, self.t1, self.start = np.zeros(n), np.zeros(n), np.array(first, float)
        self.width0 = np.minimum(self.top, 2.0) if width is None else np.array(width, float)
        self.width = self.width0.copy()
        self.mode, self.passno, self.tries = np.full(n, TRY), np.zeros(n, int), np.zeros(n, int)
        self.snap = np.zeros(n, bool)
        self.bad, self.last_w, self.last_b = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
        # the longest certified (or provisional) fit: end, bound, certified, where, cubic
        self.good, self.good_b, self.good_cert = np.full(n, np.nan), np.zeros(n), np.zeros(n, bool)
        self.good_at, self.good_end, self.good_cubic = np.zeros((n, 2), int), np.zeros((n, 2)), \
            np.zeros((n, 4, 2))
        self.first = self.start.copy()
        active = np.broadcast_to(np.asarray(active, bool), (n,))
        self.mode[~active] = DONE
        self._new_segments(np.nonzero(active)[0])

    def activate(self, rows, t0=None, start=None):
        """Start the search of the chains ``rows`` (made inactive: ``active`` False)
        from their start, or from the parameters ``t0`` (points ``start``)."""
        if not len(rows):
            return
        self.t0[rows] = 0.0 if t0 is None else t0
        self.start[rows] = self.first[rows] if start is None else start
        self.width[rows] = self.width0[rows]
        self._new_segments(rows)

    @property
    def active(self):
        return self.mode < DONE

    def cap(self, rows, top):
        """Lower the end of the chains ``rows`` (an int array) to ``top`` (a float
        array; a search from the other end has come that far): tries past it are
        moved onto it, brackets past it dropped; the search ends at it."""
        lower = top < self.top[rows]
        rows, top = rows[lower], top[lower]
        if not rows.shape[0]:
            return
        self.top[rows] = top
        past = self.t1[rows] > top
        r = rows[past]
        self.t1[r] = top[past]
        self.mode[r[self.mode[r] != HALVE]] = TRY
        self.good[r[self.good[r] > self.top[r]]] = np.nan
        self.bad[r[self.bad[r] > self.top[r]]] = np.nan

    def wait(self, rows):
        """Stop the search of ``rows`` without ending it (their chains are tried as
        equal cuts, :meth:`morph.export.refine.Refine.split`): no requests until
        :meth:`resume`."""
        self.mode[rows] = WAIT

    def resume(self, rows, t1):
        """Search ``rows`` (waiting after their first try, the whole chain, failed)
        again, the end ``t1`` as their next try: its fit, made elsewhere, is given to
        :meth:`update` next."""
        self.mode[rows], self.t1[rows] = TRY, t1

    def _new_segments(self, rows):
        """Start the segment search of ``rows`` at their t0: the first try spans
        ``width`` (the chain's guess, or :func:`next_width` of the previous segment),
        to the chain's end when little would be left."""
        if not len(rows):
            return
        self.mode[rows], self.passno[rows], self.tries[rows] = TRY, 0, 0
        self.snap[rows] = False
        self.good[rows], self.good_cert[rows] = np.nan, False
        self.bad[rows], self.last_w[rows], self.last_b[rows] = np.nan, np.nan, np.nan
        t0, top = self.t0[rows], self.top[rows]
        t1 = np.minimum(top, t0 + self.width[rows])
        self.t1[rows] = np.where(top - t1 < REACH_END * (t1 - t0), top, t1)

    def requests(self):
        """(rows, t0, t1, start, need) of the round's fits: one per searching chain;
        ``need``: PROVISIONAL in the first pass of the trying mode (not at the chain's
        end), else 0 (certify)."""
        rows = (self.mode < DONE).nonzero()[0]
        t1 = self.t1[rows]
        need = np.where((self.mode[rows] == TRY) & (self.passno[rows] == 0)
                        & (t1 != self.top[rows]) & ~self.snap[rows], PROVISIONAL, 0.0)
        return rows, self.t0[rows], t1, self.start[rows], need

    def update(self, rows, end, fits, at):
        """Take the results of :meth:`requests` (``end``: the tried ends' points;
        ``fits``: (cubic, bound, certified) arrays; ``at``: (round, request) of each)
        and advance every chain one step.  Returns the segments accepted in the
        round: (rows, t0, t1, cubic, bound, at), arrays."""
        cubic, bound, cert = fits
        t1, mode = self.t1[rows], self.mode[rows]
        ok = bound <= self.tol
        tried = mode == TRY
        better = tried & ok & (np.isnan(self.good[rows]) | (t1 > self.good[rows]))
        b = rows[better]
        self.good[b], self.good_b[b], self.good_cert[b] = t1[better], bound[better], cert[better]
        self.good_at[b], self.good_end[b] = at[better], end.compress(better, axis=0)
        self.good_cubic[b] = cubic.compress(better, axis=0)
        g = self._tried(rows[tried], t1[tried], bound[tried], cert[tried] & ok[tried])
        acc = (g, self.good[g], self.good_cubic.take(g, axis=0), self.good_b[g],
               self.good_at[g], self.good_end.take(g, axis=0))
        if not np.logical_and.reduce(tried):        # rows certifying or halving
            acc = self._certified(rows, (t1, mode, ok), (cubic, bound, at, end), acc)
        r, t1a, ca, ba, ata, ea = acc
        out = (r, self.t0[r].copy(), t1a, ca, ba, ata)
        self.width[r] = next_width(t1a - self.t0[r], ba, self.tol)
        self.t0[r], self.start[r] = t1a, ea
        finished = t1a >= self.top[r]
        self.mode[r[finished]] = DONE
        self._new_segments(r[~finished])
        return out

    def _certified(self, rows, state, fits, acc):
        """The step of :meth:`update` for the rows that certify a provisional end or
        halve (``state``: the rows' t1, mode and whether their fits are within tol;
        ``fits``: cubic, bound, at, end): a certified end is the segment (put before
        ``acc``, the segments of the trying rows), a refused one searched again, a
        failed halving halved again.  Returns the segments (rows, t1, cubic, bound,
        at, end)."""
        t1, mode, ok = state
        cubic, bound, at, end = fits
        took = (mode != TRY) & ok
        refused = rows[(mode == CERTIFY) & ~ok]
        self._refused(refused, self.t1[refused], bound[(mode == CERTIFY) & ~ok])
        halved = (mode == HALVE) & ~ok
        self.bad[rows[halved]] = t1[halved]
        self._halve(rows[halved], bound[halved])
        mine = (rows[took], t1[took], cubic.compress(took, axis=0), bound[took], at[took],
                end.compress(took, axis=0))
        return [np.concatenate(x) for x in zip(mine, acc)]

    def _tried(self, rows, t1, bound, accept):
        """The trying mode's step for ``rows``: move the bracket, aim the next end;
        a pass ends on an accepted try (certified, at least ACCEPT tol or at the
        chain's end), a tight bracket, MAX_TRIES fits or the minimal width.  Returns
        the rows whose segment is their certified ``good`` fit; the others go on
        trying, certify their provisional end, or halve."""
        t0, top = self.t0[rows], self.top[rows]
        failed = bound > self.tol
        self.bad[rows[failed]] = np.fmin(self.bad[rows[failed]], t1[failed])
        target = next_tries(t0, t1 - t0, bound, self.last_w[rows], self.last_b[rows],
                            self.good[rows], self.bad[rows], top, self.tol)
        self.last_w[rows], self.last_b[rows] = t1 - t0, bound
        self.tries[rows] += 1
        accept &= (t1 == top) | (bound >= ACCEPT * self.tol) | self.snap[rows]
        stop = (accept | np.isnan(target) | (target - t0 < self.min_width)
                | (self.tries[rows] >= MAX_TRIES))
        # a narrow bracket over a join: try the join
        good, bad = self.good[rows], self.bad[rows]
        join = np.floor(np.where(np.isnan(good), t0, good)) + 1.0
        snap = (~stop & ~np.isnan(bad) & (join < bad) & (join > t0)
                & (bad - np.where(np.isnan(good), t0, good) <= SNAP * (bad - t0))
                & ~self.snap[rows])
        target = np.where(snap, join, target)
        self.snap[rows] = snap
        self.t1[rows[~stop]] = target[~stop]
        ended = rows[stop]
        has_good = ~np.isnan(self.good[ended])
        # the search ends on a provisional try (first pass only): certify it
        check = has_good & ~self.good_cert[ended] & (self.passno[ended] == 0)
        self.mode[ended[check]] = CERTIFY
        self.t1[ended[check]] = self.good[ended[check]]
        self._halve(ended[~has_good], bound[stop][~has_good])
        return ended[has_good & ~check]

    def _refused(self, rows, t1, bound):
        """A provisional end whose certificate fails (loose here): search the
        segment again certifying every try, that end the shortest failed one."""
        if not len(rows):
            return
        t0, top = self.t0[rows], self.top[rows]
        self.bad[rows], self.last_w[rows], self.last_b[rows] = t1, np.nan, np.nan
        nan = np.full(len(rows), np.nan)
        target = next_tries(t0, t1 - t0, bound, nan, nan, nan, t1, top, self.tol)
        target = np.where(np.isnan(target) | (target == 0.0), 0.5 * (t0 + t1), target)
        self.last_w[rows], self.last_b[rows] = t1 - t0, bound
        self.mode[rows], self.passno[rows], self.tries[rows] = TRY, 1, 0
        self.good[rows], self.good_cert[rows] = np.nan, False
        self.t1[rows] = target

    def _halve(self, rows, bound):
        """No certified fit yet: try half the shortest failed interval, down to the
        minimal width (then ``fail``)."""
        if not len(rows):
            return
        t0 = self.t0[rows]
        t1 = t0 + 0.5 * (self.bad[rows] - t0)
        small = t1 - t0 < self.min_width
        if np.logical_or.reduce(small):
            i = int(np.argmax(small))
            self.fail(int(rows[i]), float(t0[i]), float(self.bad[rows[i]] - t0[i]),
                      float(bound[i]))
        self.mode[rows], self.t1[rows] = HALVE, t1
