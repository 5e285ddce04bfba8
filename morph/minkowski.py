"""Minkowski sums of regions: convolution (Secs. 3-5) trimmed to the boundary (Sec. 6).

(The module is not called ``sum`` so as not to shadow the builtin.)
"""

import numpy as np

from . import piece as pc
from . import polyline as pl
from .budget import (CONTRACT_SHARE, CONV_SHARE, FIRST_SHARE, FLAT_SHARE, GRID_SHARE,
                     TIP_FLOOR, TIP_MARGIN, TIP_REACH)
from .convolve import (ConvPieces, _turn_convex, chain, convolution, crossing_rows,
                       gauss_pair_of, with_pair_table)
from .errors import (LimitError, OperandError, SelfCrossingError, ToleranceNotMetError,
                     TopologyError)
from .limits import check_tolerance, fits_precision, point_budget
from .operands import check_operand, check_operands
from .packing import Packing, control_box
from .polyline import member, unique
from .region import validated
from .tips import corner_turns, local_bounds
from .trim import boundary
from .trim.holes import Membership, control_boxes, points_deep_enough

#: Rounds of finer approximation at sharp corners (wedge tips, :func:`_tip_tolerances`).
TIP_ROUNDS = 3
#: :func:`minkowski_sums` keeps the packed sums this many tol apart (beyond B's size)
PACK_GAP = 16.0


def minkowski_sum(region_a, region_b, tol, method="qac", gauss_pair=None):
    """Boundary of A ⊕ B as a region of rational Bézier pieces (Secs. 3-6).

    Every output point lies within ``tol`` of the exact boundary of A ⊕ B (tol
    absolute, in input units: font units for glyphs, whose command-line --tol is in
    em, converted by :func:`morph.parse.em_to_units`), split as: convolution pieces
    within 0.5 tol of the exact convolution curve (0.2 tol in the first round where
    loops can meet at a corner, FIRST_SHARE; a-priori bound of
    :func:`morph.qac.qac_error_bound`, QAC; other methods of ``morph.subdivide.METHODS`` are sampled, not bounded),
    topology decided on polylines within 0.35 tol on a grid of 0.1·sqrt(2) tol
    (:func:`morph.trim.boundary`), runs shorter than 0.05 tol contracted.  Holes
    of the winding-number result are tested exactly, x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅,
    at their deepest point.  Where the exact sum has a hole or a gap narrower than
    about 1 tol (twice the convolution share), the approximated pieces may
    overlap across it and close it: there the exact boundary can be up to that
    width from the output (a sweep case at tol = 0.074 x the size shows it); a
    feature thinner than 0.9 tol (twice the flattening and grid shares) may merge
    with its side.
    At a corner where the boundary turns by phi (the tip of a wedge: phi near
    pi), the junction of two pieces within e of their curves there (their parts
    near the corner, :func:`morph.tips.local_bounds`) can lie
    e / cos(phi / 2) from the exact corner (phi of the pieces' corner a junction
    stands for, :func:`morph.tips.corner_turns`: a junction the trimming left on
    its grid point takes the turn of the pieces' crossing next to it): the pairs
    through such corners are
    approximated again until e / cos(phi / 2) <= 0.5 tol (up to TIP_ROUNDS
    rounds; cos(phi / 2) counted as at least TIP_FLOOR, i.e. turns up to
    179.9 degrees; a pair that cannot be subdivided that far keeps the previous
    round's pieces), so the budget holds there too.  Normals are exact on QAC
    pieces.  Outer loops counter-clockwise, holes clockwise.  Raises LimitError
    (a ValueError) for a tolerance the operands cannot support
    (:func:`morph.limits.check_tolerance`), OperandError for an empty region,
    TopologyError if the convolution pieces do not close into loops.  ``gauss_pair``:
    the operands' Gauss maps when known already (:class:`morph.convolve.GaussPair`).
    Returns a validated :class:`morph.region.Region` whose ``bound`` is the error this
    sum achieved (at most tol; the shares above with the convolution's actual bounds:
    0.5 tol for TrueType sums, whose QAC pieces are exact), which a writer may give
    to its export (:meth:`morph.budget.Budget.after`).  Bad operands raise
    :class:`morph.errors.OperandError` (:func:`check_operand`).
    """
    return minkowski_sum_debug(region_a, region_b, tol, method, gauss_pair)[0]


