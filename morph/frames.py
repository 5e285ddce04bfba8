"""Shape transformation by Minkowski sums: frames (1 - a) A ⊕ a B (paper Figs. 6, 36).

Each operand is first moved so that its area centroid is at the origin (the common
reference point), so the frames stay in place as a runs from 0 to 1: frame 0 is A
and the last frame is B (the other operand shrinks to the point at its centroid).
Scaling a region by a > 0 scales its Gauss map's positions but not its angles, so
one frame is one Minkowski sum of scaled copies: the Gauss maps of A and B and their
table of compatible pairs are computed once (:func:`morph.convolve.scaled_gauss_pair`),
and the inner frames are summed several at a time, moved apart as one packed sum
(:func:`_packed_frames`), so that every phase's array calls serve a group of frames.
Every convolution piece is linear in the positions of its two operands' points (its
weights depend on tangent directions only), so the first round's pieces of every
frame are blends (1 - a) P_A + a P_B of two fixed sets, made once
(:class:`_Blend`).
"""

import numpy as np

from . import convolve
from . import gauss
from . import piece as pc
from .errors import MorphError, OperandError, ToleranceNotMetError
from .limits import check_tolerance, fits_precision, point_budget
from .minkowski import minkowski_sum
from .operands import check_operand
from .polyline import unique
from .region import (Region, region_bbox, region_centroid, scale_region, translate_region,
                     validated)

__all__ = ["centered", "frames_bbox", "iter_frames", "morph_frames", "scale_region",
           "translate_region", "FRAME_GROUP"]

#: At most this many inner frames are summed together (:func:`_packed_frames`);
#: fewer when their estimated polyline points exceed the point budget of one sum.
#: Past a few frames the array calls' fixed cost is spread thin and a group costs
#: about the sum of its frames' work; a group's frames arrive together.
FRAME_GROUP = 8


def centered(loops):
    """The region moved so that its area centroid is at the origin."""
    c = np.asarray(region_centroid(loops), float)
    return translate_region(loops, -c)


def morph_frames(region_a, region_b, n, tol, progress=None, method="qac", cache=True,
                 batch=True, blend=True):
    """The n regions (1 - a) A ⊕ a B for a = 0, 1/(n-1), ..., 1, both centred.

    tol is absolute (input units) and applies to every frame as in
    :func:`morph.minkowski.minkowski_sum`.  ``progress`` (optional) is called with each
    frame index as it is done.  ``method`` is the convolution method (Sec. 4).
    With ``cache`` the Gauss maps of A and B and their compatible pairs, which do not
    depend on the scale factors, are computed once for all frames
    (:func:`morph.convolve.scaled_gauss_pair`); with ``batch`` too, up to
    :data:`FRAME_GROUP` inner frames are summed as one packed sum
    (:func:`_packed_frames`), each held to the budget of its own sum; with ``blend``
    (and ``cache``, method "qac") too, every frame's first-round convolution is a
    blend of two sets made once (:class:`_Blend`).  Each frame is a
    :class:`morph.region.Region` whose ``bound`` is the error it achieved (at most tol;
    0 for the end frames, which are the operands), what
    :meth:`morph.budget.Budget.after` takes.  :func:`iter_frames` gives the same
    frames one at a time.  Raises ValueError for n < 2.
    """
    frames = []
    for k, out in enumerate(iter_frames(region_a, region_b, n, tol, method, cache, batch,
                                        blend)):
        frames.append(out)
        if progress is not None:
            progress(k)
    return frames


def iter_frames(region_a, region_b, n, tol, method="qac", cache=True, batch=True, blend=True):
    """The frames of :func:`morph_frames`, in order, as they are done: a writer can
    store each frame as it arrives, holding at most one group of :data:`FRAME_GROUP`
    frames in memory.  A frame whose sum raises is preceded by every frame before it."""
    if n < 2:
        raise ValueError("need at least 2 frames, got %r" % (n,))
    a = centered(region_a)
    b = centered(region_b)
    alphas = np.linspace(0.0, 1.0, n)[1:-1]
    yield _operand(a)
    if len(alphas):
        base = convolve.with_pair_table(convolve.gauss_pair_of(a, b)) if cache else None
        blend = _Blend(base, alphas) if blend and base is not None and method == "qac" \
            else None
        if base is not None and batch:
            for group in _frame_groups(a, b, alphas, tol):
                yield from _packed_frames(a, b, alphas[group], tol, method, base, blend)
        else:
            for alpha in alphas:
                yield _one_frame(a, b, alpha, tol, method, base, blend)
    yield _operand(b)


