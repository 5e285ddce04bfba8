"""Tolerance against size, and resource budgets: refuse early, in one line, with a fix.

Every entry point that computes to a tolerance (``minkowski_sum``, offsets, frames,
the CLI's shared options) calls :func:`check_tolerance` with its operands.  It raises
:class:`morph.errors.LimitError` (a ``MorphError`` and a ``ValueError``; the CLI
exits 2) when

- ``tol`` is not a positive finite number;
- ``tol`` is larger than the result (the sum of the operands' extents): nothing of
  the shape would survive it;
- ``tol`` is finer than what float64 resolves at the operands' coordinates,
  ``FP_FACTOR * eps * magnitude`` (magnitude: the largest |coordinate| of the
  result, so far-from-origin drawings count), or than the stated relative floor
  ``REL_TOL_FLOOR * size``;
- a coordinate exceeds ``MAX_COORDINATE`` (products of a few coordinates, as in
  areas and Bernstein products, must stay finite);
- the polylines the work needs exceed ``POINT_BUDGET`` points.  The estimate is
  a-priori: a polynomial piece with second-derivative bound D flattens within tol
  in ceil(sqrt(D / (8 tol))) chords (D <= n(n-1) max |Δ²P| on the control points;
  rational pieces use their Cartesian control points, an estimate, not a bound).
  The points of A ⊕ B are estimated as those of A plus those of B.  The budget is
  calibrated on the Clipper trimming engine (O ⊕ M at 1e-5 font units: 24k
  estimated points, 2.2 s and 0.3 GB; time and memory grow about linearly, and
  the sum flattens at a fraction of the user's tolerance), so 50k points stay
  within about 10 s and 1 GB; override with the environment
  variable ``MORPH_POINT_BUDGET``.

Each message says which tolerance would work.  :func:`memory_budget_bytes` is the
address-space budget the CLI sets (``MORPH_MEMORY_LIMIT`` in GB, default the smaller
of 8 GB and 3/4 of the physical memory), so work beyond it stops with a MemoryError
turned into one line, never the system's OOM killer.
"""

import math
import os

import numpy as np

from . import piece as pc
from .errors import LimitError

__all__ = [
    "FP_FACTOR",
    "MAX_COORDINATE",
    "POINT_BUDGET",
    "REL_TOL_FLOOR",
    "check_tolerance",
    "estimate_points",
    "memory_budget_bytes",
    "precision_floor",
    "point_budget",
    "fits_precision",
    "region_extent",
]

REL_TOL_FLOOR = 1e-12
FP_FACTOR = 1024.0
MAX_COORDINATE = 1e100
POINT_BUDGET = 50_000


def point_budget():
    """POINT_BUDGET, or the MORPH_POINT_BUDGET environment variable when set."""
    try:
        return float(os.environ.get("MORPH_POINT_BUDGET", POINT_BUDGET))
    except ValueError:
        return float(POINT_BUDGET)


def region_extent(region):
    """(size, magnitude) of a region from its control points (a hull bound): size is
    the larger side of the control-point box, magnitude the largest |coordinate|.
    Raises LimitError for NaN/inf or coordinates beyond MAX_COORDINATE.  ``region``
    may also be its pieces stacked (a :class:`morph.piece.Pieces`)."""
    pieces = region if isinstance(region, pc.Pieces) else [p for loop in region for p in loop]
    if not pieces:
        return 0.0, 0.0
    pts = np.concatenate([(h[..., :2] / h[..., 2:]).reshape(-1, 2)
                          for _, h, _ in pc.kind_groups(pieces)])
    with np.errstate(all="ignore"):
        finite = bool(np.all(np.isfinite(pts)))
        mag = float(np.max(np.abs(pts))) if finite else math.inf
    if not finite or mag > MAX_COORDINATE:
        raise LimitError("a shape has %s; morph computes with |coordinates| up to %g"
                         % ("a non-finite coordinate (NaN or inf)" if not finite
                            else "a coordinate of %.3g" % mag, MAX_COORDINATE))
    return float(np.max(np.ptp(pts, axis=0))), mag



def estimate_points(region, tol):
    """A-priori number of polyline points flattening ``region`` within ``tol``."""
    n = 0.0
    for _, h, _ in pc.kind_groups([p for loop in region for p in loop]):
        d = h.shape[1] - 1
        if d < 2:  # lines: one point each
            n += len(h)
            continue
        with np.errstate(all="ignore"):
            c = h[..., :2] / h[..., 2:]
            dd = np.abs(np.diff(c, 2, axis=1)).max(axis=(1, 2)) * d * (d - 1)
            steps = np.ceil(np.sqrt(dd / (8.0 * tol)))
        n += float(np.where(dd > 0, steps, 1.0).sum())
    return n