def minkowski_sum_debug(region_a, region_b, tol, method="qac", gauss_pair=None):
    """(:func:`minkowski_sum`, debug): debug["convolution"] the convolution pieces
    of the last round (:class:`morph.convolve.ConvPieces`, a sequence of
    :class:`morph.subdivide.ConvPiece`), "loops" their chains,
    "holes" the hole tests made ((point, depth, filled) each)."""
    if not region_a or not region_b:
        raise OperandError("both regions must have at least one loop")
    check_operand(region_a, "region_a")
    check_operand(region_b, "region_b")
    check_tolerance(tol, region_a, region_b, operation="minkowski sum")
    out, debug = _sum(region_a, region_b, tol, method, gauss_pair)
    _not_vanished(out, tol)
    return validated(out, _achieved_bound(out, debug["convolution"], tol, method)), debug


def minkowski_sums(regions_a, region_b, tol, method="qac", stacked=None, traced=False):
    """[A ⊕ B for A in regions_a]: :func:`minkowski_sum` of every region with one
    region B, as one computation (a font's glyphs with one nib).

    The regions are moved apart (:class:`morph.packing.Packing`: cells wider and
    taller than the largest region by B's width and height plus PACK_GAP tol, so
    that no point of one sum comes within 16 tol of another's, nor does x - B for a
    point x of one slot meet another region: the hole test stays per region) and summed
    together: each phase then costs a few array calls for all of them.  Each result
    is held to the budget of :func:`minkowski_sum` as if computed alone; the corner
    pass trims again only the slots it refines.  The regions are packed in
    consecutive groups whose estimated polyline points (:func:`morph.limits.
    check_tolerance`) fit the budget of one sum; regions whose packed coordinates
    would be too large for ``tol`` (:func:`morph.limits.fits_precision`) are summed
    one by one.  Raises as :func:`minkowski_sum` (OperandError naming the
    index of an empty region).  ``stacked``: the pieces of all of ``regions_a`` in
    order as a :class:`morph.piece.Pieces`, where the caller has them (None:
    gathered here, once, for the checks, the packing and the Gauss map).
    ``traced``: every loop of ``regions_a`` is a path traced out and back
    (:func:`morph.stroke.path_loop`), whose tips the Gauss map then knows
    (:func:`morph.gauss.gauss_table`).
    """
    regions_a = list(regions_a)
    if not region_b:
        raise OperandError("region_b is empty: both regions must have at least one loop")
    check_operand(region_b, "region_b")
    # all regions' pieces checked together; what region by region raises first (the
    # regions before an empty one, then the empty one)
    empty = [i for i, a in enumerate(regions_a) if not a]
    upto = empty[0] if empty else len(regions_a)
    if stacked is None or empty:
        stacked = _stacked(regions_a[:upto])
    points = check_operands(regions_a[:upto], ["region %d" % i for i in range(upto)],
                            region_b, tol, "minkowski sum", stacked)
    if empty:
        raise OperandError("region %d is empty: both regions must have at least one loop"
                           % upto)
    out = []
    groups = _budget_groups(points, point_budget())
    for group in groups:
        try:
            out += _packed_sums([regions_a[i] for i in group], region_b, tol, method,
                                stacked if len(groups) == 1 else None, traced)
        except SelfCrossingError:
            # name the loop's region, not its index in the packed region
            for i in group:
                gauss_pair_of(regions_a[i], region_b, ("region %d" % i, "region_b"),
                              traced=traced)
            raise
    return out


def _budget_groups(points, budget):
    """Consecutive index groups whose estimated polyline points add up to at most
    ``budget`` (a group of one where a single region needs more)."""
    groups, total = [[]], 0.0
    for i, n in enumerate(points):
        if groups[-1] and total + n > budget:
            groups.append([])
            total = 0.0
        groups[-1].append(i)
        total += n
    return groups if groups[-1] else []


def _stacked(regions):
    """The pieces of ``regions`` in order as a :class:`morph.piece.Pieces` (gathered
    once for the operand checks, the packing and the Gauss maps), or None where
    they cannot be stacked (the checks then name the bad piece)."""
    try:
        return pc.Pieces.of([p for r in regions for loop in r for p in loop])
    except (TypeError, ValueError):
        return None


def _packed_sums(regions_a, region_b, tol, method, stacked=None, traced=False):
    """:func:`minkowski_sums` of regions already checked, as one packed sum
    (``stacked``: their pieces, :func:`_stacked`, or None; ``traced``: as there)."""
    if len(regions_a) < 2:
        return _one_by_one(regions_a, region_b, tol, method, traced)
    # offsets whole multiples of the trimming's grid unit: it falls on every region
    # as on the region alone (:func:`_trimmed`'s grid is anchored at the origin)
    layout = Packing(regions_a, control_box(region_b), PACK_GAP * tol, stacked,
                     _grid_unit(tol))
    if not fits_precision(tol, layout.pieces, region_b):
        return _one_by_one(regions_a, region_b, tol, method, traced)
    pair = gauss_pair_of(layout.packed, region_b, ("region_a", "region_b"), layout.pieces,
                         traced)
    out, debug = _sum(layout.packed, region_b, tol, method, pair, layout.slot_of)
    bounds = _slot_bounds(debug["convolution"], layout, tol, method).tolist()
    out = [validated(loops, b, frozen=True) for loops, b in zip(layout.split(out), bounds)]
    for k, loops in enumerate(out):
        _not_vanished(loops, tol, " of region %d" % k)
    return out


