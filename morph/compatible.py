"""Untrimmed convolutions with elliptical nibs, fitted compatibly across masters.

For a convex nib B and a region A (or a skeleton path traced forward and back), the
convolution curve of A's boundary and B winds zero or more times around every point,
and A ⊕ B is exactly the set where it winds at least once (Guibas, Ramshaw, Stolfi
1983).  Fonts fill by the nonzero rule, so the untrimmed convolution written as
overlapping contours renders as the sum: no trimming, and so no structure that
depends on the nib.  This module builds such convolutions for *several masters at
once* (skeleton or glyph masters of one structure, each with its own ellipse) so that
every master has the same number of contours and cubic segments: the masters are
point-compatible by construction and a variable font interpolates them.

Construction (an ellipse is smooth and strictly convex, so every boundary normal n
has one nib point e(n), the support point):

- each source piece c(t) pairs with the nib point of the same outward normal:
  x(t) = c(t) + e(n(t)), n the right-hand normal of the travel direction;
- at a corner (the travel direction turns by theta, |theta| < pi) the nib arc
  between the two normals is inserted, traversed forwards for a left turn and
  backwards for a right turn (the convolution's reflex-vertex rule); a path's two
  ends turn by +pi (exact nib caps);
- every piece is split at the union of all masters' inflections, and the nib part
  E(s) = e(n(s)) of every master is fitted by cubic Hermite segments with the *same
  breaks*: a break is accepted when every master's fit is within ``tol`` at the
  sample parameters (:data:`SAMPLES` per segment, compared at equal parameter, an
  upper bound of the distance between the curves' points);
- the output cubic of a segment is c restricted to the segment (exact) plus the
  Hermite cubic of E: the only approximation is the fit of E.

A uniform nib scale is exact along an axis: e_s(n) = s e_1(n), the Hermite data is
linear in e, so the masters' cubics are c + s H_1 and interpolating them is the
convolution with the interpolated nib (to the fit's tolerance), with no
intermediate master.  Aspect, angle and source-master changes do not interpolate
exactly: :func:`interpolation_error` measures the support points' error of a
linear blend between two nibs, from which the intermediate masters are chosen.

Everything is in the caller's units (font units); loops are lists of cubics,
``(k, 4, 2)`` float arrays, positively oriented (counter-clockwise, y up).
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .errors import MorphError

__all__ = ["Ellipse", "Element", "IncompatibleMasters", "skeleton_elements",
           "region_elements", "fit_elements", "convolve_masters", "interpolation_error",
           "blend_nib", "SAMPLES"]

#: interior sample parameters per fitted segment at which every master's error is
#: measured (equal parameter: an upper bound of the point distance there)
SAMPLES = 24

#: a path turning back on itself by more than pi - this angle at a join is cut there
#: (its two parts are stroked apart, their sums unite to the path's), as
#: :func:`morph.stroke.stroke_paths` does: the cap direction of a full reversal is
#: ambiguous
REVERSAL = 1e-3

_MAX_DEPTH = 40


class IncompatibleMasters(MorphError, ValueError):
    """The masters' paths differ in structure (``.what`` says how)."""

    def __init__(self, message, what=None):
        super().__init__(message)
        self.what = what


class Ellipse(NamedTuple):
    """An elliptical nib centred on the pen point: ``width`` x ``height`` (font
    units), long axis turned by ``angle`` degrees counter-clockwise."""

    width: float
    height: float
    angle: float = 0.0

    def matrix(self):
        """M with nib = M (unit disk)."""
        a = np.radians(self.angle)
        c, s = np.cos(a), np.sin(a)
        return np.array([[c, -s], [s, c]]) @ np.diag([self.width / 2.0, self.height / 2.0])

    def support(self, normals):
        """The nib points with outward normals ``normals`` (``(..., 2)``, any length):
        e(n) = M Mᵀ n / |Mᵀ n|."""
        m = self.matrix()
        v = np.asarray(normals, float) @ m             # Mᵀ n as rows
        return (v / np.linalg.norm(v, axis=-1, keepdims=True)) @ m.T

    def extent(self):
        """(xmin, ymin, xmax, ymax) of the nib, exact."""
        m = self.matrix()
        hx, hy = np.linalg.norm(m[0]), np.linalg.norm(m[1])
        return (-hx, -hy, hx, hy)


