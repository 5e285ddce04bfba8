"""Operands of a sum: the checks that a region is one the sums can take.

:func:`check_operand` refuses what is not a list of closed loops of rational pieces
with positive weights, whose area is not negative and which bound a region
(:func:`winding_fault`: no part of negative winding, no loop crossing itself with
its own winding other than 0 or its sign): :class:`morph.errors.OperandError`, bad
input.  A validated :class:`morph.region.Region` skips the winding test.
"""

from itertools import chain

import numpy as np
import pyclipper

from . import moments as mo
from . import piece as pc
from . import polyline as pl
from .errors import OperandError, SelfCrossingError
from .polyline import winding_number
from .region import (APART, Region, loops_cross, outside_windings, region_scale,
                     sample_candidates)

__all__ = ["check_operand", "check_operands", "winding_fault"]


def check_operand(region, name):
    """OperandError (a ValueError) unless ``region`` is a list of closed loops (each
    piece ending where the next starts, within 1e-7 of the size) of pieces, each an (n+1, 3) array
    (n >= 1) of homogeneous control points with positive weights, whose signed area
    is not negative
    (beyond 1e-9 of its control box squared: a centre line traced out and back has
    area 0), and which pass :func:`winding_fault` (skipped for a
    validated :class:`morph.region.Region`): no part of negative winding, no loop
    crossing itself with its own winding other than 0 or +-1 there
    (SelfCrossingError: a figure-8, a curl undone by a counter-curl); outer loops
    counter-clockwise, holes clockwise, as :func:`morph.region.orient_region`
    makes them.  Loops turning other than once are also refused by
    :func:`morph.convolve.gauss_pair_of`."""
    for loop in region:
        if not len(loop):
            raise OperandError("%s has an empty loop" % name)
        for p in loop:
            shape = np.shape(p)
            if len(shape) != 2 or shape[1] != 3 or shape[0] < 2:
                raise OperandError("%s: a piece is an (n+1, 3) array of homogeneous control "
                                   "points (w*x, w*y, w), n >= 1; got shape %s" % (name, shape))
    pieces = [p for loop in region for p in loop]
    h = np.concatenate(pieces).astype(float, copy=False)
    if not np.all(np.isfinite(h)):
        return  # check_tolerance names it
    if not np.all(h[:, 2] > 0):
        raise OperandError("%s has a weight <= 0: rational pieces need positive weights"
                           % name)
    pts = h[:, :2] / h[:, 2:]
    starts, ends = pc.end_points(pieces)
    # the start of the next piece of the same loop, cyclically
    sizes = np.array([len(loop) for loop in region])
    first = np.repeat(np.cumsum(sizes) - sizes, sizes)
    k = np.arange(len(pieces))
    nxt = np.where(k + 1 - first == np.repeat(sizes, sizes), first, k + 1)
    with np.errstate(all="ignore"):
        size = float(np.max(np.ptp(pts, axis=0)))
        gap = np.hypot(*(starts[nxt] - ends).T)
        if np.any(gap > 1e-7 * size):
            j = int(np.argmax(gap))
            loop = int(np.searchsorted(np.cumsum(sizes), j, side="right"))
            raise OperandError("%s: loop %d is not closed: piece %d ends %.3g away from "
                               "where the next starts" % (name, loop, j - first[j], gap[j]))
        area = float(np.sum(mo.loop_areas(region)))  # the loops' areas in one batch
    if area < -1e-9 * size * size:
        raise OperandError("%s has a negative signed area (%.6g): outer loops must run "
                           "counter-clockwise and holes clockwise "
                           "(morph.region.orient_region normalises loops)" % (name, area))
    if not (isinstance(region, Region) and region.validated):
        _check_windings(region, name)