def _operand(end):
    """An end frame: the centred operand itself, its error 0."""
    return Region._make(end, isinstance(end, Region) and end.validated, 0.0)


def _one_frame(a, b, alpha, tol, method, base, blend=None):
    """Frame (1 - alpha) A ⊕ alpha B as a sum of its own (``base``: the shared Gauss
    maps, or None), its first round's convolution blended by ``blend`` when given
    (a :class:`_Blend` of ``base``: the frame is then the one a packed sum gives)."""
    from . import minkowski as mk

    pair = None if base is None else convolve.scaled_gauss_pair(base, 1.0 - alpha, alpha)
    ra, rb = scale_region(a, 1.0 - alpha), scale_region(b, alpha)
    if blend is None:
        return minkowski_sum(ra, rb, tol, method=method, gauss_pair=pair)
    # minkowski_sum's checks and result, the sum with the blended first round
    if not ra or not rb:
        raise OperandError("both regions must have at least one loop")
    check_operand(ra, "region_a")
    check_operand(rb, "region_b")
    check_tolerance(tol, ra, rb, operation="minkowski sum")
    out, debug = mk._sum(ra, rb, tol, method, pair, first=lambda row_tol: blend.frames(
        row_tol, np.array([alpha]), np.zeros((1, 2)), pair))
    mk._not_vanished(out, tol)
    return validated(out, mk._achieved_bound(out, debug["convolution"], tol, method))


def _frame_groups(a, b, alphas, tol):
    """Index groups of consecutive frames to sum together: at most FRAME_GROUP
    frames whose operands' estimated polyline points (what
    :func:`morph.limits.check_tolerance` returns) fit the point budget of one sum.
    A frame whose operands or tolerance :func:`morph.minkowski.minkowski_sum` refuses
    is a group of its own: its own sum raises, after the frames before it.  The
    operands' checks (:func:`morph.operands.check_operand`: closed loops, signed
    area, weights, windings) compare lengths with lengths and areas with areas, so a
    scaled copy passes them exactly when its operand does: they are made once, on
    A and B."""
    try:
        check_operand(a, "region_a")
        check_operand(b, "region_b")
        operands_ok = True
    except MorphError:
        operands_ok = False
    points = []
    for t in alphas:
        try:
            points.append(check_tolerance(tol, scale_region(a, 1.0 - t), scale_region(b, t),
                                          operation="minkowski sum")
                          if operands_ok else np.inf)
        except MorphError:
            points.append(np.inf)
    groups, total, budget = [[]], 0.0, point_budget()
    for k, n in enumerate(points):
        if groups[-1] and (total + n > budget or len(groups[-1]) == FRAME_GROUP):
            groups.append([])
            total = 0.0
        groups[-1].append(k)
        total += n
    return [np.array(g) for g in groups]


def _packed_frames(a, b, alphas, tol, method, base, blend=None):
    """The frames (1 - t) A ⊕ t B for t in ``alphas`` as one packed sum, in order.

    Frame k's scaled A is moved to slot k of a :class:`morph.packing.Packing`
    (cells wider than every scaled A by B's control box, which holds every t B, plus
    PACK_GAP tol), so ``(A_k + o_k) ⊕ B_k = (A_k ⊕ B_k) + o_k`` and the frames' sums
    cannot meet.  The Gauss maps are ``base``'s, scaled (and moved) per frame; the
    table of compatible pairs is ``base``'s, one copy per frame with the edge
    indices of that frame's maps, so only pairs of one frame are convolved.  Holes
    are tested per frame (:class:`_SlotHoleTest`); each frame's ``bound`` is the
    error its own pieces achieved (:func:`morph.minkowski._achieved_bound`).  The
    budget of every frame is its own sum's; what the sum decides for all its pairs
    at once is decided for the group (the first round falls back to the whole
    convolution share, and the corner pass stops, when a pair of any frame cannot
    be subdivided that far).  Where the packed coordinates would be too large for
    tol, or the packed sum raises, the frames are summed one by one: a frame that
    raises then does so after the frames before it, with its own sum's error.
    ``blend`` (a :class:`_Blend` of ``base``): the first round's convolution is
    blended from its two fixed sets instead of approximated frame by frame.
    """
    from . import minkowski as mk
    from .packing import Packing, control_box

    frames = None
    if len(alphas) >= 2:
        regions_a = [scale_region(a, 1.0 - t) for t in alphas]
        regions_b = [scale_region(b, t) for t in alphas]
        layout = Packing(regions_a, control_box(b), mk.PACK_GAP * tol)
        if fits_precision(tol, layout.packed, b):
            pair = _packed_gauss_pair(base, alphas, layout.offsets)
            na = len(a)
            member = _SlotHoleTest([(layout.packed[k * na:(k + 1) * na], rb)
                                    for k, rb in enumerate(regions_b)], tol, layout)
            first = None if blend is None else (
                lambda row_tol: blend.frames(row_tol, alphas, layout.offsets, pair))
            try:
                out, debug = mk._sum(layout.packed, None, tol, method, pair, layout.slot_of,
                                     member=member, first=first)
                frames = _split_frames(out, debug["convolution"], layout, tol, method)
            except MorphError:
                frames = None
    if frames is None:
        frames = (_one_frame(a, b, t, tol, method, base, blend) for t in alphas)
    yield from frames


