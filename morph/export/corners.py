"""Short curved runs between two lines written as the corner of the lines.

A stroked polyline (a Hershey glyph, a hanzi median) has, at every vertex, a small arc
of the nib between the two offset lines of its edges; a brushed outline has the same
at its polygon corners.  Where the two lines extended meet at a point p whose
distance to the arc is within the export's tolerance, the arc costs three points as a
cubic and draws nothing the corner does not: :func:`cut_corners` drops such runs and
moves the lines' ends to p.

**Bound.**  Let the run go from a (the end of the line before it, direction d1) to b
(the start of the line after it, direction d2), the lines extended meeting at
p = a + s d1 = b - t d2 with s, t > 0 and a turn of at most a right angle
(d1 . d2 >= 0).  Every control point of the run's pieces (rational, positive weights)
lies in the triangle (a, p, b), so the run does (convex hull).  The triangle's angles
at a and b add up to the turn, so both are acute, and with h the distance from p to
the chord ab:

- every point x of the run is within h of the sides ap, pb (the perpendicular to ab
  through x leaves the triangle through them within h);
- every point q of the sides is within h of the run (q's perpendicular foot on ab
  lies between a and b, the acute angles, and the segment from q to it, at most h
  long, separates a from b in the triangle: the run, a curve from a to b inside it,
  crosses it).

So the Hausdorff distance between the run and the corner a-p-b is at most h, and a
run is dropped when h plus the control points' allowance (``slack``: how far outside
the triangle rounding may put a point that lies on a side) is within ``tol``, the
bound every written cubic keeps.
"""

import numpy as np

from ..polyline import unique

__all__ = ["cut_corners"]

#: Rounding allowance, relative to the coordinates' size, for control points that lie
#: on the triangle's sides (a conic arc's middle point is the corner p itself): a
#: point may be this far outside and still count as in; the bound adds it.
SLACK = 1e-9


def cut_corners(bank, runs, tol, wrap):
    """The mask of the runs of :func:`morph.export.bank.plan_run_arrays` still to be
    written; the runs it drops have their neighbouring lines' ends moved to their
    corners in ``bank`` (the lines' control points, module docstring).  A run is
    dropped when it is not exact, both its neighbours in its loop are single lines
    that meet it end to end, and the corner bound is within ``tol``.  The neighbours
    of a loop's first and last runs are each other's only with ``wrap`` (the output
    need not start at the loop's start)."""
    n = len(runs.sizes)
    keep = np.ones(n, bool)
    if n < 3:
        return keep
    head = np.cumsum(runs.sizes) - runs.sizes
    first_gid, last_gid = runs.order[head], runs.order[head + runs.sizes - 1]
    prev, nxt = _neighbours(runs.loop, wrap)
    single = runs.exact & (runs.sizes == 1) & bank.line[first_gid]
    cand = ~runs.exact & (prev >= 0) & (nxt >= 0)
    cand[cand] &= single[prev[cand]] & single[nxt[cand]] & (prev[cand] != nxt[cand])
    r = np.nonzero(cand)[0]
    if not len(r):
        return keep
    lp, ln = first_gid[prev[r]], first_gid[nxt[r]]
    a, b = bank.first[first_gid[r]], bank.last[last_gid[r]]
    slack = SLACK * (1.0 + np.maximum(bank.scale[lp], bank.scale[ln]))
    p, h, ok = _corner(bank, lp, ln, a, b, slack)
    ok &= h + slack <= tol
    ok[ok] = _inside(bank, runs, head[r[ok]], runs.sizes[r[ok]], a[ok], p[ok], b[ok],
                     slack[ok])
    keep[r[ok]] = False
    _move_ends(bank, lp[ok], ln[ok], p[ok])
    return keep


