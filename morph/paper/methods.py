"""The paper's eight ways of approximating one compatible convolution piece (Sec. 4,
Sec. 5.2), and its sampled error measures: a reproduction of the paper for
``--method`` and the benchmark, outside the import path of a sum (which runs
:data:`morph.subdivide.QAC_METHOD`).

Given a *compatible pair* C1(t), C2(s) (:mod:`morph.gauss`): both monotone in tangent
angle over the same angle range of less than 90 degrees.  The exact convolution piece is
(C1 * C2)(t) = C1(t) + C2(s(t)) with C2'(s(t)) parallel to C1'(t), pointing the same way
(Eqs. 2-4, 27).  When C1 and C2 turn the same way, s runs 0 -> 1 as t runs 0 -> 1;
otherwise (convex against concave) s runs 1 -> 0.

Every method maps a pair to ONE rational Bézier piece (an ``(m+1, 3)`` array of
homogeneous control points) parametrised by C1's t, and the one subdivision driver of
Algorithm 5.1 (:func:`morph.subdivide.subdivide_nodes`, level by level on batches of
sub-pairs) splits
the pair until the error is within tolerance: at the mid tangent angle for a measured
error (:func:`pair_method`), where the a-priori bound peaks for certified QAC, which
also chooses which piece plays C2 (:data:`QAC_METHOD`, Algorithm 4.1 of
:mod:`morph.qac`, the same pieces as :mod:`morph.convolve`).  Output degrees (Table 1;
d1, d2 the degrees of C1, C2, k the degree of the fitted reparametrization s(t)):

- ctc: C1's control points P_i moved by C2(s_i), s_i matching C1's normal at the
  Greville abscissae i/D (Eqs. 25-27).  Degree max(d1, d2) (C1 elevated to it first);
  rational iff C1 is.
- lsc: least-squares Bézier of ``degree`` (default 3) through 16 exact convolution
  points at uniform t (Eq. 28), end points interpolated.  Polynomial.
- bic: Bézier of ``degree`` (default 3) interpolating exact convolution points at
  t = i/degree (Eq. 28).  Polynomial.
- hic: cubic Hermite with exact end points and end tangents, ds/dt from Eq. 33.
  Polynomial, degree 3.
- qac: C1(t) + Q2(s(t)), Q2 the quadratic of Eq. 38 and s(t) of Eq. 36
  (:func:`morph.qac.convolve_qac_piece`).  Rational, degree 3 d1 - 2 for
  polynomial C1, 5 d1 - 4 for rational C1 (C1 the piece kept: certified QAC may
  keep C2 and replace C1 by a quadratic instead).
- lrc: C1(t) + C2(s0 + (s1 - s0) t) (Eq. 41).  Degree max(d1, d2) if both are
  polynomial, else d1 + d2 (rational), or max(d1, d2) when the two denominators are
  proportional (two circular arcs of equal sweep give a rational quadratic).
- tmc: unit tangents of both curves at 33 uniform parameters matched by dynamic
  programming (Eqs. 43-45, Alg. 4.2), a least-squares polynomial s(t) of degree k
  (``s_degree``, default 2) fitted to the matches, C1(t) + C2(s(t)) composed exactly.
- src: s_i solving Eq. 27 at 16 uniform t_i, least-squares polynomial s(t) of degree k
  (Eqs. 47-48, Alg. 4.3), composed the same way.
  tmc and src: degree max(d1, k d2) if both are polynomial, else d1 + k d2; k drops to
  1 (LRC's degrees) when the fitted s(t) is a straight line, e.g. on circular arcs.

The paper's Table 1 uses a *linear* s(t) for TMC and SRC (a piecewise linear B-spline
over N samples, Eq. 48), which gives LRC's degrees: cut into Bézier pieces that is LRC
on N - 1 uniform sub-pairs.  Here the piecewise refinement is the driver's job, so
TMC and SRC fit one polynomial s(t) of degree k >= 2 per sub-pair instead
(``s_degree``; k = 1 would make them identical to LRC).

Composition C2(s(t)) is exact Bernstein arithmetic (:func:`morph.bernstein.compose`):
with s(t) = sum b_j B_j^k(t), B_i^n(s(t)) = C(n, i) s(t)^i (1 - s(t))^(n-i) is a
product of Bernstein polynomials of degree n k, applied to the homogeneous control
points (so rational C2 works as is).  Eq. 27 (the parameter with a given tangent) is
solved by :func:`morph.gauss.angle_params`.

Error measures (Sec. 5.2), all *sampled*, none is a bound:

- :func:`distance_error` (Eqs. 49-53): one-sided Hausdorff distance from
  C~2(t) = A(t) - C1(t) to the curve C2, maximised over uniform samples of t and
  refined around the largest samples.  Zero by construction for LRC, TMC and SRC,
  whose C~2 runs along C2 itself (their "trace is exact").
- :func:`normal_error` (Eqs. 54-55): the angle between the tangent lines of C1(t) and
  of C~2(t) = A(t) - C1(t), in degrees, sampled the same way.  Zero for QAC (its
  tangent is parallel to C1' by construction, Eq. 56).  ``of="approximation"``
  measures A's own tangent instead (the normal error of the convolution curve).
- :func:`hausdorff_error` (not in the paper): one-sided Hausdorff distance from A to
  the exact convolution curve.  Equal to the distance measure to first order, and
  meaningful for LRC, TMC and SRC too; :func:`approximate` uses it for them.

Only QAC has an a-priori bound: the distance from Q2 to C2 (Eqs. 39-40, after a
reparametrisation: :func:`morph.qac.qac_error_bound`), used by default when QAC runs
under the distance measure (``certified=True``).
"""

