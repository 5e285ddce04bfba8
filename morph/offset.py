"""Offsets (paper Fig. 37): a region grown by an exact disk, region ⊕ disk(R).

The disk is an exact rational quadratic circle (:func:`morph.piece.circle`), so the
offset boundary is the QAC convolution of the region with a circle, trimmed to the
boundary by :func:`morph.minkowski.minkowski_sum`, within ``tol`` of the exact offset.
"""

import numpy as np

from . import piece as pc

__all__ = ["offset_region"]


def offset_region(loops, radius, tol, method="qac", return_bound=False):
    """Outward offset of a region by ``radius``: the Minkowski sum with a disk.

    ``radius`` and ``tol`` are absolute, in the region's units.  Holes shrink and
    close when the radius exceeds their inner radius.  A radius of at most 1e-9 tol
    (0 included) returns the input, which lies within the radius of the offset.
    With ``return_bound``: (loops, the error achieved, at most tol: the debug
    "bound" of :func:`morph.minkowski.minkowski_sum`; the radius for the input returned).

    Raises:
        ValueError: radius negative (insets are not supported) or not finite.
    """
    from .minkowski import minkowski_sum

    r = float(radius)
    if not np.isfinite(r):
        raise ValueError("offset radius must be finite, got %r" % (radius,))
    if r < 0:
        raise ValueError("negative offset radius %g: insets (erosion) are not supported; "
                         "only outward offsets (radius >= 0)" % r)
    if r <= 1e-9 * tol:
        # the region itself is within r of its offset (Hausdorff distance r): for a
        # radius far below tol it is the answer (a disk of radius 1e-300 has no curve
        # of nonzero length in floating point)
        out = [list(loop) for loop in loops]
        return (out, r) if return_bound else out
    disk = [pc.circle((0.0, 0.0), r)]
    if not return_bound:
        return minkowski_sum(loops, disk, tol, method=method)
    out, debug = minkowski_sum(loops, disk, tol, method=method, return_debug=True)
    return out, debug["bound"]
