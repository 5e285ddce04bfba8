"""The batched moment fitter: cubics fitted to ranges of rational pieces by the method
of kurbo's curve fitter (``fit.rs``: end points and end tangents of the piece, signed
area and x-moment matched; R. Levien's "fitting cubic Béziers" work), done in numpy
for many ranges at once (:func:`moment_cubics`).  The fits are only candidates:
:mod:`morph.export.certify` certifies them.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import functools
import math
from collections import namedtuple

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from ..quadrature import gauss_legendre
from .bank import RunArrays, end_pair, grid_planes


#: The chains of a search as arrays: ``k`` (pieces), ``off`` (where the chain's
#: pieces start in ``bank.order``), ``extent`` (the larger side of the bounding box
#: of its control points: 0 for a chain that is one point), ``tiny`` (1e-12 of its
#: extent), and the :class:`morph.export.bank.Bank`.  Chain c is one curve of
#: parameter T in [0, k[c]]: piece j of it, the bank's global piece
#: ``bank.order[off[c] + j]``, on [j, j + 1].
ChainArrays = namedtuple("ChainArrays", "bank k off extent tiny")


def make_chains(bank, runs):
    """The :class:`ChainArrays` of the runs (arrays of global piece ids of ``bank``, or
    a :class:`morph.export.bank.RunArrays`), their extents for ``tiny`` in one
    reduction; sets ``bank.order`` (all runs' ids, concatenated)."""
    if isinstance(runs, RunArrays):            # the ids already concatenated
        sizes, order = runs.sizes, runs.order.astype(int)
    else:
        sizes = np.fromiter(map(len, runs), int, len(runs))
        order = np.concatenate(runs).astype(int) if runs else np.zeros(0, int)
    offs = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int)
    bank.order = order
    if not len(sizes):
        return ChainArrays(bank, sizes, offs, np.zeros(0), np.zeros(0))
    lo = np.minimum.reduceat(bank.lo.take(order, axis=0), offs)
    hi = np.maximum.reduceat(bank.hi.take(order, axis=0), offs)
    extent = np.maximum(hi - lo, 0.0).max(axis=1)
    return ChainArrays(bank, sizes, offs, extent, 1e-12 * np.maximum(extent, 1e-300))


def _limit_tangent(piece, t, sign, tiny):
    """Direction of travel of a piece at t where its derivative vanishes: the first
    derivative of the tangent numerator H = X'W - XW' (:func:`morph.piece.
    tangent_numerator`, zeros at the ends divided out) that is not zero, k-th
    signed by sign^k (the one-sided limit from the side ``sign``)."""
    h = pc.tangent_numerator(piece)
    for k in range(4):
        v = bz.evaluate(h, [t])[0]
        if math.hypot(*v) > tiny or len(h) == 1:
            return sign ** k * v
        h = bz.derivative(h)
    return v


# ------------------------------------------------------------------ the batched fitter

_Quadrature = namedtuple("_Quadrature", "gl8 gx gw i2 i3")


@functools.lru_cache(maxsize=1)
def _quadrature():
    """The fitter's constants, made on first use: ``gl8`` the 8-point rule on
    [-1, 1]; ``gx``, ``gw`` the 16-point rule on [0, 1]; ``i2[j, k]`` = int B_j B_k'
    and ``i3[i, j, k]`` = int B_i B_j B_k' over [0, 1] for the cubic Bernstein basis
    (the 8-point rule, exact for these degrees)."""
    gl8 = gauss_legendre(8)
    x, w = 0.5 + 0.5 * gl8[0], 0.5 * gl8[1]
    b = bz.basis(3, x)                                             # (8, 4)
    diff = 3.0 * (np.eye(3, 4, 1) - np.eye(3, 4))                  # B3_k' in B2
    db = bz.basis(2, x) @ diff
    gx, gw = gauss_legendre(16)
    return _Quadrature(gl8, 0.5 + 0.5 * gx, 0.5 * gw,
                       np.einsum("g,gj,gk->jk", w, b, db),
                       np.einsum("g,gi,gj,gk->ijk", w, b, b, db))


#: Handle lengths d0 (in chord lengths) where the moment equation is solved.
_D0_GRID = np.linspace(0.0, 2.0, 81)[1:]
#: kurbo's handle-length penalty: the sampled error is scaled by
#: (1 + max(d - elbow, 0) * slope)^2 for the longer handle d (in chord lengths).
D_ELBOW, D_SLOPE = 0.65, 2.0
#: The fitter's acceptance distance is at most this multiple of tol (a cubic 16 tol
#: away certifies nothing; the search then halves its step).
FIT_SLACK = 16.0
#: Candidate cubics kept per range (roots of the moment equation).
MAX_CANDIDATES = 6
#: The handle length (in chord lengths) of a range whose moment equation has no root.
_THIRD = np.array([1.0 / 3.0])