import numpy as np

from .. import bernstein as bz
from .. import gauss
from .. import piece as pc
from .. import nearest as nr
from .. import qac
from ..errors import MorphError, ToleranceNotMetError
from ..subdivide import METHODS, QAC_METHOD, Method, _objects, subdivide, turning_sign

MEASURES = ("distance", "normal", "hausdorff")

LSC_SAMPLES = 16     # exact convolution points per LSC fit
TMC_SAMPLES = 33     # tangent samples per curve in the TMC dynamic programme
SRC_SAMPLES = 16     # s_i samples per SRC fit
S_DEGREE = 2         # degree k of the fitted s(t) in TMC and SRC
ERROR_SAMPLES = 65   # uniform samples of t per error evaluation (then refined)


# =============================================================== matching (Eq. 27)

def same_direction(c1, c2):
    """True when s increases with t (C1 and C2 turn the same way)."""
    return turning_sign(c1) == turning_sign(c2)


def _unit_tangents(piece, u):
    """Unit tangent directions of a piece at the parameters u (m, 2)."""
    v = bz.evaluate(pc.tangent_numerator(piece), u)
    return v / np.maximum(np.hypot(v[:, 0], v[:, 1]), 1e-300)[:, None]


def params_at_angles(piece, theta):
    """Parameters where the tangent of a monotone piece has the angles theta (Eq. 27):
    :func:`morph.gauss.angle_params` on the piece's tangent numerator, vectorised."""
    theta = np.atleast_1d(np.asarray(theta, float))
    h = pc.tangent_numerator(np.asarray(piece, float))
    return gauss.angle_params(np.broadcast_to(h, (len(theta),) + h.shape), theta)


def match_params(c1, c2, ts):
    """s(t) of the exact convolution: C2'(s) parallel to C1'(t), same way (Eq. 27).

    For t = 0 and t = 1 the pair's end correspondence is used (s = 0/1, or 1/0 for
    opposite turning); inside, ``gauss.angle_param(c2, piece.tangent_angle(c1, t))``,
    vectorised (:func:`params_at_angles`).
    """
    ts = np.atleast_1d(np.asarray(ts, float))
    forward = same_direction(c1, c2)
    hv = bz.evaluate(pc.tangent_numerator(c1), ts)
    s = params_at_angles(c2, np.arctan2(hv[:, 1], hv[:, 0]))
    s = np.where(ts <= 0.0, 0.0 if forward else 1.0, s)
    return np.where(ts >= 1.0, 1.0 if forward else 0.0, s)


def convolution_points(c1, c2, ts):
    """Exact convolution points C1(t) + C2(s(t)) (Eq. 28) and the s values."""
    s = match_params(c1, c2, ts)
    return pc.evaluate(c1, ts) + pc.evaluate(c2, s), s


def _angle_at(piece, u):
    """Tangent angle of a piece at the parameter u."""
    hv = bz.evaluate(pc.tangent_numerator(piece), [u])[0]
    return float(np.arctan2(hv[1], hv[0]))


def split_pair(c1, c2, balance=0.2):
    """Split a compatible pair at a common tangent direction (Algorithm 5.1, Line 2).

    The split direction is C1's mid tangent angle (halfway between its end tangent
    angles); t_m on C1 and s_m on C2 both have it (Eq. 27), so the two sub-pairs are
    again compatible.  Near an inflection at an end of one curve the tangent angle
    moves quadratically in the parameter, and a mid-angle split would leave almost
    all of that curve in one half (the pair then shrinks ever more slowly); so when
    s_m or t_m falls outside [balance, 1 - balance] it is clamped into that interval
    and the other curve's parameter is matched to the clamped one's tangent instead.
    Returns ``((c1a, c2a), (c1b, c2b), t_m, s_m)`` with the a-halves first along t.
    """
    a0, a1 = pc.end_tangents(c1)
    thm = np.arctan2(a0[1], a0[0]) + 0.5 * np.arctan2(pc.cross2(a0, a1), np.dot(a0, a1))
    tm = float(params_at_angles(c1, thm)[0])
    sm = float(params_at_angles(c2, thm)[0])
    if not balance <= sm <= 1.0 - balance:
        sm = min(max(sm, balance), 1.0 - balance)
        tm = float(params_at_angles(c1, _angle_at(c2, sm))[0])
    if not balance <= tm <= 1.0 - balance:
        tm = min(max(tm, balance), 1.0 - balance)
        sm = float(params_at_angles(c2, _angle_at(c1, tm))[0])
    c1a, c1b = pc.split(c1, tm)
    c2lo, c2hi = pc.split(c2, sm)
    if same_direction(c1, c2):
        return (c1a, c2lo), (c1b, c2hi), tm, sm
    return (c1a, c2hi), (c1b, c2lo), tm, sm