def _packed_gauss_pair(base, alphas, offsets):
    """``base`` (:class:`morph.convolve.GaussPair`, table computed) for every frame
    of ``alphas``: A's maps scaled by 1 - t and moved by the frame's offset, B's
    scaled by t, each frame's after the previous one's; the table repeated with
    each frame's edge indices (angles and multiples of 2 pi are the same)."""
    maps_a, maps_b = [], []
    for t, off in zip(alphas, offsets):
        maps_a += [_moved_edges(convolve.scale_edges(m, 1.0 - t), off) for m in base.maps_a]
        maps_b += [convolve.scale_edges(m, t) for m in base.maps_b]
    i, j, lo, hi, k = base.table
    na, nb, f = sum(map(len, base.maps_a)), sum(map(len, base.maps_b)), len(alphas)
    step = np.arange(f)[:, None]
    table = ((i[None, :] + na * step).ravel(), (j[None, :] + nb * step).ravel(),
             np.tile(lo, f), np.tile(hi, f), np.tile(k, f))
    return convolve.GaussPair(maps_a, maps_b, table)


class _Blend:
    """The first-round convolution pieces of every frame (1 - a) A ⊕ a B as blends of
    two fixed sets, made once from the unit operands' Gauss maps and pair table
    (``base``, a :class:`morph.convolve.GaussPair`).

    A convolution piece is (X, W) in homogeneous coordinates.  Its weights W depend
    only on tangent directions, which scaling keeps, and X is a sum of a term of
    A's points and one of B's (:func:`morph.qac.qac_parts` for QAC; a translated
    edge, corner or chord is a sum of points of the two), so the frame's piece is
    ((1 - a) X_A + a X_B + W o, W) for the sub-pair the unit operands' subdivision
    accepted, o the frame's offset in the packing.  Its error is (1 - a) e_A + a e_B:
    QAC replaces one side by a quadratic (e on that side, scaled with it), a corner
    drops the short side, a chord both sagittas.  So the unit operands are
    subdivided once, within ``row_tol / f`` with f = max(a, 1 - a) over the frames
    (every frame within ``row_tol``), and each group of frames is one array
    expression over the two sets.  Inner frames get pieces up to 1 / f finer than
    their own subdivision would make (a quarter power more QAC pieces).
    """

    def __init__(self, base, alphas):
        self.base = base
        self.scale = float(np.max(np.maximum(alphas, 1.0 - alphas)))
        self.sets = {}

    def frames(self, row_tol, alphas, offsets, pair):
        """:class:`morph.convolve.ConvPieces` of the frames ``alphas`` moved by
        ``offsets``, as the convolution of their packed pair ``pair`` (frame k's
        table rows after frame k - 1's) at ``row_tol`` (one per row of ``pair``'s
        table) gives them: in its row order, each piece within its row's tolerance.
        Where the unit operands cannot be subdivided that far, that convolution."""
        f, n = len(alphas), len(self.base.table[0])
        want = np.asarray(row_tol, float).reshape(f, n).min(axis=0)
        key = want.tobytes()
        if key not in self.sets:
            try:
                self.sets[key] = _unit_sets(self.base, want / self.scale)
            except ToleranceNotMetError:
                self.sets[key] = None
        sets = self.sets[key]
        if sets is None:
            return convolve.convolution(None, None, row_tol, keep_type3=True,
                                        gauss_pair=pair)
        return _blended(sets, self.base, np.asarray(alphas, float),
                        np.asarray(offsets, float))