def blend_nib(a, b, u):
    """The nib a fraction ``u`` of the way from ``a`` to ``b``: width, height and
    angle each interpolated linearly (how a nib axis defines its instances)."""
    return Ellipse(*(float((1.0 - u) * x + u * y) for x, y in zip(a, b)))


def interpolation_error(a, b, normals=720, steps=16):
    """Max distance between the linear blend of the support points of nibs ``a`` and
    ``b`` and the support points of the blended nib, over ``normals`` directions and
    ``steps`` interior fractions: what a master pair at ``a`` and ``b`` costs an
    instance between them (0 when b is a uniform scale of a)."""
    ang = np.linspace(0.0, 2 * np.pi, normals, endpoint=False)
    n = np.column_stack([np.cos(ang), np.sin(ang)])
    ea, eb = a.support(n), b.support(n)
    worst = 0.0
    for u in np.linspace(0.0, 1.0, steps + 2)[1:-1]:
        d = (1 - u) * ea + u * eb - blend_nib(a, b, u).support(n)
        worst = max(worst, float(np.linalg.norm(d, axis=1).max()))
    return worst


# ----------------------------------------------------------------- Bézier helpers

def _bezier(ctrl, t):
    """Points of Bézier curves ``ctrl`` (..., n+1, 2) at parameters t (k,) ->
    (..., k, 2), de Casteljau."""
    t = np.asarray(t, float)[:, None]
    pts = [np.asarray(ctrl, float)[..., i, None, :] for i in range(ctrl.shape[-2])]
    while len(pts) > 1:
        pts = [(1 - t) * p + t * q for p, q in zip(pts[:-1], pts[1:])]
    return np.broadcast_to(pts[0], pts[0].shape[:-2] + (len(t), 2))


def _hodograph(ctrl):
    n = ctrl.shape[-2] - 1
    return n * (ctrl[..., 1:, :] - ctrl[..., :-1, :])


def _subcurve(ctrl, a, b):
    """Control points of the Bézier ``ctrl`` (n+1, 2) restricted to [a, b] (blossom)."""
    n = len(ctrl) - 1
    out = []
    for k in range(n + 1):
        pts = [np.asarray(p, float) for p in ctrl]
        for j in range(n):
            t = b if j < k else a
            pts = [(1 - t) * p + t * q for p, q in zip(pts[:-1], pts[1:])]
        out.append(pts[0])
    return np.array(out)


def _to_cubic(ctrl):
    """Degree-elevate a line or quadratic (exact) to a cubic."""
    ctrl = np.asarray(ctrl, float)
    while len(ctrl) < 4:
        n = len(ctrl) - 1
        i = np.arange(1, n + 1)[:, None] / (n + 1)
        mid = i * ctrl[:-1] + (1 - i) * ctrl[1:]
        ctrl = np.vstack([ctrl[:1], mid, ctrl[-1:]])
    return ctrl


def _tangents(ctrl, t):
    """Unit tangents of Bézier curves (M, n+1, 2) at t (k,) -> (M, k, 2); where the
    derivative vanishes (a handle on its end point) the parameter is moved 1e-9
    inside [0, 1] to get the limit direction."""
    t = np.asarray(t, float)
    hod = _hodograph(ctrl)
    d = np.array(_bezier(hod, t))
    norm = np.linalg.norm(d, axis=-1, keepdims=True)
    size = np.abs(ctrl).max() + 1.0
    flat = norm[..., 0] <= 1e-12 * size
    if np.any(flat):      # a handle on its end point: the limit direction
        inside = np.array(_bezier(hod, np.clip(t, 1e-9, 1 - 1e-9)))
        d[flat] = inside[flat]
        norm = np.linalg.norm(d, axis=-1, keepdims=True)
    if not np.all(norm > 0):
        raise MorphError("a piece has no tangent (all its control points coincide)")
    return d / norm


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _right(v):
    return np.stack([v[..., 1], -v[..., 0]], axis=-1)