#: Roundings (units in the last place of the largest packed coordinate) that a packed
#: sum's pieces carry besides their QAC bounds (:func:`_slot_bounds`): their
#: arithmetic at packed coordinates and the move back (the QAC bounds of exact pieces
#: measured at most 0.8 ulp of their coordinates: Noto's 'W' and 'o' with an ellipse)
PACKED_ROUNDINGS = 16


def _one_by_one(regions_a, region_b, tol, method, traced):
    """:func:`minkowski_sum` of each region of ``regions_a`` (a region alone, or
    regions whose packing would exceed the precision floor), the Gauss maps of
    ``traced`` paths with their tips known as in a packed sum: a closed path traced
    out and back has its two tips where the path runs on through them, and the
    general test of a tip (a probe beyond it) would probe the trace itself."""
    return [minkowski_sum(a, region_b, tol, method,
                          gauss_pair_of(a, region_b, ("region_a", "region_b"), traced=True)
                          if traced else None) for a in regions_a]


def _slot_bounds(conv, layout, tol, method):
    """Each packed region's ``bound``, all slots at once: (1 - CONV_SHARE) tol, the
    shares other than the convolution's, plus e / TIP_FLOOR for e the largest QAC
    bound of its slot's convolution pieces and :data:`PACKED_ROUNDINGS` ulps of the
    packed coordinates, at most tol.  That bounds what
    :func:`_achieved_bound` finds (e at smooth places, e / max(cos(phi / 2),
    TIP_FLOOR) at a corner turning by phi) without its work per region: (1 -
    CONV_SHARE) tol where the pieces are exact up to rounding (a TrueType glyph ⊕ an
    ellipse: e about 1e-13 tol in packed coordinates), tol (the sum's guarantee) for
    inexact ones (e over TIP_FLOOR CONV_SHARE tol) and other methods."""
    n = len(layout.offsets)
    if method != "qac":
        return np.full(n, float(tol))
    slot = layout.slot_of(pc.end_points(conv.pieces)[0]) if len(conv) else np.zeros(0, int)
    err = np.zeros(n + 1)
    np.maximum.at(err, np.where(slot < 0, n, slot), conv.bound)
    err = np.maximum(err[:n], err[n])   # a piece in no slot (none in a packed sum): all
    # the pieces were made at packed coordinates and are moved back: each carries a few
    # roundings of the packed coordinates' magnitude, which their QAC bounds (rounding
    # noise themselves where the pieces are exact) do not count; a sum made alone, at
    # its own smaller coordinates, is within them too
    if len(conv):
        err = err + PACKED_ROUNDINGS * np.finfo(float).eps * float(
            np.abs(pc.bboxes(conv.pieces)).max())
    return np.minimum(float(tol), (1.0 - CONV_SHARE) * tol + err / TIP_FLOOR)


def _not_vanished(loops, tol, which=""):
    """Raise LimitError when a sum came out empty: the sum of two regions with area
    has area, so nothing left means every part of it was thinner than the features
    the tolerance keeps (about 0.9 tol: the flattening and grid shares) and merged
    away; a tolerance a tenth as large is suggested."""
    if not loops:
        raise LimitError("minkowski sum%s: at tolerance %.3g every part of the sum is thinner "
                         "than the tolerance keeps and nothing is left; use a tolerance of at "
                         "most %.3g" % (which, tol, tol / 10), tol / 10)