def _unit_sets(base, tol, max_depth=30):
    """The two sets of :class:`_Blend` for the pairs of ``base``'s table, each row
    within its ``tol`` for both operands at unit scale: a
    :class:`morph.convolve.ConvPieces` whose pieces have 7 columns (X_A, X_B, W,
    e_A, e_B; the errors repeated along the rows) in the order the convolution
    gives its pieces (:func:`morph.convolve._convolve_table`)."""
    ta, tb = base.edge_tables()
    i, j, lo, hi, k = base.table
    tol = np.broadcast_to(np.asarray(tol, float), np.shape(i))
    off = gauss.TWO_PI * np.asarray(k, float)
    out = convolve._Produced()
    for p, st, points, of_a, forward in convolve.translated_batches(ta, tb, i, j, lo, hi, off):
        _add_moved(out, p, st, points, of_a, forward)
    pos = np.flatnonzero(ta.curved[i] & tb.curved[j])
    if len(pos):
        _curve_sets(out, ta, tb, pos, i[pos], j[pos], lo[pos], hi[pos], off[pos], tol[pos],
                    max_depth)
    return out.packed()


def _add_moved(out, pos, stack, points, curve_of_a, forward):
    """Pieces of a curve ``stack`` moved by ``points`` (one per row) as 7-column sets:
    the curve's term on its operand's side, the points' on the other, error 0;
    reversed where not ``forward``."""
    w = stack[:, :, 2:3]
    moved = points[:, None, :] * w
    xa, xb = (stack[:, :, :2], moved) if curve_of_a else (moved, stack[:, :, :2])
    st = np.concatenate([xa, xb, w, np.zeros(w.shape[:2] + (2,))], axis=2)
    st = np.where(forward[:, None, None], st, st[:, ::-1])
    out.add(pos, 0.0, st, 0.0, "translate")


def _curve_sets(out, ta, tb, pos, i, j, lo, hi, off, tol, max_depth):
    """Curve + curve pairs: Algorithm 4.1 as :func:`morph.convolve._qac_pairs` runs
    it (the same nodes, bounds and splits), each accepted node's piece as its two
    terms (:func:`_node_sets`) with its error on the side it comes from."""
    from . import qac

    names = np.array(qac.KIND_NAMES, object)
    for done, pieces, bounds in convolve.qac_batches(ta, tb, pos, i, j, lo, hi, off, tol,
                                                     max_depth, _node_sets):
        bounds = np.asarray(bounds, float)
        # the error's side: QAC's C2 or a corner's short piece is A's where swap
        e_a = np.where(done["swap"], bounds, 0.0)
        e_b = np.where(done["swap"], 0.0, bounds)
        chord = np.flatnonzero(done["kind"] == qac.CHORD)
        if len(chord):
            e_a[chord] = qac._sagitta_many(done["ca"][chord])
            e_b[chord] = qac._sagitta_many(done["cb"][chord])
        key = np.where(done["sa"] * done["sb"] > 0, done["lo"], -done["lo"])
        forward = done["sb"] > 0
        start = out.count
        for ks, st in pc.degree_groups(pieces):
            st = np.where(forward[ks][:, None, None], st, st[:, ::-1])
            err = np.broadcast_to(np.stack([e_a[ks], e_b[ks]], axis=1)[:, None, :],
                                  st.shape[:2] + (2,))
            out.count = start
            out.add(done["pos"][ks], key[ks], np.concatenate([st, err], axis=2), bounds[ks],
                    names[done["kind"][ks]], seq=ks)
        out.count = start + len(pieces)