def _inflections(ctrl):
    """Parameters in (0, 1) where a Bézier (n+1, 2) changes its turning sense."""
    if len(ctrl) < 4:
        return []
    d1, d2 = _hodograph(ctrl), _hodograph(_hodograph(ctrl))
    # cross(c', c'') sampled densely, sign changes refined by bisection
    t = np.linspace(0, 1, 65)
    f = lambda s: _cross(_bezier(d1, s), _bezier(d2, s))  # noqa: E731
    v = f(t)
    out = []
    for k in np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0):
        lo, hi = t[k], t[k + 1]
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            if np.sign(f(np.array([mid]))[0]) == np.sign(v[k]):
                lo = mid
            else:
                hi = mid
        out.append(0.5 * (lo + hi))
    return [s for s in out if 1e-6 < s < 1 - 1e-6]


# ------------------------------------------------------------------- elements

@dataclass
class Element:
    """One part of a loop for all skeleton masters: a source ``piece`` (``ctrl``
    (M, n+1, 2), parameter t in [0, 1]) or a nib ``arc`` at a corner (``point``
    (M, 2); normal angle phi0 + s dphi for s in [0, 1], ``phi0`` and ``dphi`` (M,)).
    ``breaks``: parameters where every master must be split (inflections)."""

    kind: str
    ctrl: np.ndarray = None
    point: np.ndarray = None
    phi0: np.ndarray = None
    dphi: np.ndarray = None
    breaks: tuple = ()

    @property
    def masters(self):
        return len(self.ctrl if self.kind == "piece" else self.point)

    def centre(self, s):
        """c(s) for every master: (M, k, 2)."""
        if self.kind == "piece":
            return _bezier(self.ctrl, s)
        return np.repeat(self.point[:, None, :], len(s), axis=1)

    def normals(self, s):
        """Outward normals at s for every master: (M, k, 2)."""
        if self.kind == "piece":
            return _right(_tangents(self.ctrl, s))
        phi = self.phi0[:, None] + self.dphi[:, None] * np.asarray(s, float)[None, :]
        return np.stack([np.cos(phi), np.sin(phi)], axis=-1)

    def cubic(self, a, b):
        """The centre part of the segment [a, b] as cubics (M, 4, 2), exact."""
        if self.kind == "piece":
            return np.array([_to_cubic(_subcurve(c, a, b)) for c in self.ctrl])
        return np.repeat(self.point[:, None, :], 4, axis=1)


def _arc(points, t_in, t_out, turn=None):
    """The corner element between unit tangents t_in and t_out (M, 2) at ``points``:
    the nib arc from normal right(t_in) turning by the signed angle between the
    tangents (or by ``turn``, for caps)."""
    if turn is None:
        turn = np.arctan2(_cross(t_in, t_out), np.einsum("ij,ij->i", t_in, t_out))
    n_in = _right(t_in)
    return Element("arc", point=np.asarray(points, float),
                   phi0=np.arctan2(n_in[:, 1], n_in[:, 0]),
                   dphi=np.broadcast_to(np.asarray(turn, float), (len(points),)).copy())


def _piece(ctrl):
    ctrl = np.asarray(ctrl, float)
    breaks = sorted({round(float(s), 12) for c in ctrl for s in _inflections(c)})
    return Element("piece", ctrl=ctrl, breaks=tuple(breaks))


def _end_tangents(ctrls):
    """(unit tangent at the start, at the end) of every master's piece."""
    return _tangents(ctrls, [0.0])[:, 0], _tangents(ctrls, [1.0])[:, 0]


def _cartesian(piece):
    p = np.asarray(piece, float)
    return p[:, :2] / p[:, 2:] if p.shape[1] == 3 else p


def _path_parts(pieces_m):
    """A path's pieces for all masters ([k][M] control arrays) cut where any master
    turns back on itself (see :data:`REVERSAL`)."""
    parts, current = [], [pieces_m[0]]
    for prev, nxt in zip(pieces_m[:-1], pieces_m[1:]):
        _, t1 = _end_tangents(prev)
        t0, _ = _end_tangents(nxt)
        if np.any(np.einsum("ij,ij->i", t1, t0) < -np.cos(REVERSAL)):
            parts.append(current)
            current = []
        current.append(nxt)
    parts.append(current)
    return parts