def _sum(region_a, region_b, tol, method, gauss_pair, slot_of=None, member=None, first=None):
    """(boundary, debug) of A ⊕ B (:func:`minkowski_sum` after its checks).

    ``slot_of(points)``: which independent part (:class:`morph.packing.Packing`) each
    point is in; the corner pass then trims again only the parts it refines.
    ``member``: the hole test of :func:`morph.trim.boundary` (default
    :class:`_HoleTest` of A and B; packed frames, whose B differs per part, pass
    one that tests each hole with its own part's operands).  ``first``: the first
    round's convolution, as :func:`_first_round` takes it.
    """
    slot_of = slot_of or (lambda pts: np.zeros(len(pts), np.int64))
    if gauss_pair is None or gauss_pair.table is None:
        names = ("region_a", "region_b")
        gauss_pair = with_pair_table(gauss_pair or gauss_pair_of(region_a, region_b, names))
    conv, row_tol = _first_round(region_a, region_b, tol, method, gauss_pair, first)
    member = member or _HoleTest(region_a, region_b, tol)
    inside = _inside_chords(gauss_pair)
    done, redo = {}, None  # finished loops by slot; slots to trim (None: all)
    stopped = np.zeros(0, np.int64)  # slots whose corner pass ended (a pair could not refine)
    for round_ in range(TIP_ROUNDS + 1):
        slot = slot_of(pc.end_points(conv.pieces)[0])
        mine = None if redo is None else pl.member(slot, np.array(sorted(redo)))
        part = conv if mine is None else conv.take(mine)
        loops, out = _trimmed(part, tol, member, inside(part))
        fresh, extra = _by_slot(out, slot_of, unique(slot) if redo is None else sorted(redo))
        done.update(fresh)
        for k, more in extra:   # loops outside the slots trimmed (none in a packed sum)
            done.setdefault(k, []).extend(more)
        finer = _tip_tolerances(out, part, tol, slot_of, slot if mine is None else slot[mine])
        finer = {r: t for r, t in finer.items() if t < row_tol[r]}
        if not finer or round_ == TIP_ROUNDS:
            break
        rows = np.array(sorted(finer))
        row_slot = np.full(len(row_tol), -1, np.int64)
        row_slot[conv.row] = slot
        rows = rows[~pl.member(row_slot[rows], stopped)]
        again, rows, stopped = _refined_rows(
            lambda r, t: convolution(region_a, region_b, t, keep_type3=True, method=method,
                                     gauss_pair=gauss_pair, rows=r),
            rows, [finer[r] for r in rows.tolist()], row_tol, row_slot, stopped)
        if not len(rows):
            break
        refined = pl.member(conv.row, rows)
        redo = set(slot[refined].tolist())
        conv = ConvPieces.concat([conv.take(~refined), again])
    out = [loop for s in sorted(done) for loop in done[s]]
    return out, {"convolution": conv, "loops": loops, "holes": member.log}


def _refined_rows(convolve, rows, tols, row_tol, row_slot, stopped):
    """(convolution pieces, rows, stopped slots) of the corner pass's pairs ``rows``
    approximated again at ``tols`` (``convolve(rows, row_tol)``; ``row_tol`` updated
    in place).  A pair that cannot be refined that far ends the corner pass of its
    slot (the region packed there, ``row_slot`` of each row): the slot's rows are
    left out and their corners keep their error, as when the region is summed
    alone; the others are approximated again without them.  ``stopped``: the slots
    already ended, with those added."""
    rows, tols = np.asarray(rows, np.int64), np.asarray(tols, float)
    while len(rows):
        before = row_tol[rows]
        row_tol[rows] = tols
        try:
            return convolve(rows, row_tol), rows, stopped
        except ToleranceNotMetError as exc:
            row_tol[rows] = before
            failed = rows if exc.rows is None else np.asarray(exc.rows, np.int64)
            stopped = unique(np.concatenate([stopped, row_slot[failed]]))
            keep = ~pl.member(row_slot[rows], stopped)
            rows, tols = rows[keep], tols[keep]
    return None, rows, stopped


def _by_slot(out, slot_of, slots):
    """({slot: its loops of ``out``, in order} for each of ``slots`` (ints), [(slot,
    loops)] of the loops in no slot of ``slots``), by the slot of each loop's first
    point: one sort and a slice per slot (no call per loop)."""
    of = slot_of(pc.end_points([lp[0] for lp in out])[0]) if out else np.zeros(0, np.int64)
    order = np.argsort(of, kind="stable")
    ordered, of = [out[k] for k in order.tolist()], of[order]
    keys = np.asarray(slots, np.int64)
    lo, hi = np.searchsorted(of, keys), np.searchsorted(of, keys, "right")
    fresh = {k: ordered[a:b] for k, a, b in zip(keys.tolist(), lo.tolist(), hi.tolist())}
    rest = (~member(of, keys)).ravel().nonzero()[0]
    extra = [(k, [ordered[j] for j in rest[of[rest] == k].tolist()])
             for k in unique(of[rest]).tolist()]
    return fresh, extra