# ============================================================ symbolic arithmetic

# ============================================================ symbolic arithmetic

def _homogeneous_parts(piece):
    """(X, W) with W of degree 0 for a polynomial piece, else the piece's columns."""
    piece = np.asarray(piece, float)
    if pc.is_polynomial(piece):
        return pc.cartesian(piece), np.ones((1, 1))
    return piece[:, :2], piece[:, 2:3]


def add_pieces(a, b):
    """The piece a(t) + b(t) of two pieces on the same parameter, exactly.

    Polynomial + polynomial: degree max.  Otherwise X_a W_b + X_b W_a over W_a W_b
    (degree sum), except when the denominators are proportional (W_b = c W_a), where
    the sum keeps the common denominator and degree max (two circular arcs of equal
    sweep: a rational quadratic again).
    """
    xa, wa = _homogeneous_parts(a)
    xb, wb = _homogeneous_parts(b)
    if len(wa) == 1 and len(wb) == 1:
        n = max(len(xa), len(xb)) - 1
        x = bz.to_degree(xa, n) + bz.to_degree(xb, n)
        return np.column_stack([x, np.ones(n + 1)])
    if len(wa) > 1 and len(wb) > 1:
        n = max(len(wa), len(wb)) - 1
        wae, wbe = bz.to_degree(wa, n), bz.to_degree(wb, n)
        ratio = wbe[:, 0] / wae[:, 0]
        if np.all(np.abs(ratio - ratio[0]) <= 1e-13 * abs(ratio[0])):
            x = bz.to_degree(xa, n) + bz.to_degree(xb, n) / ratio[0]
            return np.column_stack([x, wae])
    xab, xba, w = bz.multiply(xa, wb), bz.multiply(xb, wa), bz.multiply(wa, wb)
    n = max(len(xab), len(xba), len(w)) - 1
    x = bz.to_degree(xab, n) + bz.to_degree(xba, n)
    return np.column_stack([x, bz.to_degree(w, n)])




def reparametrized_sum(c1, c2, s_coeffs):
    """C1(t) + C2(s(t)) exactly (Sec. 4.4), s(t) a Bernstein polynomial in t.

    C2(s(t)) is the exact composition :func:`morph.bernstein.compose` on C2's
    homogeneous control points (degree n k for C2 of degree n, s of degree k; a
    rational C2 composes as is), then :func:`add_pieces`.
    """
    s = np.asarray(s_coeffs, float)
    if len(s) == 2 and s[0] == 0.0 and s[1] == 1.0:
        c2s = np.asarray(c2, float)
    elif len(s) == 2 and s[0] == 1.0 and s[1] == 0.0:
        c2s = pc.reverse(c2)
    else:
        c2s = bz.compose(c2, s)
    if pc.is_polynomial(c2s):
        c2s = np.column_stack([pc.cartesian(c2s), np.ones(len(c2s))])
    return add_pieces(c1, c2s)


def _fit_s(t, s, k, s0, s1):
    """Least-squares Bernstein polynomial of degree k with s(0)=s0, s(1)=s1.

    Coefficients are clipped to [0, 1] so s(t) stays in C2's domain (convex hull), and a
    fit within 1e-12 of the straight line is returned as the line itself (degree 1).
    """
    if k <= 1:
        return np.array([s0, s1])
    b = np.clip(bz.fit_fixed_ends(t, s, k, s0, s1), 0.0, 1.0)
    line = bz.elevate(np.array([s0, s1]), k - 1)
    if np.max(np.abs(b - line)) <= 1e-12:
        return np.array([s0, s1])
    return b


def _ends(c1, c2):
    return (0.0, 1.0) if same_direction(c1, c2) else (1.0, 0.0)


# ================================================================ the eight methods

def ctc_piece(c1, c2):
    """CTC (Sec. 4.1, Eqs. 25-27): C1's control points translated by C2(s_i).

    C1 is first elevated to D = max(d1, d2); the Greville abscissa of control point i of
    a Bézier is xi_i = i / D, and s_i has C2's tangent parallel to C1'(xi_i).  A rational
    C1 keeps its weights: (w_i (P_i + C2(s_i)), w_i).  Degree max(d1, d2).
    """
    c1 = np.asarray(c1, float)
    big = max(len(c1), len(c2)) - 1
    c1e = pc.elevate(c1, big - (len(c1) - 1))
    xi = np.arange(big + 1) / big                      # Eq. 25 for a single Bézier span
    s = match_params(c1, c2, xi)                       # Eqs. 26-27
    return _translate_each(c1e, pc.evaluate(c2, s))


def _translate_each(piece, offsets):
    """Each homogeneous control point moved by its own offset (weights kept)."""
    out = np.array(piece, float)
    out[:, :2] += offsets * out[:, 2:3]
    return out