def _to_frame(vx, vy, e, out_x, out_y):
    """Vectors (vx, vy) in the unit-chord frame whose x axis is ``e`` = chord /
    |chord|^2 (columns broadcast against vx): x along the chord, y to its left, in
    chord lengths; written to out_x, out_y."""
    ex, ey = e
    np.multiply(vx, ex, out=out_x)
    out_x += vy * ey
    np.multiply(vy, ex, out=out_y)
    out_y -= vx * ey


def moment_cubics(bank, parts, starts, ends, tiny, tol):
    """Fitted cubics for many chain ranges at once: range r runs from ``starts[r]``
    to ``ends[r]`` over the parts of :class:`Parts` ``parts`` with ``req == r``
    (pieces of ``bank``, each restricted to its [a, b]); ``tiny[r]``: below this a
    derivative counts as zero.  Returns (cubics (n, 4, 2), sampled distance (n,),
    fitted (n,) bool): where ``fitted`` is False no cubic was accepted.

    R. Levien's area-and-moment fit, as kurbo's ``fit_to_cubic`` does it (kurbo's
    fit.rs): in the frame where the chord runs from (0, 0) to (1, 0), the cubic
    with the range's end tangent directions (angles th0, th1) and handle lengths
    d0, d1 is chosen so that its signed area int y dx and moment int x y dx equal
    the range's.  The range's integrals are Gauss-Legendre sums (16 nodes on each
    part, in the part's own parameter: the integrals do not depend on the
    parametrisation); the cubic's are polynomials in (d0, d1) (exact Bernstein
    integrals of :func:`_quadrature`).  The area is linear in d1, so d1 = d1(d0)
    and the moment equation becomes one equation in d0, solved on a grid of d0
    (sign changes, refined by regula falsi; without one, the grid point of least
    residual, like kurbo's real part of a complex root pair).  Of the candidates
    the one with the least sampled distance wins: rays from the range's samples
    along their normals to the cubic (Newton), scaled by kurbo's penalty on long
    handles, kept if below the acceptance distance (half the chord, at least tol,
    at most FIT_SLACK tol).  A chord shorter than that gets its straight line.
    Nothing here is a certificate: the caller certifies (:func:`certify_many`).
    The fourth result, :class:`Rays`, holds what the rays of the picked cubics found
    at every sample, for the certificate to start from.
    """
    n = starts.shape[0]
    if not n:
        return np.zeros((0, 4, 2)), np.zeros(0), np.zeros(0, bool), \
            Rays(np.zeros((0, 16)), np.zeros((0, 16)), np.zeros((0, 16)))
    chord = ends - starts
    chord2 = (chord * chord).sum(1)
    length = np.sqrt(chord2)
    acc = np.maximum(tol, np.minimum(0.5 * length, FIT_SLACK * tol))
    short = length <= acc
    good = ~short & (chord2 > 0)
    safe2 = np.where(good, chord2, 1.0)
    sam = _range_samples(bank, parts, starts, chord / safe2[:, None], tiny)
    ta, tm = _cubic_integrals(sam.t0, sam.t1)
    cr, cd0, cd1 = _handle_candidates(sam.area, sam.moment, ta, tm, good)
    t0, t1 = sam.t0, sam.t1
    ctrl = np.zeros((cr.shape[0], 4, 2))
    ctrl[:, 1] = cd0[:, None] * t0[cr]
    ctrl[:, 2, 0] = 1.0 - cd1 * t1[cr, 0]
    ctrl[:, 2, 1] = -cd1 * t1[cr, 1]
    ctrl[:, 3, 0] = 1.0
    # sampled distance: rays along the samples' normals to the candidate cubic
    scale = (1.0 + np.maximum(np.maximum(cd0, cd1) - D_ELBOW, 0.0) * D_SLOPE) ** 2
    err, rays = _ray_distance(ctrl, cr, sam, parts.req, parts.b - parts.a,
                              length[cr], scale, acc[cr])
    err = err * length[cr]
    cubic, dist, fitted, pick = _picked_cubics(err * scale, err, cr, ctrl, acc, short, starts,
                                               ends, chord)
    return cubic, dist, fitted, _picked_rays(sam, parts, length, cr, pick, rays)


def _picked_rays(sam, parts, length, cr, pick, rays):
    """:class:`Rays` of the picked cubics: their parameters at the samples' rays,
    the rays' lengths and the pieces' speeds there (what the certificate starts
    from); NaN where no picked cubic's ray reached a sample.  ``rays``: the
    (candidate, part, stages) of :func:`_ray_distance`."""
    feet, gap = np.zeros((2,) + sam.speed.shape[::-1]) + np.nan      # (P, 16) each
    cand, part, stages = rays
    for pairs, cols, s, ray in stages:
        c = cand[pairs]
        mine = (pick[cr[c]] == c).nonzero()[0]
        at = (part[pairs[mine], None], cols)
        feet[at] = s[mine]
        gap[at] = ray[mine] * length[cr[c[mine]], None]
    speed = sam.speed * (length[parts.req] * (parts.b - parts.a))
    return Rays(feet, gap, np.ascontiguousarray(speed.T))