def check_operands(regions, names, region_b, tol, operation, pieces=None):
    """[:func:`morph.limits.check_tolerance` (tol, region, region_b)] of every region
    after its :func:`check_operand`, raising what region by region would raise first.

    The pieces of all regions are checked together (shapes, finite values, weights,
    closed loops, areas, extents, estimated points: a few array calls for a font's
    chunk); a region that any of these flags, or that is not a validated
    :class:`morph.region.Region` (the winding test), is then checked on its own, in
    order, by the functions themselves, so that the first error and its message
    are theirs.  ``region_b`` must have passed :func:`check_operand`.  ``pieces``:
    the regions' pieces in order, stacked (a :class:`morph.piece.Pieces`; None:
    stacked here)."""
    from . import limits as lm

    regions = list(regions)
    n = len(regions)
    if not n:
        return []
    try:
        tol_ok = float(tol) > 0 and np.isfinite(float(tol))
    except (TypeError, ValueError):
        tol_ok = False
    if not tol_ok:   # check_tolerance names it
        return _one_by_one(regions, names, region_b, tol, operation, range(n))
    tol = float(tol)
    checked = _piece_flags(regions, pieces)
    if checked is None:
        return _one_by_one(regions, names, region_b, tol, operation, range(n))
    flag, size, mag, packed, region_of = checked
    # the tolerance: the extents with B's, and the estimated points
    b_size, b_mag = lm.region_extent(region_b)
    tot_size, tot_mag = size + b_size, mag + b_mag
    floor = np.maximum(lm.REL_TOL_FLOOR * tot_size, lm.precision_floor(tot_mag))
    points = _estimate_points_many(packed, region_of, n, tol) + lm.estimate_points(region_b, tol)
    flag |= ((tot_size > 0) & (tol > tot_size)) | (tol < floor) | (points > lm.point_budget())
    check = [i for i in range(n) if flag[i] or not (
        isinstance(regions[i], Region) and regions[i].validated)]
    out = points.tolist()
    for i, p in zip(check, _one_by_one(regions, names, region_b, tol, operation, check)):
        out[i] = p
    return out


def _piece_flags(regions, stacked=None):
    """What the pieces of all ``regions`` show at once, for :func:`check_operands`:
    ``(flag, size, mag, packed, region_of)``, where ``flag`` marks each region with an
    empty loop, a non-finite or too large control point, a loop that does not close
    (gap over 1e-7 of its size) or a negative area, ``size``/``mag`` are each
    region's extent and largest coordinate, ``packed`` the stacked pieces and
    ``region_of`` each piece's region; None where some piece is not a (k >= 2, 3)
    array (the functions themselves then name it).  ``stacked``: the pieces as a
    :class:`morph.piece.Pieces` already (None: stacked here)."""
    from . import limits as lm

    n = len(regions)
    loops = list(chain.from_iterable(regions))
    region_of_loop = np.repeat(np.arange(n), np.fromiter(map(len, regions), np.int64, n))
    sizes = np.fromiter(map(len, loops), np.int64, len(loops))
    pieces = list(chain.from_iterable(loops))
    flag = np.zeros(n, bool)
    flag[region_of_loop[sizes == 0]] = True
    if not pieces:
        return None
    # the pieces stacked by number of rows: every stack (k, rows >= 2, 3) exactly
    # when every piece is a (rows >= 2, 3) array
    try:
        packed = pc.Pieces.of(pieces) if stacked is None else stacked
    except (TypeError, ValueError):
        return None
    if any(h.ndim != 3 or h.shape[1] < 2 or h.shape[2] != 3 for _, h in packed.groups):
        return None
    region_of = np.repeat(region_of_loop, sizes)
    big = np.zeros(n)
    bad, lo, hi, mag = _control_extents(packed, region_of, n)
    flag |= bad | (mag > lm.MAX_COORDINATE)
    size = np.where(np.isfinite(hi - lo).all(axis=1), (hi - lo).max(axis=1), 0.0)
    # closed loops: each piece ends where the next of its loop starts
    starts, ends = pc.end_points(packed)
    first = np.repeat(np.cumsum(sizes) - sizes, sizes)
    k = np.arange(len(pieces))
    nxt = np.where(k + 1 - first == np.repeat(sizes, sizes), first, k + 1)
    with np.errstate(all="ignore"):
        gap = np.hypot(*(starts[nxt] - ends).T)
        np.maximum.at(big, region_of, np.nan_to_num(gap, nan=np.inf))
        flag |= big > 1e-7 * size
        area = np.bincount(region_of_loop, weights=mo.loop_areas(loops, packed),
                           minlength=n)
        # summed in another order than check_operand's: flagged with room to spare
        flag |= ~(area >= -0.5e-9 * size * size)
    return flag, size, mag, packed, region_of