def _bezier_fit(ts, pts, degree):
    """Polynomial Bézier of a degree with both ends interpolated, least squares inside."""
    ctrl = bz.fit_fixed_ends(ts, pts, degree, pts[0], pts[-1])
    return np.column_stack([ctrl, np.ones(degree + 1)])


def lsc_piece(c1, c2, degree=3, samples=LSC_SAMPLES):
    """LSC (Sec. 4.2.1, Eq. 28): least-squares Bézier through sampled convolution points.

    ``samples`` exact points C1(t_k) + C2(s_k) at uniform t_k = k / (samples - 1); the
    end points are interpolated (so consecutive pieces join), the inner control points
    minimise sum_k |A(t_k) - (C1 * C2)(t_k)|^2.  Polynomial, degree ``degree``.
    """
    ts = np.linspace(0.0, 1.0, samples)
    pts, _ = convolution_points(c1, c2, ts)
    return _bezier_fit(ts, pts, degree)


def bic_piece(c1, c2, degree=3):
    """BIC (Sec. 4.2.1, Eq. 28): Bézier interpolating convolution points at t = i/degree.

    The Bernstein collocation matrix at distinct nodes is invertible, so the piece is
    unique.  Polynomial, degree ``degree``.
    """
    ts = np.linspace(0.0, 1.0, degree + 1)
    pts, _ = convolution_points(c1, c2, ts)
    ctrl = np.linalg.solve(bz.basis(degree, ts), pts)
    return np.column_stack([ctrl, np.ones(degree + 1)])


def convolution_speed(c1, c2, ts, ss):
    """ds/dt of the exact reparametrization (Eqs. 31-33).

    Differentiating cross(C1'(t), C2'(s(t))) = 0 gives
    s'(t) = -cross(C1''(t), C2'(s)) / cross(C1'(t), C2''(s)).
    """
    d1 = pc.derivative(c1, ts)
    dd1 = pc.second_derivative(c1, ts)
    d2 = pc.derivative(c2, ss)
    dd2 = pc.second_derivative(c2, ss)
    with np.errstate(divide="ignore", invalid="ignore"):
        return -pc.cross2(dd1, d2) / pc.cross2(d1, dd2)


def hic_piece(c1, c2):
    """HIC (Sec. 4.2.2, Eqs. 30-33): cubic Hermite with exact ends and end tangents.

    (C1 * C2)'(t) = C1'(t) + C2'(s) s'(t) with s'(t) of Eq. 33.  Where that is not
    finite (zero curvature of C2 at an end: s' is infinite) the end tangent falls back
    to C1's direction with the chord length as magnitude.  Polynomial cubic.
    """
    ts = np.array([0.0, 1.0])
    pts, ss = convolution_points(c1, c2, ts)
    sp = convolution_speed(c1, c2, ts, ss)
    tan = pc.derivative(c1, ts) + pc.derivative(c2, ss) * sp[:, None]   # Eq. 30
    chord = float(np.hypot(*(pts[1] - pts[0])))
    u0, u1 = pc.end_tangents(c1)
    for k, u in ((0, u0), (1, u1)):
        if not np.all(np.isfinite(tan[k])) or np.hypot(*tan[k]) > 1e3 * max(chord, 1e-300):
            tan[k] = u * chord
    ctrl = np.array([pts[0], pts[0] + tan[0] / 3, pts[1] - tan[1] / 3, pts[1]])
    return np.column_stack([ctrl, np.ones(4)])


def qac_piece(c1, c2):
    """QAC (Sec. 4.4, Eqs. 34-38): C1(t) + Q2(s(t)), see :func:`morph.qac.convolve_qac_piece`.

    The paper's one piece, C2 replaced by its quadratic.  Degree 3 d1 - 2 for
    polynomial C1, 5 d1 - 4 for rational C1; normals exact.  The certified driver
    (:data:`QAC_METHOD`) also chooses which piece plays C2 (Sec. 4.4).
    """
    return qac.convolve_qac_piece(c1, c2)


def lrc_piece(c1, c2):
    """LRC (Sec. 4.4.1, Eq. 41): C1(t) + C2(s0 + (s1 - s0) t), no fitting at all.

    Trace exact (C~2 runs on C2).  Degree max(d1, d2) for two polynomials, d1 + d2 if
    either is rational (max(d1, d2) when the denominators are proportional).
    """
    s0, s1 = _ends(c1, c2)
    return reparametrized_sum(c1, c2, np.array([s0, s1]))


