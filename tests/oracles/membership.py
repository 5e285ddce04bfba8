"""The exact membership predicate of a Minkowski sum and the checks built on it.

x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅, evaluated by shapely on operands flattened far below the
tolerance under test (:class:`Oracle`); :func:`straddle_sides` asks whether the true
boundary passes within d of each sampled boundary point (points of the sum and points
outside it within d), :func:`check_loops` adds membership at random points.  Used by
tests/test_minkowski.py and by the acceptance sweeps (tests/oracles/sweep.py).
"""

import numpy as np

from tests.oracles import need

shapely = need("shapely", "the exact membership predicate")
import shapely.affinity  # noqa: E402 - after the check that shapely is installed

from morph import piece as pc  # noqa: E402
from morph import polyline as pl
from morph.minkowski import minkowski_sum  # noqa: E402
from tests.oracles import reference as R  # noqa: E402


def _polygon(region, tol):
    return R.region_to_shapely(region, tol)


class Oracle:
    """x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ (shapely, inputs flattened to ``flat``)."""

    def __init__(self, a, b, flat):
        self.pa = _polygon(a, flat)
        shapely.prepare(self.pa)
        self.neg_b = shapely.affinity.scale(_polygon(b, flat), -1, -1, origin=(0, 0))

    def __call__(self, points):
        moved = [shapely.affinity.translate(self.neg_b, x, y) for x, y in points]
        return shapely.intersects(self.pa, np.array(moved, dtype=object))


def boundary_samples(loops, per_piece=3):
    pts, normals = [], []
    for loop in loops:
        for p in loop:
            t = (np.arange(per_piece) + 0.5) / per_piece
            d = pc.derivative(p, t)
            n = np.column_stack([d[:, 1], -d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
            pts.append(pc.evaluate(p, t))
            normals.append(n)  # outward: right of travel (outer CCW, holes CW)
    return np.concatenate(pts), np.concatenate(normals)


def inside(loops, points):
    polys = [pl.flatten_loop(l, 0.01) for l in loops]
    return R.winding_number(points, polys) != 0


def straddle(oracle, pts, nrm, d, n_ring=24):
    """Membership of probes around each boundary point: (len(pts), 2 + n_ring).

    The true boundary is within d of p iff the disk of radius d around p has points
    in and out of the sum; probed at the two normal points and n_ring points of the
    circle (along the normal alone fails legitimately near concave corners; 24
    directions see wedges down to 15 degrees, e.g. a hole's sharp tip).
    """
    ang = np.linspace(0, 2 * np.pi, n_ring, endpoint=False)
    ring = np.column_stack([np.cos(ang), np.sin(ang)])
    probes = np.concatenate([pts[:, None, :] + d * nrm[:, None, :],
                             pts[:, None, :] - d * nrm[:, None, :],
                             pts[:, None, :] + d * ring[None, :, :]], axis=1)
    return oracle(probes.reshape(-1, 2)).reshape(len(pts), -1)


#: a spike's or crack's tip turns by pi, in one junction or over a few (uniFDB3's:
#: 160 and 20 degrees): junctions turning by more than 45 degrees are its candidates
SHARP_COS = np.cos(np.pi / 4)


def sharp_starts(loops, cos_max=SHARP_COS):
    """Per piece of ``loops`` (in order): whether its start is a junction where the
    boundary turns by more than acos(cos_max)."""
    out = []
    for loop in loops:
        first, last = pc.end_tangents_many(loop, strict=False)
        out.append(np.einsum("ij,ij->i", np.roll(last, 1, axis=0), first) < cos_max)
    return np.concatenate(out) if out else np.zeros(0, bool)


def sharp_junctions(loops):
    """Junction points where the boundary turns by more than 45 degrees, (k, 2)."""
    starts = np.array([pc.start(p) for loop in loops for p in loop], float).reshape(-1, 2)
    return starts[sharp_starts(loops)]


def straddle_sides(oracle, pts, nrm, d):
    """(has a point in the sum, has one out) within d of each point: the probes of
    :func:`straddle`, and where they see one side only, 1440 more (8 radii x 180
    directions: wedges down to 2 degrees, e.g. the tip of a narrow notch at a sharp
    junction, which 24 directions miss)."""
    inside = straddle(oracle, pts, nrm, d)
    has_in, has_out = inside.any(axis=1), (~inside).any(axis=1)
    ang = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    disk = ((d * np.arange(1, 9) / 8)[:, None, None]
            * np.stack([np.cos(ang), np.sin(ang)], axis=1)[None]).reshape(-1, 2)
    for i in np.flatnonzero(~(has_in & has_out)):
        ins = oracle(pts[i] + disk)
        has_in[i], has_out[i] = has_in[i] | ins.any(), has_out[i] | (~ins).any()
    return has_in, has_out


def check_sum(a, b, tol, slack, rng, n_random=60, max_boundary=80):
    return check_loops(minkowski_sum(a, b, tol), a, b, tol, slack, rng, n_random, max_boundary)


def check_loops(loops, a, b, tol, slack, rng, n_random=60, max_boundary=80):
    """Straddle and membership tests of ``loops`` as A ⊕ B within tol + slack."""
    assert loops, "empty sum"
    oracle = Oracle(a, b, 1e-3)
    pts, nrm = boundary_samples(loops)
    if len(pts) > max_boundary:
        pick = rng.choice(len(pts), max_boundary, replace=False)
        pts, nrm = pts[pick], nrm[pick]
    # and every junction turning by more than 45 degrees: a spike's or crack's tip
    # (the ring probes judge it; a corner has no one normal)
    sharp = sharp_junctions(loops)
    pts, nrm = np.concatenate([pts, sharp]), np.concatenate([nrm, np.zeros_like(sharp)])
    has_in, has_out = straddle_sides(oracle, pts, nrm, tol + slack)
    assert has_in.all(), "boundary point farther than tol+slack outside"
    assert has_out.all(), "boundary point farther than tol+slack inside"
    lo = np.min([pc.bbox(p)[:2] for l in loops for p in l], axis=0) - 20
    hi = np.max([pc.bbox(p)[2:] for l in loops for p in l], axis=0) + 20
    x = rng.uniform(lo, hi, size=(n_random, 2))
    ours = inside(loops, x)
    truth = oracle(x)
    # points within slack of our boundary may legitimately disagree
    assert np.array_equal(ours, truth), "membership differs at %s" % (x[ours != truth][:3],)
    return loops