#: What the rays of :func:`moment_cubics` found at each part's samples (P, 16), the
#: samples at the 16-point Gauss-Legendre nodes u_j of the part's own parameter:
#: ``feet`` the parameters s_j on the picked cubic where the ray along the piece's
#: normal at the sample meets it, ``gap`` the ray's length |C(s_j) - R(u_j)|,
#: ``speed`` |dR/du| in the part's parameter (NaN feet and gaps where the range's
#: cubic was not picked).
Rays = namedtuple("Rays", "feet gap speed")


#: Parts of fit ranges (arrays, sorted by range): range ``req``, global piece ``gid``
#: of the bank, restricted to its parameters [a, b]; ``subs``: None, or a dict that
#: :func:`moment_cubics` fills with the parts it cut out of their pieces ({control
#: points: (part indices, sub-pieces)}), for the certificate to take them
#: (:func:`cut_pieces`) instead of cutting them again.
Parts = namedtuple("Parts", "req gid a b subs", defaults=(None,))


def cut_pieces(parts, idx, h):
    """The sub-pieces (k, n, 3) of the parts ``idx`` (cut: not [0, 1]) whose pieces
    are ``h`` (k, n, 3): those :func:`moment_cubics` cut (``parts.subs``), the
    others cut here (the same call on the same rows: the same numbers)."""
    if parts.subs is None or h.shape[1] not in parts.subs:
        return bz.cut_many(h, parts.a[idx], parts.b[idx])
    have, stack = parts.subs[h.shape[1]]
    at = np.minimum(have.searchsorted(idx), have.shape[0] - 1)
    todo = have[at] != idx
    if not np.logical_or.reduce(todo):                   # all cut already
        return stack.take(at, axis=0)
    out = np.empty_like(h)
    out[~todo] = stack.take(at[~todo], axis=0)
    out[todo] = bz.cut_many(h.compress(todo, axis=0), parts.a[idx[todo]], parts.b[idx[todo]])
    return out


#: The samples of :func:`_range_samples`: ``q`` (4, 16, P) the planes x, y, x', y'
#: of every part (a column) at the 16 Gauss-Legendre nodes of its own parameter (a
#: row), in its range's chord frame; ``speed`` (16, P) = |(x', y')|; per range the
#: unit end tangents ``t0``, ``t1`` (n, 2), the ``area`` and ``moment``
#: (Gauss-Legendre sums) and its parts ``lo:hi`` (their positions, the parts being
#: sorted by range).
_Samples = namedtuple("_Samples", "q speed t0 t1 area moment lo hi")


def _range_samples(bank, parts, starts, e, tiny):
    """The ranges' :class:`_Samples` for :func:`moment_cubics`, in the chord frames
    (``e`` = chord / |chord|^2): 16 Gauss-Legendre nodes on each part (whole pieces
    from the bank's cache, :meth:`morph.export.bank.Bank.node_planes`; cut ones one
    evaluation per degree), the end tangents one-sided limits where the derivative
    vanishes.  Sample-major planes: a part's numbers (start, frame) broadcast along
    the rows, every operation a few long contiguous loops."""
    n = starts.shape[0]
    req, gid, lo, hi = parts.req, parts.gid, parts.a, parts.b
    width = hi - lo
    rng = np.arange(n)
    first, last = req.searchsorted(rng), req.searchsorted(rng, side="right") - 1
    quad = _quadrature()
    jets = np.empty((4, quad.gx.shape[0], gid.shape[0]))
    whole = (lo == 0.0) & (width == 1.0)          # whole pieces: one basis for all
    jets[:, :, whole] = bank.node_planes(gid[whole], quad.gx)
    # every part's end derivatives (2, P, 2) in its own parameter: of its piece
    # (whole), of its sub-piece on [a, b] (cut, made here) divided by b - a
    ends = bank.d_ends.take(gid, axis=1)
    cut = (~whole).nonzero()[0]         # cut pieces: the piece on [a, b] at the nodes
    for rows, h in bank.gather(gid[cut]):
        i = cut[rows]
        sub, major = bz.cut_many(h, lo[i], hi[i], major=True)    # on [a, b], 0 <= a < b <= 1
        if parts.subs is not None:
            parts.subs[h.shape[1]] = (i, sub)
        part = grid_planes(sub, *_node_bases(h.shape[1] - 1), major=major)
        part[2:] /= width[i]
        jets[:, :, i] = part
        ends[:, i] = end_pair(sub) / width[i, None]
    # the ranges' end derivatives: at the start of the first part, the end of the last
    de = np.concatenate([ends[0, first], ends[1, last]])
    for j in (np.hypot(de[:, 0], de[:, 1]) <= np.concatenate([tiny, tiny])).nonzero()[0].tolist():
        r, sign = j % n, (1.0 if j < n else -1.0)
        i = first[r] if sign > 0 else last[r]
        de[j] = _limit_tangent(bank.pieces[gid[i]], lo[i] if sign > 0 else hi[i],
                               sign, tiny[r])
    q = np.empty_like(jets)
    pe = e.take(req, axis=0).T                                                   # (2, P)
    jets[:2] -= starts.take(req, axis=0).T[:, None]
    # points and derivatives together: planes (x, x') and (y, y')
    _to_frame(jets[0::2], jets[1::2], pe, q[0::2], q[1::2])
    t = np.empty((2, 2 * n))
    _to_frame(de[:, 0], de[:, 1], np.concatenate([e, e]).T, t[0], t[1])
    t /= np.maximum(np.hypot(t[0], t[1]), 1e-300)
    wu = q[2] * (quad.gw[:, None] * width)
    wu *= q[1]
    area = np.bincount(req, np.add.reduce(wu, 0), n)
    wu *= q[0]
    speed = q[2] * q[2]                                 # |(x', y')|, frame units
    speed += q[3] * q[3]
    return _Samples(q, np.sqrt(speed, out=speed), t[:, :n].T, t[:, n:].T, area,
                    np.bincount(req, np.add.reduce(wu, 0), n), first, last + 1)