def tangent_field_matching(c1, c2, samples=TMC_SAMPLES):
    """Discrete tangent field matching (Cohen et al.; Eqs. 43-45), by dynamic programming.

    Both curves are sampled at ``samples`` uniform parameters; unit tangents T1_i, T2_j.
    Maximise sum_i <T1_i, T2_j(i)> subject to j(0) = 0, j(N-1) = N-1 and
    j(i) <= j(i+1) (Eq. 45), in O(N^2): best[i, j] = <T1_i, T2_j> + max_{j' <= j}
    best[i-1, j'].  C2's samples are taken in matching order (reversed for opposite
    turning).  Returns (t_i, s_j(i)).
    """
    n = samples
    ts = np.linspace(0.0, 1.0, n)
    s0, s1 = _ends(c1, c2)
    ss = np.linspace(s0, s1, n)

    sim = _unit_tangents(c1, ts) @ _unit_tangents(c2, ss).T            # <T1_i, T2_j>, Eq. 44
    best = np.full(n, -np.inf)
    best[0] = sim[0, 0]                            # j(0) = 0
    back = np.zeros((n, n), dtype=int)
    idx = np.arange(n)
    for i in range(1, n):
        run = np.maximum.accumulate(best)
        arg = np.maximum.accumulate(np.where(best == run, idx, 0))
        back[i] = arg
        best = sim[i] + run
    j = np.empty(n, dtype=int)
    j[-1] = n - 1                                  # j(N-1) = N-1
    for i in range(n - 1, 0, -1):
        j[i - 1] = back[i, j[i]]
    return ts, ss[j]


def tmc_piece(c1, c2, s_degree=S_DEGREE, samples=TMC_SAMPLES):
    """TMC (Sec. 4.4.2, Alg. 4.2): s(t) from tangent field matching, composed exactly.

    The matched pairs of :func:`tangent_field_matching` are fitted by a polynomial s(t)
    of degree ``s_degree`` (least squares, ends fixed); C1(t) + C2(s(t)) is then exact
    Bernstein composition.  Trace exact.  Degree: see the module table.
    """
    t, s = tangent_field_matching(c1, c2, samples)
    s0, s1 = _ends(c1, c2)
    return reparametrized_sum(c1, c2, _fit_s(t, s, s_degree, s0, s1))


def src_piece(c1, c2, s_degree=S_DEGREE, samples=SRC_SAMPLES):
    """SRC (Sec. 4.4.3, Eqs. 47-48, Alg. 4.3): sampled s_i fitted by a polynomial s(t).

    s_i solves Eq. 27 at ``samples`` uniform t_i; s(t) is the least-squares polynomial
    of degree ``s_degree`` with the ends fixed; C1(t) + C2(s(t)) by exact composition.
    Trace exact.  Degree: see the module table.
    """
    t = np.linspace(0.0, 1.0, samples)
    s = match_params(c1, c2, t)
    s0, s1 = _ends(c1, c2)
    return reparametrized_sum(c1, c2, _fit_s(t, s, s_degree, s0, s1))


ONE_PIECE = {
    "ctc": ctc_piece, "lsc": lsc_piece, "bic": bic_piece, "hic": hic_piece,
    "qac": qac_piece, "lrc": lrc_piece, "tmc": tmc_piece, "src": src_piece,
}


def output_degree(method, d1, d2, rational1=False, rational2=False, degree=3,
                  s_degree=S_DEGREE):
    """Degree of one output piece (Table 1), before any simplification.

    Simplifications can only lower it: LRC/TMC/SRC with proportional denominators
    (max instead of sum) and TMC/SRC with a fitted s(t) that is linear (k = 1).
    """
    rational = rational1 or rational2
    if method == "ctc":
        return max(d1, d2)
    if method in ("lsc", "bic"):
        return degree
    if method == "hic":
        return 3
    if method == "qac":
        return 5 * d1 - 4 if rational1 else 3 * d1 - 2
    k = 1 if method == "lrc" else s_degree
    if method in ("lrc", "tmc", "src"):
        return d1 + k * d2 if rational else max(d1, k * d2)
    raise ValueError("unknown method %r (one of %s)" % (method, ", ".join(METHODS)))


# ================================================================ error measures

def _sampled_max(f, n, zooms=2, zoom_samples=17, candidates=2):
    """max over t in [0, 1] of a vectorised f, sampled at n points then refined.

    The largest ``candidates`` local maxima among the samples are re-sampled at
    ``zoom_samples`` points on their neighbouring intervals, ``zooms`` times (each zoom
    narrows the spacing by (zoom_samples - 1) / 2).  A sampled estimate from below,
    not a bound.  Returns (value, t).
    """
    t = np.linspace(0.0, 1.0, n)
    v = np.asarray(f(t), float)
    v = np.where(np.isnan(v), np.inf, v)
    best = int(np.argmax(v))
    vbest, tbest = float(v[best]), float(t[best])
    if not np.isfinite(vbest):
        return vbest, tbest
    peaks = np.flatnonzero((v[1:-1] >= v[:-2]) & (v[1:-1] >= v[2:])) + 1
    peaks = peaks[np.argsort(v[peaks])[::-1][:candidates]]
    centres, half = t[peaks], 1.0 / (n - 1)
    u = np.linspace(-1.0, 1.0, zoom_samples)
    for _ in range(zooms):
        if centres.size == 0:
            break
        tt = np.clip(centres[:, None] + half * u[None, :], 0.0, 1.0).ravel()
        vv = np.asarray(f(tt), float).reshape(len(centres), zoom_samples)
        k = np.argmax(vv, axis=1)
        centres = tt.reshape(len(centres), zoom_samples)[np.arange(len(centres)), k]
        top = int(np.argmax(vv.max(axis=1)))
        if vv[top].max() > vbest:
            vbest, tbest = float(vv[top].max()), float(centres[top])
        half *= 2.0 / (zoom_samples - 1)
    return vbest, tbest