def precision_floor(magnitude):
    """The finest tolerance honoured at coordinates up to ``magnitude``:
    FP_FACTOR ulps of it (see the module docstring)."""
    return FP_FACTOR * np.finfo(float).eps * magnitude


def fits_precision(tol, *regions):
    """Whether ``tol`` is above :func:`precision_floor` of the regions' largest
    coordinate (for layouts of several regions, such as :mod:`morph.packing`)."""
    return tol >= precision_floor(max(region_extent(r)[1] for r in regions))


def _fmt(x):
    return "%.2g" % x


def _round_up(x):
    """x rounded up to two significant digits (as :func:`_fmt` prints it)."""
    e = 10.0 ** (math.floor(math.log10(x)) - 1)
    return math.ceil(x / e * (1 - 1e-12)) * e


def _passing_tolerance(tol, regions, unit):
    """The tolerance to suggest for a refused ``tol`` at or above the precision floor:
    two significant digits in the user's unit (rounded up, so that the printed value
    works), and estimated points within the budget: points scale about as tol^(-1/2)
    (each piece keeps at least one point, so the first guess can fall short); raised
    by 10 % until it fits."""
    budget = point_budget()
    points = sum(estimate_points(r, tol) for r in regions)
    need = tol * max(points / budget, 1.0) ** 2
    for _ in range(64):
        need = _round_up(need / unit) * unit
        if sum(estimate_points(r, need) for r in regions) <= budget:
            break
        need *= 1.1
    return need


def check_tolerance(tol, *regions, operation="this operation", unit=1.0, unit_name=""):
    """Refuse a tolerance the operands cannot support (see the module docstring).

    ``regions`` are the operands whose sum is computed (one region for outlines and
    offsets -- pass the disk too --, two for a sum); ``tol`` is absolute in their
    units.  ``unit`` converts tolerances into the user's unit for the messages
    (e.g. units per em for glyphs, with ``unit_name`` "em").  Returns the estimated
    number of polyline points.  Raises LimitError naming ``operation``.
    """
    def user(x):
        return "%s%s" % (_fmt(x / unit), (" " + unit_name) if unit_name else "")

    try:
        tol = float(tol)
    except (TypeError, ValueError):
        raise LimitError("%s: tolerance %r is not a number" % (operation, tol)) from None
    if not (tol > 0 and math.isfinite(tol)):
        raise LimitError("%s: tolerance must be a positive finite number, got %s"
                         % (operation, tol))
    size, mag = 0.0, 0.0
    for r in regions:
        s, m = region_extent(r)
        size, mag = size + s, mag + m
    if size > 0 and tol > size:
        raise LimitError("%s: tolerance %s is larger than the shapes (size %s): use a "
                         "tolerance below %s" % (operation, user(tol), user(size),
                                                 user(size / 10)), size / 10)
    floor = max(REL_TOL_FLOOR * size, precision_floor(mag))
    if tol < floor:
        why = ("the floating-point resolution at coordinates of %s" % _fmt(mag)
               if floor > REL_TOL_FLOOR * size else "%g of the size %s" % (REL_TOL_FLOOR,
                                                                         user(size)))
        need = _passing_tolerance(floor, regions, unit)
        raise LimitError("%s: tolerance %s is finer than %s; use a tolerance of at least %s"
                         % (operation, user(tol), why, user(need)), need)
    points = sum(estimate_points(r, tol) for r in regions)
    budget = point_budget()
    if points > budget:
        need = _passing_tolerance(tol, regions, unit)
        raise LimitError("%s: at tolerance %s the curves need about %d polyline points, "
                         "more than the budget of %d (MORPH_POINT_BUDGET); use a tolerance "
                         "of at least %s" % (operation, user(tol), points, budget, user(need)),
                         need)
    return points


def memory_budget_bytes():
    """Address-space budget for one morph process, in bytes (see module docstring)."""
    env = os.environ.get("MORPH_MEMORY_LIMIT")
    if env:
        try:
            return int(float(env) * 2 ** 30)
        except ValueError:
            pass
    try:
        phys = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        phys = 16 * 2 ** 30
    return int(min(8 * 2 ** 30, 0.75 * phys))