@functools.lru_cache(maxsize=None)
def _node_bases(n):
    """The Bernstein bases of degrees n and n - 1 at the 16-point Gauss-Legendre nodes."""
    gx = _quadrature().gx
    return bz.basis(n, gx), bz.basis(n - 1, gx)


def _cubic_integrals(t0, t1):
    """Area and moment of the frame cubics K + d0 U + d1 V (end tangents t0, t1) as
    polynomials in (d0, d1): ``ta`` (n, 2, 3) area terms d_b m_c and ``tm``
    (n, 3, 2, 3) moment terms m_a d_b m_c, m = (1, d0, d1) (exact Bernstein
    integrals of :func:`_quadrature`):

        ta[b, c] = sum_jk y_b[j] x_c[k] i2[j, k]
        tm[a, b, c] = sum_ijk x_a[i] y_b[j] x_c[k] i3[i, j, k]

    with the control points x_K = (0, 0, 1, 1), x_U = (0, cos th0, 0, 0), x_V = (0, 0,
    -cos th1, 0), y_U = (0, sin th0, 0, 0), y_V = (0, 0, sin th1, 0).  Only the
    terms whose control points are not zero by construction are summed (in the order
    of the indices, products left to right, from 0: the very numbers of the whole
    sums, whose other terms are zeros); all terms of all ranges in a few array
    operations (:func:`_integral_terms`: each sum's terms added layer by layer)."""
    n = t0.shape[0]
    v = np.empty((n, 5))
    v[:, 0] = 1.0
    v[:, 1:3] = t0
    v[:, 3:] = -t1
    (ya, xa, ca, sa, la), (um, ym, xm, cm, sm, lm) = _integral_terms()
    ta = _layered((v[:, ya] * v[:, xa]) * ca, la, 6).reshape(n, 2, 3)
    tm = _layered(((v[:, um] * v[:, ym]) * v[:, xm]) * cm, lm, 18).reshape(n, 3, 2, 3)
    return ta, tm


def _layered(terms, layers, size):
    """(n, size): the terms summed into their slots, from 0, in the order of the
    terms: ``layers`` (:func:`_layers`) lists per layer the slots and the columns of
    ``terms`` of the terms that are the l-th of their slot (distinct slots within a
    layer), so a slot's sum is the left-to-right sum."""
    out = np.zeros((terms.shape[0], size))
    for at, cols in layers:
        out[:, at] = out[:, at] + terms[:, cols]
    return out


def _layers(slot, cols=None):
    """The layers of :func:`_layered` of the terms whose slots are ``slot`` (term i is
    the k-th of its slot): per layer (its terms' slots, their columns: the terms'
    positions, or ``cols`` of them)."""
    seen, rank = {}, []
    for s in slot:
        rank.append(seen.get(s, 0))
        seen[s] = rank[-1] + 1
    rank = np.array(rank, int)
    cols = np.arange(len(rank)) if cols is None else cols
    return [(slot[lay], cols[lay]) for lay in
            (np.nonzero(rank == k)[0] for k in range(int(rank.max()) + 1 if len(rank) else 0))]


@functools.lru_cache(maxsize=1)
def _integral_terms():
    """The terms of :func:`_cubic_integrals`, as indices into the values (1, cos th0,
    sin th0, -cos th1, -sin th1) and constants: area (y, x, constant, slot, layers)
    and moment (u, y, x, constant, slot, layers), slots b * 3 + c and (a * 2 + b) * 3
    + c, terms in the order of the written-out sums."""
    quad = _quadrature()
    xs = ({2: 0, 3: 0}, {1: 1}, {2: 3})                 # K, U, V: control index: value
    ys = ({1: 2}, {2: 4})                               # U, V
    area, moment = [], []
    for b, yb in enumerate(ys):
        for c, xc in enumerate(xs):
            for j, y in yb.items():
                for k, x in xc.items():
                    area.append((y, x, quad.i2[j, k], b * 3 + c))
            for a, xa in enumerate(xs):
                for i, u in xa.items():
                    for j, y in yb.items():
                        for k, x in xc.items():
                            moment.append((u, y, x, quad.i3[i, j, k], (a * 2 + b) * 3 + c))
    ya, xa, ca, sa = (np.array(col) for col in zip(*area))
    um, ym, xm, cm, sm = (np.array(col) for col in zip(*moment))
    return (ya, xa, ca, sa, _layers(sa)), (um, ym, xm, cm, sm, _layers(sm))


