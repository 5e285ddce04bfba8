"""Offsets (paper Fig. 37): a region grown by an exact disk, region ⊕ disk(R), or
shrunk by one (an inset, the erosion region ⊖ disk(R)).

The disk is an exact rational quadratic circle (:func:`morph.piece.circle`), so the
offset boundary is the QAC convolution of the region with a circle, trimmed to the
boundary by :func:`morph.minkowski.minkowski_sum`, within ``tol`` of the exact offset.
An inset is the same sum on the complement: A ⊖ D = not((not A) ⊕ (−D)), D = −D for a
disk, with "not A" a box around A, margin beyond 2 R, with A's loops as its holes
(:func:`inset_region`; any region B in place of the disk: :func:`erode_region`).
"""

import numpy as np

from . import piece as pc
from .region import Region, region_bbox, reverse_loop, validated

__all__ = ["erode_region", "inset_region", "offset_region"]


def offset_region(loops, radius, tol, method="qac"):
    """Offset of a region by ``radius``: outward (the Minkowski sum with a disk) for
    a positive radius, inward (:func:`inset_region` by -radius) for a negative one.

    ``radius`` and ``tol`` are absolute, in the region's units.  Outward, holes shrink
    and close when the radius exceeds their inner radius.  A radius of at most 1e-9
    tol in size (0 included) returns the input, which lies within the radius of the
    offset.  Returns a :class:`morph.region.Region` whose ``bound`` is the error
    achieved, at most tol (that of :func:`morph.minkowski.minkowski_sum`; the radius
    for the input returned).

    Raises:
        ValueError: radius not finite.
    """
    from .minkowski import minkowski_sum

    r = float(radius)
    if not np.isfinite(r):
        raise ValueError("offset radius must be finite, got %r" % (radius,))
    if r < -1e-9 * tol:
        return inset_region(loops, -r, tol, method)
    if r <= 1e-9 * tol:
        # the region itself is within |r| of its offset (Hausdorff distance |r|): for
        # a radius far below tol, either sign, it is the answer (a disk of radius 1e-300 has no curve
        # of nonzero length in floating point)
        return Region._make(loops, isinstance(loops, Region) and loops.validated, abs(r))
    return minkowski_sum(loops, [pc.circle((0.0, 0.0), r)], tol, method=method)


def inset_region(loops, radius, tol, method="qac"):
    """Inward offset (erosion) of a region by ``radius`` > 0: the points whose disk
    of that radius lies in the region, :func:`erode_region` by the exact disk.

    Exact-normal curves within ``tol`` of the inner offset, sharp where the region's
    convex corners are (the inset of a square is a smaller square).  Parts narrower
    than 2 ``radius`` vanish; a region narrower everywhere gives [].  The region is
    taken as given: a crack in it, however narrow, is a channel 2 ``radius`` wide in
    the inset (erosion is not continuous in its input).
    The result's ``bound`` as :func:`offset_region`'s.
    """
    r = float(radius)
    if not (np.isfinite(r) and r > 0):
        raise ValueError("inset radius must be positive and finite, got %r" % (radius,))
    return erode_region(loops, [pc.circle((0.0, 0.0), r)], tol, method)


def erode_region(loops, shape, tol, method="qac"):
    """The erosion (Minkowski difference) A ⊖ B = {x : x + B inside A} of a region A
    by a region B, as A ⊖ B = not((not A) ⊕ (−B)).

    "not A" is a box around A, its margin twice B's extent and 1 % of A's size (so
    the box's own sum stays clear of A's), holding A's loops reversed (outer loops
    become holes, holes become islands); −B is B turned by pi about the origin (its
    loops keep their orientation).  The sum's loops other than the grown box, the
    one reaching lowest, are the boundary of A ⊖ B reversed back: exact-normal curves
    within ``tol`` (absolute) of it.  Parts of A that B does not fit in vanish; []
    when B fits nowhere.  The result's ``bound`` is the error achieved (that of
    :func:`morph.minkowski.minkowski_sum`).
    """
    from .minkowski import minkowski_sum
    from .region import transform_region

    x0, y0, x1, y1 = region_bbox(loops)
    extent = float(np.abs(np.reshape(region_bbox(shape), (2, 2))).max())
    m = 2.0 * extent + 0.01 * max(x1 - x0, y1 - y0)
    corners = np.array([[x0 - m, y0 - m], [x1 + m, y0 - m], [x1 + m, y1 + m], [x0 - m, y1 + m]])
    box = [pc.line(corners[k], corners[(k + 1) % 4]) for k in range(4)]
    complement = [box] + [reverse_loop(loop) for loop in loops]
    if isinstance(loops, Region) and loops.validated:
        complement = validated(complement)  # A's loops reversed: holes and islands of the box
    turned = transform_region(shape, [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    out = minkowski_sum(complement, turned, tol, method=method)
    lows = [region_bbox([loop])[1] for loop in out]
    grown_box = int(np.argmin(lows))
    return validated((reverse_loop(loop) for k, loop in enumerate(out) if k != grown_box),
                     out.bound)