def _first_round(region_a, region_b, tol, method, gauss_pair, first=None):
    """(convolution pieces, per-row tolerances) of the first round: rows whose pieces
    may cross a non-neighbouring row's (:func:`morph.convolve.crossing_rows`, the only
    ones that can meet at a corner) within FIRST_SHARE of the convolution budget,
    the others within the whole budget; the whole budget for the pairs that
    cannot be subdivided that far (the corner pass then refines what it needs).
    ``first(row_tol)``, when given, is that convolution made another way (packed
    frames blend theirs from two fixed sets, :mod:`morph.frames`)."""
    budget = CONV_SHARE * tol
    row_tol = np.where(crossing_rows(gauss_pair, tol), FIRST_SHARE * budget, budget)
    while True:     # each pass gives at least one row the whole budget
        try:
            if first is not None:
                return first(row_tol), row_tol
            return convolution(region_a, region_b, row_tol, keep_type3=True,
                               method=method, gauss_pair=gauss_pair), row_tol
        except ToleranceNotMetError as exc:
            # the rows that cannot be subdivided that far (a row's subdivision is its
            # own: which rows fail does not depend on the regions packed with it)
            failed = np.arange(len(row_tol)) if exc.rows is None else np.asarray(exc.rows)
            failed = failed[row_tol[failed] < budget]
            if not len(failed):
                raise
            row_tol[failed] = budget


def _inside_chords(gauss_pair):
    """``inside(conv) -> mask``: the convolution pieces that the trimming may take as
    their chords (lines between their ends) without changing the sum it finds.

    Such a piece is a concave corner v of one operand (a vertex whose sweep is
    negative) paired with an edge of the other, every loop of which turns convex
    counter-clockwise (:func:`morph.gauss.turns_convex`; so that operand, say B,
    is a union of convex sets K with no holes): the piece is v + an arc of the
    boundary of one K.  Its chord lies in v + conv(arc), inside v + K, inside
    A ⊕ B (v is a point of A).  Replacing the piece by its chord changes the
    winding numbers of the loops only between the two, inside the sum, so no point
    outside the sum is filled; the piece is of type 3 (Fig. 20), never on the
    boundary, and the winding there stays at least 1 (both sides of the piece are
    inside the sum; a pocket left at winding 0 would be a hole, which the exact
    hole test fills).  So the boundary is the same, with no threshold.  What it
    saves: the arcs a round nib sweeps at a skeleton's concave corners are flattened
    near the crossing of the two offset sides (as finely as the topology there
    needs), 23 % of the flattened vertices of 300 hanzi strokes; a chord is one
    segment.
    (Loops that turn convex allow sweeps down to -TURN_EPS = -1e-9 rad: their arcs
    bulge out of their chords' side by at most 1e-9 of their length.)"""
    ta, tb = gauss_pair.edge_tables()
    i_of, j_of = gauss_pair.table[0], gauss_pair.table[1]
    a_convex = ta.n_loops > 0 and bool(_turn_convex(ta).all())
    b_convex = tb.n_loops > 0 and bool(_turn_convex(tb).all())

    def inside(conv):
        i, j = i_of[conv.row], j_of[conv.row]
        corner_a = ta.vertex[i] & (ta.sign[i] < 0) & b_convex
        corner_b = tb.vertex[j] & (tb.sign[j] < 0) & a_convex
        return (conv.type == 3) & (corner_a | corner_b)

    return inside


def _with_chords(pieces, mask):
    """:class:`morph.piece.Pieces` ``pieces`` with those of ``mask`` replaced by lines
    between their ends (:func:`_inside_chords`)."""
    k = np.flatnonzero(mask)
    if not len(k):
        return pieces
    starts, ends = pc.end_points(pieces.take(k))
    lines = np.ones((len(k), 2, 3))
    lines[:, 0, :2], lines[:, 1, :2] = starts, ends
    groups, line_ks, line_h = [], [k], [lines]
    for ks, h in pieces.groups:
        keep = ~mask[ks]
        if h.shape[1] == 2:
            line_ks.append(ks[keep])
            line_h.append(h[keep])
        elif keep.any():
            groups.append((ks[keep], h[keep]))
    ks = np.concatenate(line_ks)
    order = np.argsort(ks, kind="stable")
    groups.append((ks[order], np.concatenate(line_h)[order]))
    return pc.Pieces(groups, len(pieces))


def _trimmed(conv, tol, member, inside=None):
    """(loops, boundary) of convolution pieces: chained into loops and trimmed; the
    pieces of ``inside`` (a mask) as their chords (:func:`_inside_chords`)."""
    pieces = conv.pieces if inside is None else _with_chords(conv.pieces, inside)
    # ends of consecutive pieces agree to rounding in most places, but where a
    # tangent angle is solved at high curvature they can be a few 1e-9 of the size
    # apart: ends within a hundredth of tol are joined (inside the contraction share)
    loops, packed = chain(pieces, 0.01 * tol, packed=True)
    return loops, boundary(loops, FLAT_SHARE * tol, _grid_unit(tol), "positive", member,
                           CONTRACT_SHARE * tol, pieces=packed, origin=(0.0, 0.0))


def _grid_unit(tol):
    """The unit of the trimming's integer grid (:func:`morph.trim.boundary`),
    anchored at the origin: a sum's grid then depends on its own coordinates and
    ``tol`` only, not on the other regions packed with it (:func:`_packed_sums`)."""
    return GRID_SHARE * np.sqrt(2.0) * tol