def _monomial_coefficients(tm):
    """(n, 9): the moment terms m_a n_b m_c tm[a, b, c] (m = (1, d0, d1), n = (d0,
    d1)) summed into the coefficients of the monomials d0^i d1^j of
    :data:`_MONOMIAL_POWERS` (additions in a fixed order, term by term, by
    :func:`_layered`: a range's coefficients do not depend on the batch, as a BLAS
    product's may)."""
    return _layered(tm.reshape(tm.shape[0], 18), _monomial_terms(), len(_MONOMIAL_POWERS))


@functools.lru_cache(maxsize=1)
def _monomial_terms():
    """The layers of :func:`_layered` of :func:`_monomial_coefficients`: the terms'
    monomials (slots) and flat indices into tm (n, 18) (columns)."""
    em = [(0, 0), (1, 0), (0, 1)]
    idx, slot = [], []
    for a in range(3):
        for b in range(2):
            for c in range(3):
                i = em[a][0] + (1 - b) + em[c][0]
                j = em[a][1] + b + em[c][1]
                idx.append((a * 2 + b) * 3 + c)
                slot.append(_MONOMIAL_POWERS.index((i, j)))
    return _layers(np.array(slot, int), np.array(idx, int))


#: The monomials d0^i d1^j of the frame cubic's moment (:func:`_handle_candidates`).
_MONOMIAL_POWERS = [(1, 0), (0, 1), (2, 0), (1, 1), (0, 2), (3, 0), (2, 1), (1, 2), (0, 3)]


def _handle_candidates(area, moment, ta, tm, good):
    """Candidate handle lengths (range, d0, d1) of :func:`moment_cubics`: the roots
    of the moment residual in d0 on :data:`_D0_GRID` (sign changes refined by regula
    falsi), its local minima that do not cross zero, and handles of a third where
    nothing solves; at most MAX_CANDIDATES per range, positive and finite."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return _solved_handles(area, moment, _area_terms(ta), _monomial_coefficients(tm), good)


def _solved_handles(area, moment, at, cf, good):
    """:func:`_handle_candidates` from the area terms ``at`` (:func:`_area_terms`) and
    the moment's monomial coefficients ``cf`` (:func:`_monomial_coefficients`), with
    numpy's warnings silenced (d1 is inf or NaN where the area equation has no
    root, the residual undefined there)."""
    n = area.shape[0]

    def resid(d0, d1, c):
        # the moment as the cubic polynomial of (d0, d1) with coefficients c (9 rows)
        c0, c1, c2, c3, c4, c5, c6, c7, c8 = c
        inner = c4 + c7 * d0 + c8 * d1
        inner = (c1 + (c3 + c6 * d0) * d0) + d1 * inner
        return (c0 + (c2 + c5 * d0) * d0) * d0 + d1 * inner

    rr, gg, fa, fb, rn, gn = _grid_scan(area, moment, at, cf, good.nonzero()[0], resid)
    # the bracket (a, f(a)), (b, f(b)) and the new point (x, f(x)), rows of one array
    ends = np.empty((3, 2, rr.shape[0]))
    ends[0, 0], ends[0, 1], ends[1, 0], ends[1, 1] = _D0_GRID[gg], fa, _D0_GRID[gg + 1], fb
    (a, fa), (b, fb), (x, fx) = ends                                       # views
    lo, hi, new = ends
    # the rows of the ranges' terms, split once (the same numbers every iteration)
    area_r, at_r = area[rr], tuple(at.take(rr, axis=1))
    cf_r, moment_r = tuple(np.ascontiguousarray(cf.take(rr, axis=0).T)), moment[rr]
    for _ in range(4):                                             # regula falsi
        np.divide(a * fb - b * fa, fb - fa, out=x)
        np.subtract(resid(x, _d1_of(x, area_r, at_r), cf_r), moment_r, out=fx)
        left = np.sign(fx) == np.sign(fa)
        np.copyto(lo, new, where=left)                           # x replaces a or b
        np.copyto(hi, new, where=~left)
    roots = (a * fb - b * fa) / (fb - fa)
    none = np.zeros(n, bool)
    none[rn] = True
    none[rr] = True
    # nothing solves (e.g. a straight range: area and moment vanish): handles of a
    # third, the straight cubic when the tangents run along the chord
    rt = (good & ~none).nonzero()[0]
    cr = np.concatenate([rr, rn, rt])
    m = cr.shape[0]
    cd0 = np.concatenate([roots, _D0_GRID[gn], _THIRD.repeat(rt.shape[0])])
    thirds = np.arange(m) >= m - rt.shape[0]
    # at most MAX_CANDIDATES per range, the first ones in the order above
    by = cr.argsort(kind="stable")
    rank = np.empty(m, int)
    rank[by] = np.arange(m) - cr[by].searchsorted(cr[by])
    keep = rank < MAX_CANDIDATES
    cr, cd0, thirds = cr[keep], cd0[keep], thirds[keep]
    cd1 = np.where(thirds, _THIRD[0], _d1_of(cd0, area[cr], at.take(cr, axis=1)))
    fine = np.isfinite(cd1) & (cd1 > 0) & (cd0 > 0)
    return cr[fine], cd0[fine], cd1[fine]


#: Ranges per block of :func:`_grid_scan` (its arrays of 80 grid values a range stay
#: in a core's cache).
GRID_BLOCK = 512


def _grid_scan(area, moment, at, cf, good, resid):
    """The moment residual on :data:`_D0_GRID` for the ranges ``good`` (indices), in
    blocks of GRID_BLOCK ranges: its sign changes (range, grid index, residual at
    both ends) and the grid points of locally least |residual| that are not next to
    one (range, grid index), each in range order; where d1 is not finite and
    positive the residual is undefined.  A block is grid-major (80, ranges): a
    range's coefficients broadcast along the rows."""
    out = []
    d0 = _D0_GRID[:, None]
    cf_t = np.ascontiguousarray(cf.T)
    for lo in range(0, good.shape[0], GRID_BLOCK):
        rows = good[lo:lo + GRID_BLOCK]
        d1 = _d1_of(d0, area[rows], at.take(rows, axis=1))
        ok = d1 > 0
        ok &= d1 < np.inf
        bad = ~ok
        f = resid(d0, d1, cf_t.take(rows, axis=1))                # read only where ok
        f -= moment[rows]
        sign = np.sign(f)
        cross = ok[:-1] & ok[1:] & (sign[:-1] != sign[1:])
        r, g = cross.T.nonzero()
        # local minima of |f| that do not cross zero (kurbo: the real part of a
        # complex root pair, a near-double root): the grid points where |f| is least,
        # an undefined neighbour counting as infinite
        af = np.abs(f, out=sign)
        dip = np.zeros(ok.shape, bool)
        dip[1:-1] = (((af[1:-1] <= af[:-2]) | bad[:-2]) & ((af[1:-1] <= af[2:]) | bad[2:])
                     & ok[1:-1])
        dip[0] = ok[0] & ((af[0] <= af[1]) | bad[1])
        dip[:-1] &= ~cross
        dip[1:] &= ~cross
        rd, gd = dip.T.nonzero()
        out.append((rows[r], g, f[g, r], f[g + 1, r], rows[rd], gd))
    if len(out) == 1:
        return out[0]
    if not out:
        return [np.zeros(0, int)] * 6
    return [np.concatenate(x) for x in zip(*out)]