def _curve_distance(curve, samples=33, newton=4):
    """q -> distances to the piece: the nearest of ``samples`` uniform samples, then
    ``newton`` Newton steps to the foot point (:func:`morph.nearest.closest_params_many`);
    the smaller of the sampled and the refined distance."""
    c = np.asarray(curve, float)
    us = np.linspace(0.0, 1.0, samples)
    cs = pc.evaluate(c, us)

    def dist(q):
        q = np.atleast_2d(q)
        d2 = np.sum((q[:, None, :] - cs[None, :, :]) ** 2, axis=2)
        i = np.argmin(d2, axis=1)
        dmin = np.sqrt(d2[np.arange(len(q)), i])
        u = nr.closest_params_many(c[None], q[None], us[i][None], newton)[0]
        return np.minimum(dmin, np.hypot(*(pc.evaluate(c, u) - q).T))

    return dist


def distance_error(approx, c1, c2, n=ERROR_SAMPLES):
    """Distance measure of Sec. 5.2 (Eqs. 49-53), sampled: not a bound.

    C~2(t) = A(t) - C1(t) lies on C2 for the exact convolution (Eq. 50); the error is
    max_t min_s |C~2(t) - C2(s)|, the one-sided Hausdorff distance from C~2 to the
    curve C2, taken at n uniform t (and refined near the largest samples, see
    :func:`_sampled_max`) with the inner minimum by sampling + Newton.  In input units.
    """
    dist = _curve_distance(c2)

    def f(t):
        return dist(pc.evaluate(approx, t) - pc.evaluate(c1, t))

    return _sampled_max(f, n)[0]


def hausdorff_error(approx, c1, c2, n=ERROR_SAMPLES, samples=65, iterations=10):
    """Distance from the approximation to the exact convolution curve, sampled.

    max_t min_u |A(t) - K(u)|, K(u) = C1(u) + C2(s(u)) the exact convolution piece
    (Eq. 27 solved for s): the one-sided Hausdorff distance from A to K, at n uniform
    t refined near the largest samples (not a bound).  The inner minimum: K sampled at
    ``samples`` uniform u; the foot point solves g(u) = (K(u) - q)·T1(u) = 0, T1 the
    unit tangent of C1 (K' is parallel to it, Eq. 30), found by the Illinois method on
    the sign change next to the nearest sample (no derivative of K: s'(u) is infinite
    where C2 has an inflection, Eq. 33).  Without a sign change there the nearest
    sample's distance is used.

    To first order this equals :func:`distance_error` (the normals of C2 at s(u) and
    of K at u are parallel), but unlike that measure it is not zero for LRC, TMC and
    SRC: a point C1(t) + C2(s~) with s~ != s(t) lies off the convolution curve.
    """
    us = np.linspace(0.0, 1.0, samples)
    ks = convolution_points(c1, c2, us)[0]
    ts_ = _unit_tangents(c1, us)

    def f(t):
        q = pc.evaluate(approx, t)
        m = len(q)
        diff = ks[None, :, :] - q[:, None, :]
        dist = np.hypot(diff[..., 0], diff[..., 1])
        g = np.sum(diff * ts_[None], axis=2)
        rows = np.arange(m)
        i = np.argmin(dist, axis=1)
        # candidates: the nearest sample and K(t) itself (A is parametrised like K)
        best = np.minimum(dist[rows, i], np.hypot(*(convolution_points(c1, c2, t)[0] - q).T))
        # bracket: the sign change of g next to the nearest sample, if any
        left = (i > 0) & (g[rows, np.maximum(i - 1, 0)] * g[rows, i] <= 0)
        right = (i < samples - 1) & (g[rows, i] * g[rows, np.minimum(i + 1, samples - 1)] <= 0)
        ok = left | right
        ja = np.where(left, i - 1, i)
        jb = np.where(left, i, np.minimum(i + 1, samples - 1))
        a, b = us[ja], us[jb]
        ga, gb = g[rows, ja], g[rows, jb]
        for _ in range(iterations):
            with np.errstate(divide="ignore", invalid="ignore"):
                c = np.where(gb != ga, b - gb * (b - a) / (gb - ga), 0.5 * (a + b))
            c = np.where(np.isfinite(c) & (c >= np.minimum(a, b)) & (c <= np.maximum(a, b)),
                         c, 0.5 * (a + b))
            kc = convolution_points(c1, c2, c)[0]
            gc = np.sum((kc - q) * _unit_tangents(c1, c), axis=1)
            best = np.where(ok, np.minimum(best, np.hypot(*(kc - q).T)), best)
            same = gc * gb > 0                      # replace b, halve ga (Illinois)
            a, ga, b, gb = (np.where(same, a, b), np.where(same, 0.5 * ga, gb),
                            c, gc)
        return best

    return _sampled_max(f, n)[0]


