"""Shape transformation by Minkowski sums: frames (1 - a) A ⊕ a B (paper Figs. 6, 36).

Each operand is first moved so that its area centroid is at the origin (the common
reference point), so the frames stay in place as a runs from 0 to 1: frame 0 is A
and the last frame is B (the other operand shrinks to the point at its centroid).
Scaling a region by a > 0 scales its Gauss map's positions but not its angles, so
one frame is one Minkowski sum of scaled copies: the Gauss maps of A and B and their
table of compatible pairs are computed once (:func:`morph.convolve.scaled_gauss_pair`),
and the inner frames are summed several at a time, moved apart as one packed sum
(:func:`_packed_frames`), so that every phase's array calls serve a group of frames.
"""

import numpy as np

from . import convolve
from . import gauss
from . import piece as pc
from .errors import MorphError
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
                 batch=True):
    """The n regions (1 - a) A ⊕ a B for a = 0, 1/(n-1), ..., 1, both centred.

    tol is absolute (input units) and applies to every frame as in
    :func:`morph.minkowski.minkowski_sum`.  ``progress`` (optional) is called with each
    frame index as it is done.  ``method`` is the convolution method (Sec. 4).
    With ``cache`` the Gauss maps of A and B and their compatible pairs, which do not
    depend on the scale factors, are computed once for all frames
    (:func:`morph.convolve.scaled_gauss_pair`); with ``batch`` too, up to
    :data:`FRAME_GROUP` inner frames are summed as one packed sum
    (:func:`_packed_frames`), each held to the budget of its own sum.  Each frame is a
    :class:`morph.region.Region` whose ``bound`` is the error it achieved (at most tol;
    0 for the end frames, which are the operands), what
    :meth:`morph.budget.Budget.after` takes.  :func:`iter_frames` gives the same
    frames one at a time.  Raises ValueError for n < 2.
    """
    frames = []
    for k, out in enumerate(iter_frames(region_a, region_b, n, tol, method, cache, batch)):
        frames.append(out)
        if progress is not None:
            progress(k)
    return frames


def iter_frames(region_a, region_b, n, tol, method="qac", cache=True, batch=True):
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
        if base is not None and batch:
            for group in _frame_groups(a, b, alphas, tol):
                yield from _packed_frames(a, b, alphas[group], tol, method, base)
        else:
            for alpha in alphas:
                yield _one_frame(a, b, alpha, tol, method, base)
    yield _operand(b)


def _operand(end):
    """An end frame: the centred operand itself, its error 0."""
    return Region._make(end, isinstance(end, Region) and end.validated, 0.0)


def _one_frame(a, b, alpha, tol, method, base):
    """Frame (1 - alpha) A ⊕ alpha B as a sum of its own (``base``: the shared Gauss
    maps, or None)."""
    pair = None if base is None else convolve.scaled_gauss_pair(base, 1.0 - alpha, alpha)
    return minkowski_sum(scale_region(a, 1.0 - alpha), scale_region(b, alpha), tol,
                         method=method, gauss_pair=pair)


def _frame_groups(a, b, alphas, tol):
    """Index groups of consecutive frames to sum together: at most FRAME_GROUP
    frames whose operands' estimated polyline points (what
    :func:`morph.limits.check_tolerance` returns) fit the point budget of one sum.
    A frame whose operands or tolerance :func:`morph.minkowski.minkowski_sum` refuses
    is a group of its own: its own sum raises, after the frames before it."""
    points = []
    for t in alphas:
        ra, rb = scale_region(a, 1.0 - t), scale_region(b, t)
        try:
            check_operand(ra, "region_a")
            check_operand(rb, "region_b")
            points.append(check_tolerance(tol, ra, rb, operation="minkowski sum"))
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


def _packed_frames(a, b, alphas, tol, method, base):
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
            try:
                out, debug = mk._sum(layout.packed, None, tol, method, pair, layout.slot_of,
                                     member=member)
                frames = _split_frames(out, debug["convolution"], layout, tol, method)
            except MorphError:
                frames = None
    if frames is None:
        frames = (_one_frame(a, b, t, tol, method, base) for t in alphas)
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


def _moved_edges(edges, offset):
    """The Gauss map of a loop moved by ``offset``: the same angles, moved positions."""
    offset = np.asarray(offset, float)
    return [gauss.Edge(e.kind, None if e.piece is None else pc.translate(e.piece, offset),
                       np.asarray(e.point, float) + offset, e.theta, e.sweep) for e in edges]


def _split_frames(out, conv, layout, tol, method):
    """The packed sum's loops, one validated region per frame moved back, each with
    the bound its own convolution pieces achieved."""
    from . import minkowski as mk

    f = len(layout.offsets)
    slot = layout.slot_of(np.array([pc.start(loop[0]) for loop in out]).reshape(-1, 2))
    # conv: the last round's pieces (:class:`morph.convolve.ConvPieces`), all frames'
    starts = pc.end_points(conv.pieces)[0] if len(conv) else np.zeros((0, 2))
    conv_slot = layout.slot_of(starts)
    if (slot < 0).any():
        raise ValueError("a loop of the packed frames lies outside every slot")
    frames = []
    for k in range(f):
        loops = [loop for loop, s in zip(out, slot) if s == k]
        mk._not_vanished(loops, tol, " of frame %d" % k)
        bound = mk._achieved_bound(loops, conv.take(conv_slot == k), tol, method)
        frames.append(validated(translate_region(loops, -layout.offsets[k]), bound))
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