def _picked_cubics(score, err, cr, ctrl, acc, short, starts, ends, chord):
    """Per range the candidate of least score below its acceptance distance (the
    first of equal scores), mapped back from the chord frame (the straight cubic for
    a short chord), with its sampled distance: (cubics, err, fitted) as
    :func:`moment_cubics` returns them."""
    n = starts.shape[0]
    valid = (score < acc[cr]).nonzero()[0]
    valid = valid[np.lexsort((valid, score[valid], cr[valid]))]
    sorted_cr = cr[valid]      # sorted: each range's first entry is its pick
    at = np.concatenate(([True], sorted_cr[1:] != sorted_cr[:-1]))[:valid.shape[0]].nonzero()[0]
    pick = np.zeros(n, int) - 1
    pick[sorted_cr[at]] = valid[at]
    has = pick >= 0
    c = (ctrl.take(np.maximum(pick, 0), axis=0) if ctrl.shape[0]
         else np.zeros((n, 4, 2)))                                  # (n, 4, 2)
    normal = chord[:, ::-1] * _LEFT                    # (-chord_y, chord_x)
    cubic = starts[:, None] + c[..., :1] * chord[:, None] + c[..., 1:] * normal[:, None]
    no = ~has                  # the straight cubic
    cubic[no, 1] = starts[no] + chord[no] / 3.0
    cubic[no, 2] = ends[no] - chord[no] / 3.0
    cubic[:, 0], cubic[:, -1] = starts, ends
    fitted = (has | short) & np.logical_and.reduce(np.isfinite(cubic.reshape(n, 8)), axis=1)
    dist = np.where(has, err[np.maximum(pick, 0)] if err.shape[0] else 0.0, 0.0)
    return cubic, dist, fitted, pick


#: (-1, 1): a vector (x, y) reversed and times this is its normal (-y, x).
_LEFT = np.array([-1.0, 1.0])


def _area_terms(ta):
    """The coefficients of the area equation of :func:`_d1_of` (4, n), from ``ta`` (n,
    2, 3) of :func:`_cubic_integrals`: ta[0, 0], ta[0, 1], ta[1, 0], ta[0, 2] +
    ta[1, 1]."""
    return np.array([ta[:, 0, 0], ta[:, 0, 1], ta[:, 1, 0], ta[:, 0, 2] + ta[:, 1, 1]])