def normal_error(approx, c1, n=ERROR_SAMPLES, of="difference"):
    """Normal deviation of Sec. 5.2 (Eqs. 54-55) in degrees, sampled: not a bound.

    of="difference" (the paper's measure): delta(t) = <C1'(t), N~2(t)>^2 /
    (|C1'|^2 |N~2|^2) with N~2 a normal of C~2(t) = A(t) - C1(t); the error is
    max_t |pi/2 - arccos sqrt(delta(t))|, the angle between the tangent lines of C1 and
    C~2 (as Eq. 46 for TMC).  It is ill-conditioned where C~2 is stationary: at an end
    of a pair where C1 has an inflection, s'(t) = 0 (Eq. 33), the exact C~2' vanishes
    and any approximation's C~2' there has an arbitrary direction.
    of="approximation": the angle between the tangent lines of A(t) itself and of
    C1(t), i.e. the normal error of the convolution curve (the exact one has C1's
    normal at t).  Never larger than the difference measure when C1' and C~2' point
    the same way, and well conditioned at inflections.

    Sampled at n uniform t, refined near the largest samples.  Where a tangent
    vanishes the angle counts as 0.
    """
    if of not in ("difference", "approximation"):
        raise ValueError("of must be 'difference' or 'approximation', got %r" % (of,))

    def f(t):
        d1 = pc.derivative(c1, t)
        d2 = pc.derivative(approx, t)
        if of == "difference":
            d2 = d2 - d1
        return np.degrees(np.arctan2(np.abs(pc.cross2(d1, d2)), np.abs(np.sum(d1 * d2, axis=1))))

    return _sampled_max(f, n)[0]


def qac_bound(c2):
    """A-priori bound of QAC's distance error with C2 replaced by its quadratic:
    :func:`morph.qac.qac_error_bound` (Eqs. 39-40, reparametrised)."""
    return qac.qac_error_bound(c2, qac.quadratic_approximation(c2))[0]


def _valid(piece):
    piece = np.asarray(piece, float)
    return bool(np.all(np.isfinite(piece)) and np.all(piece[:, 2] > 0))


def _measured(piece_fn, error_fn, a, b):
    """(piece, error) of one sub-pair; (None, inf) where the method fails on it."""
    try:
        piece = piece_fn(a, b)
    except (ValueError, MorphError):      # e.g. QAC: parallel end tangents
        return None, np.inf
    if piece is None or not _valid(piece):
        return None, np.inf
    return piece, float(error_fn(piece, a, b))


def _pair_root(c1, c2):
    """The root node of a pair for :func:`pair_method`'s callables (id 1; the
    children of node i are 2i and 2i + 1)."""
    return {"ca": np.asarray(c1, float)[None], "cb": np.asarray(c2, float)[None],
            "t0": np.zeros(1), "t1": np.ones(1), "id": np.ones(1, np.int64)}


def _split_or_raise(a, b, err, tol):
    """:func:`split_pair`; ToleranceNotMetError where the pair cannot be split."""
    try:
        left, right, tm, _ = split_pair(a, b)
    except MorphError as exc:             # a sub-pair too small to turn
        raise ToleranceNotMetError(
            "error %g above tolerance %g, pair cannot be split further (%s)"
            % (err, tol, exc), piece=(a, b), achieved=err) from exc
    return left, right, tm


def pair_method(piece_fn, error_fn, memo=None):
    """The :class:`Method` of a one-pair approximation ``piece_fn(c1, c2) -> piece``
    measured by ``error_fn(piece, c1, c2) -> float``, node by node.

    The piece is built and measured in ``bound`` (a piece with non-positive weights
    or non-finite entries, or a method raising ValueError or MorphError, counts as
    infinite error); pairs are split by :func:`split_pair` (C1 at its mid tangent
    angle, C2 at the matching s).  ``memo`` (a dict, optional) keeps every visited
    node (piece, error, children) by its position in the tree; reuse it only for the
    same pair and method, to sweep tolerances cheaply.
    """
    memo = {} if memo is None else memo

    def bound(nodes, tol):
        k = len(nodes["id"])
        pieces, err = _objects([None] * k), np.empty(k)
        for r, key in enumerate(nodes["id"].tolist()):
            if key not in memo:
                memo[key] = [*_measured(piece_fn, error_fn, nodes["ca"][r], nodes["cb"][r]), None]
            pieces[r], err[r] = memo[key][:2]
        nodes.update(piece=pieces, err=err, tol=np.full(k, tol))
        return err, np.full(k, 0.5)

    def split(nodes, where):
        kids = []
        for r, key in enumerate(nodes["id"].tolist()):
            node = memo[key]
            if node[2] is None:
                node[2] = _split_or_raise(nodes["ca"][r], nodes["cb"][r], nodes["err"][r],
                                          nodes["tol"][r])
            kids.append(node[2])
        t0, t1 = nodes["t0"], nodes["t1"]
        tm = t0 + np.array([kid[2] for kid in kids]) * (t1 - t0)
        halves = []
        for side, (a, b) in enumerate(((t0, tm), (tm, t1))):
            halves.append({"ca": np.array([kid[side][0] for kid in kids]),
                           "cb": np.array([kid[side][1] for kid in kids]),
                           "t0": a, "t1": b, "id": 2 * nodes["id"] + side})
        return halves

    return Method(_pair_root, lambda nodes: list(nodes["piece"]), bound, split,
                  lambda nodes, r: (nodes["ca"][r], nodes["cb"][r]))


