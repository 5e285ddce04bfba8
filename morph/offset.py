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
    close when the radius exceeds their inner radius.  Radius 0 returns the input.
    With ``return_bound``: (loops, the error achieved, at most tol: the debug
    "bound" of :func:`morph.minkowski.minkowski_sum`, 0 for radius 0).

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
    if r == 0:
        out = [list(loop) for loop in loops]
        return (out, 0.0) if return_bound else out
    disk = [pc.circle((0.0, 0.0), r)]
    if not return_bound:
        return minkowski_sum(loops, disk, tol, method=method)
    out, debug = minkowski_sum(loops, disk, tol, method=method, return_debug=True)
    return out, debug["bound"]