def _corner(t_in, t_out, points, loops):
    """Append the arc of a join unless no master turns there."""
    turn = np.arctan2(_cross(t_in, t_out), np.einsum("ij,ij->i", t_in, t_out))
    if np.any(turn != 0.0):
        loops.append(_arc(points, t_in, t_out, turn))


def skeleton_elements(paths_by_master, label="glyph"):
    """Loops of elements (:class:`Element`) of skeleton paths, for every master.

    ``paths_by_master``: for each master a list of paths ``(pieces, closed)``
    (:func:`morph.parse.ufo.glyph_paths`), pieces as homogeneous or cartesian
    control arrays; the masters must have the same paths, each with the same
    pieces of the same degrees.  Every path is traced forward and back (a closed
    path is stroked, not filled) with +pi caps at its two ends; a zero-length path
    (a dot) gives the whole nib.  Returns a list of loops, each a list of elements.

    Raises:
        IncompatibleMasters: the masters' paths differ (the message says where).
    """
    nm = len(paths_by_master)
    first = paths_by_master[0]
    for m, paths in enumerate(paths_by_master[1:], 1):
        if len(paths) != len(first):
            raise IncompatibleMasters("%s: master %d has %d paths, master 0 has %d"
                                      % (label, m, len(paths), len(first)), "paths")
        for k, ((a, _), (b, _)) in enumerate(zip(first, paths)):
            if len(a) != len(b):
                raise IncompatibleMasters("%s: path %d has %d pieces in master %d, %d in "
                                          "master 0" % (label, k, len(b), m, len(a)), "pieces")
            for j, (p, q) in enumerate(zip(a, b)):
                if len(p) != len(q):
                    raise IncompatibleMasters("%s: path %d piece %d has degree %d in master "
                                              "%d, %d in master 0" % (label, k, j, len(q) - 1,
                                                                      m, len(p) - 1), "degree")
    loops = []
    for k in range(len(first)):
        pieces = [np.array([_cartesian(paths_by_master[m][k][0][j]) for m in range(nm)])
                  for j in range(len(first[k][0]))]
        if all(np.ptp(p, axis=1).max() == 0 for p in pieces):   # a dot: the nib itself
            pt = pieces[0][:, 0]
            loops.append([Element("arc", point=pt, phi0=np.zeros(nm),
                                  dphi=np.full(nm, 2 * np.pi))])
            continue
        pieces = [p for p in pieces if np.ptp(p, axis=1).max() > 0]
        for part in _path_parts(pieces):
            loops.append(_forward_back(part))
    return loops


def _forward_back(part):
    """The loop of a path part traced forward and back, with its corners and caps."""
    rev = [p[:, ::-1] for p in reversed(part)]
    loop = []
    for side in (part, rev):
        for j, p in enumerate(side):
            if j:
                _, t_in = _end_tangents(side[j - 1])
                t_out, _ = _end_tangents(p)
                _corner(t_in, t_out, p[:, 0], loop)
            loop.append(_piece(p))
        _, t_end = _end_tangents(side[-1])
        loop.append(_arc(side[-1][:, -1], t_end, -t_end, turn=np.pi))   # the cap
    return loop


def region_elements(loops_by_master, label="glyph"):
    """Loops of elements of closed region boundaries (a filled glyph), for every
    master: ``loops_by_master[m]`` is a list of closed loops of pieces, outer loops
    counter-clockwise and holes clockwise, the same structure in every master.

    Raises:
        IncompatibleMasters: the masters' loops differ.
    """
    nm = len(loops_by_master)
    first = loops_by_master[0]
    for m, loops in enumerate(loops_by_master[1:], 1):
        if len(loops) != len(first) or any(len(a) != len(b) or any(len(p) != len(q)
                                                                   for p, q in zip(a, b))
                                           for a, b in zip(first, loops)):
            raise IncompatibleMasters("%s: master %d has other contours or segments than "
                                      "master 0" % (label, m), "contours")
    out = []
    for k in range(len(first)):
        pieces = [np.array([_cartesian(loops_by_master[m][k][j]) for m in range(nm)])
                  for j in range(len(first[k]))]
        pieces = [p for p in pieces if np.ptp(p, axis=1).max() > 0]
        if not pieces:
            continue
        loop = []
        for j, p in enumerate(pieces):
            _, t_in = _end_tangents(pieces[j - 1])
            t_out, _ = _end_tangents(p)
            _corner(t_in, t_out, p[:, 0], loop)
            loop.append(_piece(p))
        out.append(loop)
    return out