def _node_sets(nodes):
    """:func:`morph.qac.piece_nodes` as two terms: each accepted node's piece along
    ca as (X_A, X_B, W) (n+1, 5), None where a QAC piece has a weight <= 0.  A
    corner or chord is built twice, once with B's points at the origin and once
    with A's (the weights kept): both are linear in the points.  The nodes of each
    kind (and role) at once, with :mod:`morph.qac`'s operations row by row."""
    from . import qac

    ca, cb, sa, sb = nodes["ca"], nodes["cb"], nodes["sa"], nodes["sb"]
    kind, swap = nodes["kind"], nodes["swap"]
    out = [None] * len(ca)
    for long_is_b in (False, True):
        rows = np.flatnonzero((kind == qac.CORNER) & (swap == long_is_b))
        if len(rows):
            a, b, same = ca[rows], cb[rows], sa[rows] == sb[rows]
            _put(out, rows, _two_term_stack(
                qac.corner_pieces(a, _at_origin(b), same, long_is_b),
                qac.corner_pieces(_at_origin(a), b, same, long_is_b)))
    rows = np.flatnonzero(kind == qac.CHORD)
    if len(rows):
        a, b, same = ca[rows], cb[rows], sa[rows] == sb[rows]
        _put(out, rows, _two_term_stack(qac.chord_pieces(a, _at_origin(b), same),
                                        qac.chord_pieces(_at_origin(a), b, same)))
    for sw in (False, True):
        sel = np.flatnonzero((kind == qac.QAC) & (swap == sw))
        if len(sel):
            c1 = (cb if sw else ca)[sel]
            # C1 is B's where swap (QAC's role): its term is B's; reversed where C1
            # = cb runs against ca
            back = sw & (sa[sel] != sb[sel])
            for r, piece in zip(sel.tolist(), _qac_sets(c1, nodes["q2"][sel], sw, back)):
                out[r] = piece
    return out


def _put(out, rows, stack):
    """out[rows[k]] = stack[k] (its rows, views), in one C-level pass."""
    list(map(out.__setitem__, rows.tolist(), stack))


def _two_term_stack(piece_a, piece_b):
    """(X_A, X_B, W) of pieces built once from A's points and once from B's, rows of
    stacks: (k, n+1, 5)."""
    return np.concatenate([piece_a[..., :2], piece_b[..., :2], piece_a[..., 2:]], axis=2)


def _qac_sets(c1, q2, sw, back):
    """The QAC pieces of :func:`morph.qac.qac_parts` for each row of a stack c1 with
    quadratics q2 as (X1, XQ, W) (XQ first where ``sw``), as
    :func:`morph.qac.qac_pieces` makes them (rows whose tangent numerator vanishes
    at an end with their ends divided out), reversed where ``back``; None where a
    weight is <= 0.  A list."""
    from . import qac

    out = [None] * len(c1)
    for rows, _, h, odd in pc.numerator_groups(c1):
        x1, xq, w = qac.qac_parts(c1[rows], h, q2[rows])
        st = np.concatenate([xq, x1, w[:, :, None]] if sw else [x1, xq, w[:, :, None]], axis=2)
        st[back[rows]] = st[back[rows]][:, ::-1]
        good = (w > 0).all(axis=1) & ~odd
        _put(out, rows[good], st[good])
        for row in rows[odd].tolist():
            h1 = pc.tangent_numerator(c1[row])
            x1r, xqr, wr = (x[0] for x in qac.qac_parts(c1[row][None], h1[None],
                                                        q2[row][None]))
            if np.all(wr > 0):
                piece = np.concatenate([xqr, x1r, wr[:, None]] if sw else
                                       [x1r, xqr, wr[:, None]], axis=1)
                out[row] = piece[::-1].copy() if back[row] else piece
    return out


def _at_origin(stack):
    """A stack of pieces with every point at the origin, the weights kept."""
    out = np.zeros_like(stack)
    out[:, :, 2] = stack[:, :, 2]
    return out