def _d1_of(d0, area, at):
    """d1 from the area equation (linear in d1) for handle lengths d0, with the
    ranges' ``area`` and area terms ``at`` (:func:`_area_terms`) gathered (or
    broadcast) to d0's shape (inf or NaN where the equation has no root: the caller
    silences numpy's warnings, :func:`_handle_candidates`)."""
    num = area - d0 * (at[0] + d0 * at[1])
    den = at[2] + d0 * at[3]
    return num / den


#: Rays of :func:`_ray_distance` per block: a block's dozen working arrays (64 KB
#: each) stay in a core's cache through Newton's iterations, where arrays of all the
#: rays of a round (millions) would be read from memory at every operation.
RAY_BLOCK = 8192
#: The samples (of the 16 of a part) whose rays every candidate gets first: their
#: largest distance is a lower bound of the candidate's sampled distance, which
#: rules out most candidates before the other samples are measured.
COARSE = np.array([1, 5, 10, 14])
_FINE = np.array([j for j in range(16) if j not in COARSE])


class _RayCaster:
    """The rays of :func:`_ray_distance`: each candidate's (candidate, part) pairs
    (``cand``, ``part``), :meth:`cast` casting the rays of some pairs from some of
    their samples (recorded in ``stages``), :meth:`dist_of` the candidates' largest
    rays so far.

    What a ray needs of a sample is kept sample-major, ``data`` (6, 16, P): the
    tangent (x', y'), the point (x, y), the start of Newton's iteration (the sample's
    share of its range's arc length) and -(x, y).(x', y'); what it needs of a
    candidate, ``coef`` (6, N) per pair: the power coefficients a_1, a_2, a_3 (x and
    y) of C(s) = a_1 s + a_2 s^2 + a_3 s^3 (the frame cubic starts at 0)."""

    def __init__(self, ctrl, cr, sam, req, width):
        q = sam.q
        speed = sam.speed * (_quadrature().gw[:, None] * width)        # (16, P)
        size = np.add.reduce(speed, 0)
        tot = np.bincount(req, size)
        # each sample's share of its range's length: the lengths before it (in the
        # range's earlier parts, in its part before it) and half its own
        before = size.cumsum() - size - (tot.cumsum() - tot)[req]
        frac = speed.cumsum(axis=0)
        frac -= 0.5 * speed
        frac += before
        frac /= np.maximum(tot[req], 1e-300)
        pu = q[0] * q[2]
        pu += q[1] * q[3]
        self.data = np.array([q[2], q[3], q[0], q[1], frac, np.negative(pu, out=pu)])
        self.nreq = tot.shape[0]
        self.counts = counts = (sam.hi - sam.lo)[cr]                 # pairs of each candidate
        self.first = first = counts.cumsum() - counts
        self.ncand = ncand = cr.shape[0]
        self.cand = np.arange(ncand).repeat(counts)
        npairs = self.cand.shape[0]
        self.part = (sam.lo[cr] - first).repeat(counts) + np.arange(npairs)
        p1, p2 = ctrl[:, 1], ctrl[:, 2]                               # P0 = (0, 0)
        a2 = 3.0 * (p2 - 2.0 * p1)
        a3 = ctrl[:, 3] + 3.0 * (p1 - p2)
        # (6, N) rows contiguous: np.take along the last axis keeps a row of a plane
        # contiguous in memory (indexing ``[:, idx]`` would give the pairs the outer
        # stride, and every Newton operation would stream through strided copies)
        self.coef = np.concatenate([3.0 * p1, a2, a3], axis=1).T.take(self.cand, axis=1)
        self.planes = {}                  # data's rows per tuple of columns (cast)
        self.worst = np.zeros(npairs)                                  # largest ray of a pair
        self.stages = []
        # the candidates with pairs, and where their pairs start (dist_of's reduction)
        self.some = counts > 0
        self.some_first = first[self.some]

    def cast(self, pairs, cols):
        """The rays of ``pairs`` from their samples ``cols`` (rows of ``data``)."""
        npairs, ncols = pairs.shape[0], cols.shape[0]
        if not npairs:
            return
        key = cols.tobytes()
        if key not in self.planes:
            self.planes[key] = self.data[:, cols]                     # (6, c, P)
        data = self.planes[key]
        s, ray = np.empty((2, ncols, npairs))
        step = max(RAY_BLOCK // ncols, 1)
        for lo in range(0, npairs, step):
            b = pairs[lo:lo + step]
            s[:, lo:lo + step], ray[:, lo:lo + step] = _rays(
                self.coef.take(b, axis=1)[:, None], data.take(self.part[b], axis=2))
        # the largest ray so far (a NaN ray makes it NaN, as in one max over all)
        self.worst[pairs] = np.maximum(self.worst[pairs], np.maximum.reduce(ray, axis=0))
        self.stages.append((pairs, cols, s.T, ray.T))

    def dist_of(self, cands):
        """The largest ray cast so far of each candidate ``cands`` (index or mask)."""
        out = np.zeros(self.ncand)
        if self.some_first.shape[0]:
            out[self.some] = np.maximum(np.maximum.reduceat(self.worst, self.some_first), 0.0)
        return out[cands]


def _ray_distance(ctrl, cr, sam, req, width, length, scale, acc):
    """Largest distance (frame units) from each candidate's range samples to the
    candidate cubic along the samples' normals: Newton on (C(s) - q) . q' = 0 from
    the sample's share of the range's arc length, s clipped to [0, 1].  ``length``,
    ``scale``, ``acc``: each candidate's chord length, handle penalty and acceptance
    distance (the pick of :func:`_picked_cubics`: least ``err * length * scale``
    below ``acc``).  Returns (distance (C,), rays): rays = (candidate (N,), part (N,),
    stages) for the (candidate, part) pairs, ``stages`` a list of (pairs, columns,
    s, length): the parameters s where the rays from the samples ``columns`` of
    those pairs met the cubic, and the rays' lengths (the rays cast, see below).

    Only what can change the pick is measured: every candidate's rays at the
    COARSE samples first (a lower bound of its distance); a candidate whose bound
    already fails ``acc`` is dropped; of the others, the one of least bound in each
    range is measured at every sample, and the rest only where their bound does not
    exceed its score.  The distance of a dropped candidate is inf: the pick is the
    one all samples of all candidates give, and its rays are all cast.  Each ray is
    computed alone (:func:`_rays`), so its result does not depend on the others.
    """
    rc = _RayCaster(ctrl, cr, sam, req, width)
    cand, part, stages, dist_of, cast = rc.cand, rc.part, rc.stages, rc.dist_of, rc.cast
    nreq = rc.nreq
    if not cr.shape[0]:
        return np.zeros(0), (cand, part, stages)
    cast(np.arange(cand.shape[0]), COARSE)
    bound = dist_of(slice(None)) * length * scale
    alive = ~(bound >= acc)
    # per range the live candidate of least bound (the first of equal ones)
    live = alive.nonzero()[0]
    live = live[np.lexsort((live, bound[live], cr[live]))]
    best = live[np.concatenate(([True], cr[live][1:] != cr[live][:-1]))[:live.shape[0]]]
    done = np.zeros(cr.shape[0], bool)
    done[best] = True
    cast(done[cand].nonzero()[0], _FINE)
    full = np.zeros(nreq) + np.nan
    full[cr[best]] = dist_of(best) * length[best] * scale[best]
    others = alive & ~done & ~(bound > full[cr])
    cast(others[cand].nonzero()[0], _FINE)
    done |= others
    err = np.zeros(cr.shape[0]) + np.inf
    err[done] = dist_of(done)
    return err, (cand, part, stages)


def _rays(a, d):
    """Rays from the points (x, y) along the normals of the tangents (x', y') of the
    samples ``d`` (6, c, b: :class:`_RayCaster`'s ``data``) to the cubics of power
    coefficients ``a`` (6, 1, b), Newton on g(s) = (C(s) - p) . t from the start in
    ``d``, s clipped to [0, 1]: (the parameters met, the rays' lengths) (c, b), one
    block of :func:`_ray_distance`, every operation elementwise."""
    a1x, a1y, a2x, a2y, a3x, a3y = a
    ux, uy, px, py, s, g0 = d                           # s: a gathered copy, updated
    g1, g2, g3 = a1x * ux, a2x * ux, a3x * ux          # g(s) = g0 + g1 s + g2 s^2 + g3 s^3
    g1 += a1y * uy
    g2 += a2y * uy
    g3 += a3y * uy
    h2, h3 = 2.0 * g2, 3.0 * g3
    gv, gd = np.empty((2,) + s.shape)
    tiny = np.empty(s.shape, bool)
    for _ in range(5):
        np.multiply(h3, s, out=gd)
        gd += h2
        gd *= s
        gd += g1
        np.less_equal(np.abs(gd, out=gv), 1e-300, out=tiny)      # Newton's step guarded
        np.multiply(g3, s, out=gv)                      # g(s) = ((g3 s + g2) s + g1) s + g0
        gv += g2
        gv *= s
        gv += g1
        gv *= s
        gv += g0
        np.copyto(gd, 1e-300, where=tiny)
        np.divide(gv, gd, out=gv)
        np.subtract(s, gv, out=s)
        np.maximum(s, 0.0, out=s)                       # s clipped to [0, 1]
        np.minimum(s, 1.0, out=s)
    for c3, c2, c1, p, out in ((a3x, a2x, a1x, px, gv), (a3y, a2y, a1y, py, gd)):
        np.multiply(c3, s, out=out)                     # C(s) - p: the ray
        out += c2
        out *= s
        out += c1
        out *= s
        out -= p
    gv *= gv                                            # |C(s) - p| (no overflow:
    gd *= gd                                            # frame units, about 1)
    gv += gd
    return s, np.sqrt(gv, out=gv)