def _control_extents(packed, region_of, n):
    """(bad, lo, hi, mag) per region of ``n``: whether any piece has a non-finite
    value or a weight not > 0, and the finite control points' box and largest
    coordinate.  ``packed``: a :class:`morph.piece.Pieces`; ``region_of``: each
    piece's region."""
    lo, hi = np.full((n, 2), np.inf), np.full((n, 2), -np.inf)
    mag = np.zeros(n)
    bad = np.zeros(n, bool)
    for ks, h in packed.groups:
        r = region_of[ks]
        with np.errstate(all="ignore"):
            x = h[..., :2] / h[..., 2:]
        fin = np.isfinite(h).all(axis=(1, 2)) & np.isfinite(x).all(axis=(1, 2))
        bad[r[~fin]] = True
        bad[r[~(h[..., 2] > 0).all(axis=1)]] = True
        np.minimum.at(lo, r, np.where(fin[:, None], x.min(axis=1), np.inf))
        np.maximum.at(hi, r, np.where(fin[:, None], x.max(axis=1), -np.inf))
        np.maximum.at(mag, r, np.where(fin, np.abs(x).max(axis=(1, 2)), 0.0))
    return bad, lo, hi, mag


def _one_by_one(regions, names, region_b, tol, operation, which):
    """check_operand and check_tolerance of the regions ``which``, in order."""
    from .limits import check_tolerance

    out = []
    for i in which:
        check_operand(regions[i], names[i])
        out.append(check_tolerance(tol, regions[i], region_b, operation=operation))
    return out


def _estimate_points_many(packed, region_of, n, tol):
    """:func:`morph.limits.estimate_points` of each region (its pieces: ``region_of``)
    at once: (n,) floats (sums of integers: the same in any order)."""
    out = np.zeros(n)
    for ks, h, _ in pc.kind_groups(packed):
        d = h.shape[1] - 1
        if d < 2:
            np.add.at(out, region_of[ks], 1.0)
            continue
        with np.errstate(all="ignore"):
            c = h[..., :2] / h[..., 2:]
            dd = np.abs(np.diff(c, 2, axis=1)).max(axis=(1, 2)) * d * (d - 1)
            steps = np.ceil(np.sqrt(dd / (8.0 * tol)))
        np.add.at(out, region_of[ks], np.where(dd > 0, steps, 1.0))
    return out


def _check_windings(region, name):
    """SelfCrossingError or OperandError naming the loop and a point where
    :func:`winding_fault` finds ``region`` bounds no region."""
    fault = winding_fault(region)
    if fault is None:
        return
    (x, y), w, loop, crossed = fault
    if crossed:
        raise SelfCrossingError(
            "%s: loop %d crosses itself and winds %d times round (%.6g, %.6g), where a "
            "loop winds 0 times or once; morph.region.orient_region (with on_crossing="
            "morph.trim.fill_region) makes a region of it" % (name, loop, w, x, y), loop)
    which = "loop %d is a hole outside the other loops, or reaching out of them: " % loop \
        if loop is not None else ""
    raise OperandError("%s: %sthe winding number near (%.6g, %.6g) is %d, where a region's "
                       "is 0 or more; morph.region.orient_region (with on_crossing="
                       "morph.trim.fill_region) makes a region of the loops"
                       % (name, which, x, y, w))


def winding_fault(loops):
    """Where the loops fail to bound a region the sums can take: None, or
    (point, winding, loop, crossed) with ``point`` (x, y) in the faulty part.

    Two faults: a loop that crosses itself so that its own winding number is
    other than 0 and its orientation's sign (``crossed`` True, ``loop`` its index,
    ``winding`` its own: a figure-8 or a curl undone by a counter-curl, which turns
    once in all); or a part where the winding number of all loops is negative
    (``crossed`` False, ``loop`` the clockwise loop just around it when known, else
    None: a hole outside every outer loop or reaching out of its own).  Loops of one
    direction may overlap or nest (winding 2 or more: the sum is linear in the loops
    and fills it once); a loop may touch itself or pass through its own crossing
    with winding 0 or 1 beside it (the boundary of a pinched region).

    Loops whose arcs stay apart (:func:`loops_cross` says no) are simple: only the
    winding just outside each clockwise loop is needed (:func:`outside_windings`,
    at least 1).  Otherwise the loops are flattened within f = 1e-5 of their size
    (integer points on a grid of f / 100) and Clipper finds, for each loop that
    comes near itself, the parts where it winds other than 0 or its sign (its own
    filled set subtracted from it as a cycle), then the parts of negative winding,
    each eroded by 3 f so that the slivers where flattened arcs touch vanish: a
    part thinner than 6 f is not reported.  Parts of zero width wind 0 on both
    sides and pass (a spike, a slit, a hole sharing an edge with its outer loop, a
    stroke's centre line traced out and back): the sums take them as traced, like
    the closed set they bound; one that crosses the rest of its loop makes the
    loop turn other than once, which :func:`morph.convolve.gauss_pair_of`
    refuses."""
    loops = [loop for loop in loops if len(loop)]
    if not loops:
        return None
    scale = region_scale(loops)
    polys = pl.flatten_loops(loops, APART * scale)
    areas = [mo.loop_area(loop) for loop in loops]
    if not loops_cross(loops, scale, polys):
        return _hole_outside(loops, areas, scale, polys)
    return _crossed_fault(loops, areas, scale, polys)