# -------------------------------------------------------------------- fitting

def _nib_part(el, nibs, owners, s):
    """E_j(s) for every fitted master j: (J, k, 2).  A piece's is e_j(n(s)), the nib
    point of the piece's normal; an arc's runs along the nib's own parameter psi
    (e = M (cos psi, sin psi)) linearly between the psi of its two normals, so that a
    quarter of the nib is one cubic at any eccentricity (the normal angle runs fast
    near the tips of a thin nib)."""
    s = np.asarray(s, float)
    if el.kind == "piece":
        n = el.normals(s)
        return np.stack([nib.support(n[o]) for nib, o in zip(nibs, owners)])
    out = []
    for nib, o in zip(nibs, owners):
        psi0, dpsi = _psi_range(nib, el.phi0[o], el.dphi[o])
        psi = psi0 + dpsi * s
        out.append(np.column_stack([np.cos(psi), np.sin(psi)]) @ nib.matrix().T)
    return np.stack(out)


def _psi_range(nib, phi0, dphi):
    """(psi0, dpsi): the nib parameters of the normals phi0 and phi0 + dphi, dpsi of
    dphi's sign (the map from normal angle to nib parameter is increasing)."""
    m = nib.matrix()
    v0 = np.array([np.cos(phi0), np.sin(phi0)]) @ m
    v1 = np.array([np.cos(phi0 + dphi), np.sin(phi0 + dphi)]) @ m
    psi0 = np.arctan2(v0[1], v0[0])
    if abs(dphi) >= 2 * np.pi - 1e-12:
        return psi0, float(np.sign(dphi)) * 2 * np.pi
    if dphi == 0:
        return psi0, 0.0
    if abs(dphi) == np.pi:                 # caps: n -> -n is psi -> psi + pi exactly
        return psi0, float(dphi)
    # |dphi| < pi gives |dpsi| < pi (the map commutes with n -> -n)
    return psi0, float((np.arctan2(v1[1], v1[0]) - psi0 + np.pi) % (2 * np.pi) - np.pi)


def _hermite(el, nibs, owners, a, b):
    """Cubic Hermite control points (J, 4, 2) of every master's nib part on [a, b],
    the end derivatives by one-sided 3-point differences inside [a, b]."""
    h = 1e-4 * (b - a)
    s = np.array([a, a + h, a + 2 * h, b - 2 * h, b - h, b])
    e = _nib_part(el, nibs, owners, s)
    d0 = (-3 * e[:, 0] + 4 * e[:, 1] - e[:, 2]) / (2 * h)
    d1 = (3 * e[:, 5] - 4 * e[:, 4] + e[:, 3]) / (2 * h)
    w = (b - a) / 3.0
    return np.stack([e[:, 0], e[:, 0] + w * d0, e[:, 5] - w * d1, e[:, 5]], axis=1)


_U = np.linspace(0.0, 1.0, SAMPLES + 2)[1:-1]


def _speed(el, nibs, owners, t):
    """d/dt of the convolution along the piece's unit tangent, every master: (J, k).
    It changes sign at the cusps of the convolution (where the source's curvature
    radius equals the nib's: the swallowtails of the inner side)."""
    h = 1e-6
    lo, hi = np.clip(t - h, 0.0, 1.0), np.clip(t + h, 0.0, 1.0)
    tau = _tangents(el.ctrl, t)                                  # (M, k, 2)
    dc = _bezier(_hodograph(el.ctrl), t)
    de = (_nib_part(el, nibs, owners, hi) - _nib_part(el, nibs, owners, lo)) / \
        (hi - lo)[None, :, None]
    return np.einsum("jkd,jkd->jk", dc[owners] + de, tau[owners])