def _blended(sets, base, alphas, offsets):
    """The 7-column ``sets`` of :func:`_unit_sets` blended for each frame (``alphas``,
    ``offsets``): :class:`morph.convolve.ConvPieces` of the frames one after the
    other, as the convolution of their packed pair gives them (rows, loops and
    edges numbered frame by frame)."""
    ta, tb = base.edge_tables()
    f, n, m = len(alphas), len(sets), len(base.table[0])
    a = alphas[:, None, None, None]
    groups, e = [], np.zeros((n, 2))
    for ks, h in sets.pieces.groups:
        w = h[None, :, :, 4:5]
        x = (1.0 - a) * h[None, :, :, 0:2] + a * h[None, :, :, 2:4] \
            + offsets[:, None, None, :] * w
        st = np.concatenate([x, np.broadcast_to(w, x.shape[:3] + (1,))], axis=3)
        groups.append(((np.arange(f)[:, None] * n + ks[None]).ravel(),
                       st.reshape((-1,) + st.shape[2:])))
        e[ks] = h[:, 0, 5:7]
    bound = ((1.0 - alphas)[:, None] * e[None, :, 0] + alphas[:, None] * e[None, :, 1]).ravel()
    i, j = base.table[0][sets.row], base.table[1][sets.row]
    typ = convolve.pair_type(ta.sign[i], tb.sign[j], ta.vertex[i], tb.vertex[j])
    frame = np.repeat(np.arange(f), n)
    source = np.tile(np.stack([ta.loop[i], ta.index[i], tb.loop[j], tb.index[j]], axis=1),
                     (f, 1)).astype(int)
    source[:, 0] += frame * ta.n_loops
    source[:, 2] += frame * tb.n_loops
    return convolve.ConvPieces(pc.Pieces(groups, f * n), bound, np.tile(sets.kind, f),
                               np.tile(np.asarray(typ, int), f),
                               (frame * m + np.tile(sets.row, f)).astype(int), source)


def _moved_edges(edges, offset):
    """The Gauss map of a loop moved by ``offset``: the same angles, moved positions."""
    offset = np.asarray(offset, float)
    return [gauss.Edge(e.kind, None if e.piece is None else pc.translate(e.piece, offset),
                       np.asarray(e.point, float) + offset, e.theta, e.sweep) for e in edges]


def _split_frames(out, conv, layout, tol, method):
    """The packed sum's loops, one validated region per frame moved back, each with
    the bound its own convolution pieces achieved (all frames' bounds in one
    :func:`morph.minkowski._achieved_bounds`, all loops moved back at once)."""
    from . import minkowski as mk
    from .packing import _translated

    f = len(layout.offsets)
    slot = layout.slot_of(np.array([pc.start(loop[0]) for loop in out]).reshape(-1, 2))
    # conv: the last round's pieces (:class:`morph.convolve.ConvPieces`), all frames'
    starts = pc.end_points(conv.pieces)[0] if len(conv) else np.zeros((0, 2))
    conv_slot = layout.slot_of(starts)
    if (slot < 0).any():
        raise ValueError("a loop of the packed frames lies outside every slot")
    bounds = mk._achieved_bounds(out, conv, tol, method, slot, conv_slot, f)
    moved = _translated(out, -layout.offsets[slot]) if out else []
    frames = []
    for k in range(f):
        loops = [loop for loop, s in zip(moved, slot) if s == k]
        mk._not_vanished(loops, tol, " of frame %d" % k)
        frames.append(validated(loops, bounds[k]))
    return frames


class _SlotHoleTest:
    """The hole test of a packed sum of frames: each hole ring goes to the exact
    membership test (:class:`morph.minkowski._HoleTest`) of its own frame, on that
    frame's moved A and its B (``parts``: (A_k + o_k, B_k) per slot), by the slot of
    the ring's first point; the holes of one frame are tested together."""

    def __init__(self, parts, tol, layout):
        from .minkowski import _HoleTest

        self.tests = [_HoleTest(pa, pb, tol) for pa, pb in parts]
        self.layout = layout

    @property
    def log(self):
        return [entry for test in self.tests for entry in test.log]

    def __call__(self, ring, islands):
        return self.many([(ring, islands)])[0]

    def many(self, holes):
        slot = self.layout.slot_of(np.array([ring[0] for ring, _ in holes]).reshape(-1, 2))
        if (slot < 0).any():
            raise ValueError("a hole of the packed frames lies outside every slot")
        out = [False] * len(holes)
        for s in unique(slot).tolist():
            idx = np.flatnonzero(slot == s)
            for k, filled in zip(idx, self.tests[s].many([holes[k] for k in idx])):
                out[k] = filled
        return out


def frames_bbox(region_a, region_b):
    """The tight box of every frame together: the union of the boxes of centred A and
    B.  A box's sides are the support function h(u) = max <x, u> at the four axis
    directions, and h((1 - a) A ⊕ a B) = (1 - a) h(A) + a h(B) lies between h(A) and
    h(B); so a writer can fix the frame box before the first sum is done."""
    boxes = np.array([region_bbox(centered(r)) for r in (region_a, region_b)])
    return np.concatenate([boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)])