def _hole_outside(loops, areas, scale, polys):
    """:func:`winding_fault` of loops whose arcs stay apart: a clockwise loop with
    winding less than 1 just outside it (on its polylines ``polys``), or None."""
    # a loop of area 0 (a centre line traced out and back) winds round nothing
    holes = [k for k, a in enumerate(areas) if a < -1e-9 * scale * scale]
    if not holes:
        return None
    outside = outside_windings(loops, scale, polys) if len(loops) > 1 else [0]
    for k in holes:
        if outside[k] < 1:
            return sample_candidates(loops[k])[0], outside[k] - 1, k, False
    return None


def _crossed_fault(loops, areas, scale, polys):
    """:func:`winding_fault` of loops that come near each other or themselves, on
    Clipper's integer polylines: a loop's own wrong winding first, then a part of
    negative winding."""
    fine = 1e-5 * scale
    grid = fine / 100.0
    depth = 3 * fine / grid  # the erosion, in grid units
    lo = np.min(np.concatenate(polys), axis=0)
    flat = pl.flatten_loops(loops, fine)
    paths = [np.round((p - lo) / grid).astype(np.int64).tolist() for p in flat]
    for k, (loop, path) in enumerate(zip(loops, paths)):
        if len(path) < 3 or not loops_cross([loop], scale):
            continue
        path = path if areas[k] >= 0 else path[::-1]
        filled = _clipper_union([path], pyclipper.PFT_POSITIVE)
        core = _clipper_core([path] + [ring[::-1] for ring in filled], pyclipper.PFT_NONZERO,
                             depth)
        if core is not None:
            point = core * grid + lo
            return point, int(round(winding_number(point[None], [flat[k]])[0])), k, True
    core = _clipper_core([p for p in paths if len(p) >= 3], pyclipper.PFT_NEGATIVE, depth)
    if core is None:
        return None
    point = core * grid + lo
    w = int(round(winding_number(point[None], flat)[0]))
    return point, w, _loop_around(point, loops, areas, flat), False


def _clipper_union(paths, fill_type):
    """Clipper's union of integer paths under ``fill_type`` ([] when every path lies
    on a line)."""
    clip = pyclipper.Pyclipper()
    try:
        clip.AddPaths(paths, pyclipper.PT_SUBJECT, True)
    except pyclipper.ClipperException:  # every path on a line: encloses nothing
        return []
    return clip.Execute(pyclipper.CT_UNION, fill_type, fill_type)


def _clipper_core(paths, fill_type, depth):
    """A point (float array, grid units) of the union of integer ``paths`` under
    ``fill_type`` eroded by ``depth`` grid units, or None when nothing is left."""
    parts = _clipper_union(paths, fill_type)
    if not parts:
        return None
    erode = pyclipper.PyclipperOffset()
    erode.AddPaths(parts, pyclipper.JT_MITER, pyclipper.ET_CLOSEDPOLYGON)
    core = erode.Execute(-depth)
    return np.asarray(core[0][0], float) if core else None


def _loop_around(point, loops, areas, flat):
    """Index of the clockwise loop whose polyline winds round ``point``, or None."""
    for k, a in enumerate(areas):
        if a < 0 and len(flat[k]) >= 3 and winding_number(point[None], [flat[k]])[0] < -0.5:
            return k
    return None