def _tip_tolerances(out, conv, tol, slot_of=None, piece_slot=None):
    """Finer tolerances for the pairs whose pieces meet at a sharp corner of ``out``.

    Where the boundary turns by phi at a junction of two pieces, each within e of
    its exact curve, the corner of the approximations can lie up to
    e / cos(phi / 2) from the exact corner (two lines at that angle, each moved by
    e): at the tip of a thin wedge (phi near pi) far more than e.  The budget
    CONV_SHARE tol holds at such a corner when every piece through it has
    e <= CONV_SHARE tol cos(phi / 2) (TIP_MARGIN for phi measured on the
    approximations; cos(phi / 2) at least TIP_FLOOR).  The pieces through the
    corner are those whose control-point box comes within TIP_REACH tol of it (a
    superset: the corner was found on polylines within (FLAT_SHARE + GRID_SHARE) tol
    of them).  phi of a junction with such pieces is that of the corner of the pieces
    it stands for (:func:`morph.tips.corner_turns`: its own where it is a crossing
    of two of them; where the trimming left it off them, on its grid point, that of
    their sharpest crossing within TIP_REACH tol).  e of a piece whose bound is above
    that is its certified error along its part that can decide where the corner is
    (:func:`morph.tips.local_bounds`, :func:`_local_reach`).  Returns {table row:
    tolerance} for the pairs to approximate again.  The corners looked at are those
    whose budget the largest bound of their own region's pieces exceeds
    (``slot_of(points)`` and ``piece_slot``: the packed region of each point and of
    each piece of ``conv``, :class:`morph.packing.Packing`; None: one region): the
    corners a region refines do not depend on the regions packed with it.
    """
    bounds = conv.bound
    if float(bounds.max(initial=0.0)) <= 0 or not out:
        return {}
    pts, cos_half = _corners(out)
    # the corners where a piece of its own region can be above its budget (no other
    # corner can have one): those the rule below can pick, and only those
    worst = _slot_worst(bounds, piece_slot, pts, slot_of)
    floor = TIP_MARGIN * np.maximum(cos_half, TIP_FLOOR)
    sharp = np.flatnonzero(floor < worst / (CONV_SHARE * tol))
    if not len(sharp):
        return {}
    want = CONV_SHARE * tol * TIP_MARGIN * np.maximum(cos_half[sharp], TIP_FLOOR)
    corner, piece = _corners_near(pts[sharp], pc.bboxes(conv.pieces), TIP_REACH * tol)
    hit = bounds[piece] > want[corner]
    if hit.any():   # the turns of the corners those junctions stand for
        at = unique(corner[hit])
        sel = member(corner, at)
        turn = corner_turns(pts[sharp[at]], cos_half[sharp[at]],
                            np.searchsorted(at, corner[sel]), piece[sel], conv, tol)
        want[at] = CONV_SHARE * tol * TIP_MARGIN * np.maximum(turn, TIP_FLOOR)
        hit = bounds[piece] > want[corner]
    if hit.any():   # their error along their parts at the corner
        k = np.flatnonzero(hit)
        reach = _local_reach(corner, bounds[piece], want / (CONV_SHARE * tol), tol)
        hit[k] = local_bounds(conv, pts[sharp], reach, corner[k], piece[k]) > want[corner[k]]
    rows = unique(conv.row[piece[hit]])
    at = np.searchsorted(rows, conv.row[piece[hit]])
    finer = np.full(len(rows), np.inf)     # each row's least tolerance of its corners
    np.minimum.at(finer, at, want[corner[hit]])
    return dict(zip(rows.tolist(), finer.tolist()))


def _slot_worst(bounds, piece_slot, pts, slot_of):
    """The largest of ``bounds`` (one per piece) of the region (slot) of each point
    ``pts``: of all pieces where there are no slots (``slot_of`` None)."""
    if slot_of is None or piece_slot is None:
        return np.full(len(pts), float(bounds.max(initial=0.0)))
    at = slot_of(pts)
    n = int(max(piece_slot.max(initial=-1), at.max(initial=-1))) + 2
    worst = np.zeros(n)      # the last entry: slot -1 (points in no slot)
    np.maximum.at(worst, np.where(piece_slot < 0, n - 1, piece_slot), bounds)
    return worst[np.where(at < 0, n - 1, at)]


def _local_reach(corner, bounds, cos_half, tol):
    """The reach of each corner for :func:`morph.tips.local_bounds`: the part of a
    piece that can decide where the corner is.  With e the largest ``bounds`` of the
    (corner, piece) pairs ``corner`` and the corner's ``cos_half`` (turns as the
    corner pass counts them, TIP_MARGIN and TIP_FLOOR applied), the exact corner is
    within e / cos_half of the junction and the pieces' points matched to the exact
    curves' there within e more; at least TIP_REACH tol (the pieces through the
    corner)."""
    worst = np.zeros(len(cos_half))
    np.maximum.at(worst, corner, bounds)
    return np.maximum(TIP_REACH * tol, worst / cos_half + worst)