def method_functions(method, measure="distance", certified=True, n=ERROR_SAMPLES,
                     normal_of="difference", memo=None, **options):
    """The :class:`Method` of a method name and measure, for :func:`subdivide`.

    options go to the method (``degree`` for lsc/bic, ``s_degree``/``samples`` for
    tmc/src, ``samples`` for lsc).  QAC under the distance (or hausdorff) measure
    with ``certified`` is :data:`QAC_METHOD` (its a-priori bound, Eqs. 39-40, the
    default QAC of :mod:`morph.convolve`); otherwise QAC is the paper's one piece
    C1 + Q2 measured like the other methods (Sec. 5.2.3's fair comparison).
    ``normal_of`` selects the normal measure's curve (see :func:`normal_error`);
    ``memo``: see :func:`pair_method` (not used by certified QAC).
    """
    key = str(method).lower()
    if key not in ONE_PIECE:
        raise ValueError("unknown method %r (one of %s)" % (method, ", ".join(METHODS)))
    if measure not in MEASURES:
        raise ValueError("measure must be one of %s, got %r" % (MEASURES, measure))
    if key == "qac" and certified and measure in ("distance", "hausdorff"):
        return QAC_METHOD
    base = ONE_PIECE[key]
    one_piece = (lambda a, b: base(a, b, **options)) if options else base
    if measure == "normal":
        error = lambda piece, a, b: normal_error(piece, a, n, normal_of)  # noqa: E731
    elif measure == "hausdorff":
        error = lambda piece, a, b: hausdorff_error(piece, a, b, n)  # noqa: E731
    else:
        error = lambda piece, a, b: distance_error(piece, a, b, n)  # noqa: E731
    return pair_method(one_piece, error, memo)


def pair_measure(method):
    """The distance measure :func:`approximate` uses for a method by default: the
    paper's distance (Eqs. 49-53), or for "lrc", "tmc", "src", whose paper distance is
    0 by construction, the sampled distance to the exact convolution curve."""
    return "hausdorff" if str(method).lower() in ("lrc", "tmc", "src") else "distance"


def approximate(c1, c2, method="qac", tol=None, measure=None, max_angle_deg=None,
                certified=True, max_depth=24, normal_of="difference", memo=None, **options):
    """Approximate the convolution of a compatible pair by one of the eight methods:
    Algorithm 5.1 (:func:`morph.subdivide.subdivide`), a list of
    :class:`morph.subdivide.ConvPiece` in C1's parameter order and direction, each
    parametrised by its sub-pair's t (for certified QAC, by the t of the sub-pair's
    piece it keeps), consecutive pieces sharing end points.

    ``method`` in ``METHODS``.  The limit is either a distance ``tol`` (absolute, in
    input units) under ``measure``:

    - "distance": the paper's sampled max_t dist(P(t) - C1(t), C2) (Eqs. 49-53);
      for QAC with ``certified`` its a-priori bound max |C2 - Q2| (Eqs. 39-40, the
      only bound; normals exact);
    - "hausdorff": the sampled distance from P to the exact convolution curve
      (:func:`hausdorff_error`; QAC with ``certified`` uses its bound);
    - None (default): :func:`pair_measure` (the paper's distance is 0 for LRC, TMC
      and SRC, whose trace is exact);

    or an angle ``max_angle_deg`` (degrees): the sampled normal deviation (Eqs. 54-55,
    measure "normal"; ``normal_of`` = "difference", the paper's, or "approximation",
    see :func:`normal_error`).  ``options`` go to the method (``degree``;
    ``s_degree``, ``samples``); ``memo``: see :func:`pair_method`.

    Raises ValueError for an unknown method or measure, a limit not given once or
    not positive, DegenerateCurveError for a straight input, ToleranceNotMetError
    after ``max_depth`` halvings.
    """
    key = str(method).lower()
    if (tol is None) == (max_angle_deg is None):
        raise ValueError("give one limit: tol (a distance) or max_angle_deg (an angle)")
    if max_angle_deg is not None:
        if measure not in (None, "normal"):
            raise ValueError("max_angle_deg limits the normal measure, not %r" % (measure,))
        measure, limit = "normal", float(max_angle_deg)
    else:
        if measure == "normal":
            raise ValueError("the normal measure is an angle: give max_angle_deg, not tol")
        measure, limit = measure or pair_measure(key), float(tol)
    m = method_functions(key, measure, certified, normal_of=normal_of, memo=memo, **options)
    return subdivide(c1, c2, m, limit, max_depth, kind=key)


def control_point_count(pieces):
    """Control points of the pieces as one C0 chain: sum of degrees + 1 (joints shared)."""
    return int(sum(len(p) - 1 for p in pieces)) + 1 if pieces else 0