def _move_ends(bank, before, after, corner):
    """Lines ``before`` end at ``corner``, lines ``after`` start there (a line is
    before one run at most and after one at most): their rows of the bank's stack
    of lines rewritten (weights 1)."""
    gids = unique(np.concatenate([before, after]))
    if not len(gids):
        return
    lines = np.stack([bank.first[gids], bank.last[gids]], axis=1)    # (k, 2, 2)
    lines[np.searchsorted(gids, before), 1] = corner
    lines[np.searchsorted(gids, after), 0] = corner
    stack = bank.stacks[2]
    stack[bank.idx[gids], :, :2] = lines
    stack[bank.idx[gids], :, 2] = 1.0


def _neighbours(loop, wrap):
    """(previous, next) run of every run in its loop (-1: none)."""
    n = len(loop)
    idx = np.arange(n)
    start = np.searchsorted(loop, loop)                 # the loop's first run
    stop = np.searchsorted(loop, loop, side="right") - 1
    prev = np.where(idx > start, idx - 1, stop if wrap else -1)
    nxt = np.where(idx < stop, idx + 1, start if wrap else -1)
    return prev, nxt


def _corner(bank, lp, ln, a, b, slack):
    """(p, h, ok): the corner of the lines ``lp`` (ending at the run's start a) and
    ``ln`` (starting at its end b), its distance h to the chord ab, and whether the
    lines meet the run end to end and each other ahead of a and behind b at a turn
    of at most a right angle."""
    d1 = bank.last[lp] - bank.first[lp]
    d2 = bank.last[ln] - bank.first[ln]
    ab = b - a
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    safe = np.where(cross == 0, 1.0, cross)
    s = (ab[:, 0] * d2[:, 1] - ab[:, 1] * d2[:, 0]) / safe
    t = (d1[:, 0] * ab[:, 1] - d1[:, 1] * ab[:, 0]) / safe
    p = a + s[:, None] * d1
    chord = np.hypot(ab[:, 0], ab[:, 1])
    ap = p - a
    h = np.abs(ap[:, 0] * ab[:, 1] - ap[:, 1] * ab[:, 0]) / np.where(chord > 0, chord, 1.0)
    meet = ((np.abs(bank.last[lp] - a).max(axis=1) <= slack)
            & (np.abs(bank.first[ln] - b).max(axis=1) <= slack))
    ok = (meet & (cross != 0) & (s > 0) & (t > 0) & (chord > 0)
          & ((d1 * d2).sum(axis=1) >= 0))
    return p, h, ok


def _inside(bank, runs, head, sizes, a, p, b, slack):
    """Whether every control point of the runs of ``sizes`` pieces starting at
    ``head`` (in ``runs.order``) lies in its triangle (a, p, b), ``slack`` outside at
    most."""
    which = np.repeat(np.arange(len(head)), sizes)
    within = np.arange(int(sizes.sum())) - np.repeat(np.cumsum(sizes) - sizes, sizes)
    gids = runs.order[np.repeat(head, sizes) + within]
    ok = np.ones(len(head), bool)
    for rows, h in bank.gather(gids):
        x = h[..., :2] / h[..., 2:]                                   # (k, n, 2)
        w = which[rows]
        inside = np.ones(len(rows), bool)
        for u, v, o in ((a, p, b), (p, b, a), (b, a, p)):
            inside &= _same_side(u[w], v[w], o[w], x, slack[w])
        np.logical_and.at(ok, w, inside)
    return ok


def _same_side(u, v, o, x, slack):
    """Whether all points x (k, n, 2) are on o's side of the line uv, or within
    ``slack`` of it."""
    e = v - u
    length = np.hypot(e[:, 0], e[:, 1])
    length = np.where(length > 0, length, 1.0)
    side = np.sign(e[:, 0] * (o - u)[:, 1] - e[:, 1] * (o - u)[:, 0])
    dist = (e[:, None, 0] * (x[..., 1] - u[:, None, 1])
            - e[:, None, 1] * (x[..., 0] - u[:, None, 0])) / length[:, None]
    return np.all(side[:, None] * dist >= -slack[:, None], axis=1)