def _corners_near(pts, boxes, reach):
    """(corner, piece) index pairs: the boxes (k, 4) that come within ``reach`` of
    the points ``pts`` (j, 2), compared in blocks of about _BLOCK pairs."""
    step = max(1, _BLOCK // max(len(boxes), 1))
    corner, piece = [], []
    for c in range(0, len(pts), step):
        x, y = pts[c:c + step, 0:1], pts[c:c + step, 1:2]
        near = ((boxes[:, 0] - reach <= x) & (x <= boxes[:, 2] + reach)
                & (boxes[:, 1] - reach <= y) & (y <= boxes[:, 3] + reach))
        i, j = np.nonzero(near)
        corner.append(i + c)
        piece.append(j)
    return np.concatenate(corner), np.concatenate(piece)


def _achieved_bound(out, conv, tol, method):
    """A bound of the Hausdorff distance between ``out`` and the exact boundary, at
    most ``tol`` (the sum's own guarantee): the shares of tol that are not the
    convolution's, plus the largest convolution error e where the boundary is
    smooth and e / cos(phi / 2) at a junction turning by phi (cos(phi / 2) at
    least TIP_FLOOR, as the corner pass counts it) with e the largest bound of the
    pieces through it (along their parts there, as the corner pass counts it).  Only
    QAC bounds are a-priori bounds: for the other methods it is ``tol``.  What
    :func:`morph.budget.export_tolerance` takes."""
    return float(_achieved_bounds(out, conv, tol, method)[0])


def _achieved_bounds(out, conv, tol, method, out_part=None, conv_part=None, parts=1):
    """:func:`_achieved_bound` of each of ``parts`` independent sums at once (the
    frames of a packed sum): loop i of ``out`` belongs to part ``out_part[i]``,
    piece k of ``conv`` to ``conv_part[k]`` (None: all to part 0); a junction is
    compared with the pieces of its own part only.  (parts,) floats."""
    if method != "qac":
        return np.full(parts, float(tol))
    out_part = np.zeros(len(out), np.int64) if out_part is None else np.asarray(out_part)
    conv_part = np.zeros(len(conv), np.int64) if conv_part is None else np.asarray(conv_part)
    bounds = conv.bound
    err = np.zeros(parts)
    np.maximum.at(err, conv_part, bounds)
    if out:
        pts, cos_half = _corners(out)
        part_of = np.repeat(out_part, [len(loop) for loop in out])
        boxes = pc.bboxes(conv.pieces)
        lo, hi = boxes[:, :2] - TIP_REACH * tol, boxes[:, 2:] + TIP_REACH * tol
        for p in np.flatnonzero(err > 0):
            sharp = np.flatnonzero((part_of == p) & (cos_half < 1.0))
            mine = np.flatnonzero(conv_part == p)
            step = max(1, _BLOCK // max(len(mine), 1))
            for c in range(0, len(sharp), step):
                k = sharp[c:c + step]
                x, y = pts[k, 0:1], pts[k, 1:2]
                near = ((lo[mine, 0] <= x) & (x <= hi[mine, 0])
                        & (lo[mine, 1] <= y) & (y <= hi[mine, 1]))
                has = near.any(axis=1)
                if has.any():
                    err[p] = max(err[p], _tip_error(pts[k[has]], cos_half[k[has]],
                                                    near[has], bounds[mine], mine, conv, tol))
    return np.minimum(float(tol), (1.0 - CONV_SHARE) * tol + err)


def _tip_error(pts, cos_half, near, bounds, pieces, conv, tol):
    """The largest e / cos(phi / 2) of junctions ``pts`` (turns ``cos_half``), e the
    largest bound of the pieces ``near`` each ((j, k) bools over ``pieces``, indices
    into ``conv``, with those ``bounds``); where that is above the corner pass's
    budget, phi is the turn of the corner the junction stands for
    (:func:`morph.tips.corner_turns`) and e the pieces' error along their parts at
    the corner (:func:`morph.tips.local_bounds`), as the corner pass counts them."""
    worst = np.where(near, bounds, -np.inf).max(axis=1)
    big = np.flatnonzero(worst / np.maximum(cos_half, TIP_FLOOR) > CONV_SHARE * tol)
    if len(big):
        corner, col = np.nonzero(near[big])
        cos_half = cos_half.copy()
        cos_half[big] = corner_turns(pts[big], cos_half[big], corner, pieces[col], conv, tol)
        # the pieces' error along their parts at the corner (tips.local_bounds)
        floor = np.maximum(cos_half[big], TIP_FLOOR)
        reach = _local_reach(corner, bounds[col], TIP_MARGIN * floor, tol)
        local = np.zeros(len(big))
        np.maximum.at(local, corner, local_bounds(conv, pts[big], reach, corner, pieces[col]))
        worst = worst.copy()
        worst[big] = local
    return float(np.max(worst / np.maximum(cos_half, TIP_FLOOR)))


#: :func:`_achieved_bounds` compares junctions with pieces in blocks of about this
#: many (junction, piece) pairs
_BLOCK = 1 << 20


def _corners(out):
    """Junction points of the loops of ``out`` and cos(phi / 2) of the turn phi there
    (the pieces stacked once for their end tangents and end points)."""
    pieces = pc.Pieces.of([p for loop in out for p in loop])
    lens = np.fromiter(map(len, out), np.int64, len(out))
    ends = np.cumsum(lens) - 1
    nxt = np.arange(1, len(pieces) + 1)      # each piece's successor in its loop
    nxt[ends] = ends - lens + 1
    first, last = pc.end_tangents_many(pieces, strict=False)
    dot = np.einsum("ij,ij->i", last, first[nxt])
    pts = pc.end_points(pieces)[1]
    return pts, np.sqrt(np.clip(0.5 * (1.0 + dot), 0.0, 1.0))


#: The hole test's point needs to be no deeper than this many tol inside the hole's
#: ring (which is within about tol of the exact boundary): from there on the answer
#: stays the same, the exact one (:func:`_membership_depths`).
HOLE_DEPTH = 8.0


#: :func:`_membership_depths` flattens for depths of at most this many tol: coarser
#: flattenings of a glyph hardly have fewer points (a point or two per piece already)
HOLE_COARSEST = 64.0


def _membership_depths(depths, tol):
    """The depth each hole's point is tested at (:class:`morph.trim.holes.Membership`
    flattens A and B within a tenth of it, on a grid of a twentieth): powers of two
    times ``tol``, so that points share flattenings.  A point ``depth`` deep in its
    hole's ring lies at least depth - tol from the exact boundary of the sum (the
    rings are within the sum's tol of it); the flattened, rounded operands are
    within 0.14 of the key each, so the answer is the exact one where 0.28 key <
    depth - tol: key at most (depth - tol) / 2, and at least tol x 2^floor(log2(
    min(depth, tol) / tol)) (down to tol / 8) for points less than 3 tol deep,
    whose predicate keeps its tenth of min(depth, tol); at most HOLE_COARSEST tol."""
    d = np.maximum(depths, 1e-300) / tol
    near = np.clip(np.floor(np.log2(d)), -3, 0)
    far = np.floor(np.log2(np.maximum(0.5 * (d - 1.0), 1e-300)))
    return tol * 2.0 ** np.clip(np.maximum(near, far), -3, np.log2(HOLE_COARSEST))


class _HoleTest:
    """hole_test for :func:`morph.trim.boundary`: the exact predicate at the hole's
    deepest point, or one HOLE_DEPTH tol deep (A and B flattened within a tenth of
    the depth :func:`_membership_depths` gives the point)."""

    def __init__(self, region_a, region_b, tol):
        self.a, self.b, self.tol = region_a, region_b, tol
        self.cache = {}
        self.areas = None  # the loop areas of A, for every Membership (NaN: not yet)
        self.boxes = None  # the control boxes of A's loops
        self.log = []

    def __call__(self, ring, islands):
        return self.many([(ring, islands)])[0]

    def many(self, holes):
        """The test of every (ring, islands) of ``holes``, at points HOLE_DEPTH tol
        deep where there are such, found together
        (:func:`morph.trim.holes.points_deep_enough`)."""
        points, depths = points_deep_enough(holes, HOLE_DEPTH * self.tol)
        keys = _membership_depths(depths, self.tol)
        # no point inside (a hole of no area outside its islands): it stays a hole
        filled = np.zeros(len(points), bool)
        for key in unique(keys[depths > 0.0]).tolist():
            if key not in self.cache:
                if self.areas is None:
                    self.areas = np.full(len(self.a), np.nan)
                    self.boxes = control_boxes(self.a)
                self.cache[key] = Membership(self.a, self.b, key, self.areas, self.boxes)
            at = np.flatnonzero((keys == key) & (depths > 0.0))
            filled[at] = self.cache[key].many(points[at])
        self.log.extend(zip(points, depths.tolist(), filled.tolist()))
        return filled.tolist()


__all__ = ["minkowski_sum", "minkowski_sum_debug", "minkowski_sums", "check_operand",
           "TopologyError"]