def _cusps(el, nibs, owners, samples=65):
    """Parameters of every master's cusps on a piece (sign changes of
    :func:`_speed`, refined by bisection): breaks for all masters, so that each
    master's cusp is an end point of its segments, where the Hermite ends give the
    fitted curve a zero derivative too (a true cusp, not a small loop whose inside
    would have the wrong winding)."""
    if el.kind != "piece":
        return []
    t = np.linspace(0.0, 1.0, samples)
    v = _speed(el, nibs, owners, t)
    out = []
    for j, k in zip(*np.nonzero(np.sign(v[:, :-1]) * np.sign(v[:, 1:]) < 0)):
        lo, hi, sign = t[k], t[k + 1], np.sign(v[j, k])
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            if np.sign(_speed(el, nibs, owners, np.array([mid]))[j, 0]) == sign:
                lo = mid
            else:
                hi = mid
        out.append(0.5 * (lo + hi))
    return out


def _fit_element(el, nibs, owners, tol):
    """[(a, b, hermite (J, 4, 2))] of one element, every master within tol; pieces
    are split first at their inflections and at every master's cusps."""
    cuts = sorted(set(el.breaks) | set(_cusps(el, nibs, owners)))
    bounds = [0.0]
    for s in cuts:
        if 1e-9 < s < 1 - 1e-9 and s - bounds[-1] > 1e-9:
            bounds.append(s)
    bounds.append(1.0)
    todo = [(a, b, 0) for a, b in zip(bounds[:-1], bounds[1:])][::-1]
    out = []
    while todo:
        a, b, depth = todo.pop()
        herm = _hermite(el, nibs, owners, a, b)
        exact = _nib_part(el, nibs, owners, a + _U * (b - a))
        err = np.linalg.norm(_bezier(herm, _U) - exact, axis=-1).max()
        if err <= tol:
            out.append((a, b, herm))
        elif depth >= _MAX_DEPTH:
            raise MorphError("the nib part does not fit within %g after %d halvings (error "
                             "%g)" % (tol, depth, err))
        else:
            m = 0.5 * (a + b)
            todo += [(m, b, depth + 1), (a, m, depth + 1)]
    return out


def fit_elements(loops, nibs, owners=None, tol=0.25):
    """The convolution loops of every fitted master, point-compatible.

    ``loops``: from :func:`skeleton_elements` / :func:`region_elements` (M skeleton
    masters); ``nibs``: one :class:`Ellipse` per fitted master; ``owners``: the
    skeleton master of each fitted master (default: master j for nib j, or master 0
    for all when M is 1).  ``tol``: the fit tolerance (font units) every master's
    nib part meets at the sample parameters.

    Returns one list per fitted master of loops, each a ``(k, 4, 2)`` array of
    cubics (the same k for every master), positively oriented.
    """
    nm = loops[0][0].masters if loops else 1
    if owners is None:
        owners = [0] * len(nibs) if nm == 1 else list(range(len(nibs)))
    out = [[] for _ in nibs]
    for loop in loops:
        cubics = []
        for el in loop:
            for a, b, herm in _fit_element(el, nibs, owners, tol):
                cubics.append(el.cubic(a, b)[owners] + herm)
        cubics = np.stack(cubics, axis=1)       # (J, k, 4, 2)
        # joins exact: each segment starts where the one before ends
        cubics[:, 1:, 0] = cubics[:, :-1, 3]
        cubics[:, 0, 0] = cubics[:, -1, 3]
        for j in range(len(nibs)):
            out[j].append(cubics[j])
    return out


def convolve_masters(paths_by_master, nibs, owners=None, tol=0.25, label="glyph"):
    """:func:`fit_elements` of :func:`skeleton_elements`: a skeleton glyph's
    untrimmed convolution loops for every (skeleton master, nib) pair."""
    return fit_elements(skeleton_elements(paths_by_master, label), nibs, owners, tol)
