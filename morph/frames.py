"""Shape transformation by Minkowski sums: frames (1 - a) A ⊕ a B (paper Figs. 6, 36).

Each operand is first moved so that its area centroid is at the origin (the common
reference point), so the frames stay in place as a runs from 0 to 1: frame 0 is A
and the last frame is B (the other operand shrinks to the point at its centroid).
Scaling a region by a > 0 scales its Gauss map's positions but not its angles, so
one frame is one Minkowski sum of scaled copies.
"""

import numpy as np

from . import convolve
from .minkowski import minkowski_sum
from .region import Region, region_bbox, region_centroid, scale_region, translate_region

__all__ = ["centered", "frames_bbox", "iter_frames", "morph_frames", "scale_region",
           "translate_region"]


def centered(loops):
    """The region moved so that its area centroid is at the origin."""
    c = np.asarray(region_centroid(loops), float)
    return translate_region(loops, -c)


def morph_frames(region_a, region_b, n, tol, progress=None, method="qac", cache=True):
    """The n regions (1 - a) A ⊕ a B for a = 0, 1/(n-1), ..., 1, both centred.

    tol is absolute (input units) and applies to every frame as in
    :func:`morph.minkowski.minkowski_sum`.  ``progress`` (optional) is called with each
    frame index as it is done.  ``method`` is the convolution method (Sec. 4).
    With ``cache`` the Gauss maps of A and B and their compatible pairs, which do not
    depend on the scale factors, are computed once for all frames
    (:func:`morph.convolve.scaled_gauss_pair`).  Each frame is a
    :class:`morph.region.Region` whose ``bound`` is the error it achieved (at most tol;
    0 for the end frames, which are the operands), what
    :meth:`morph.budget.Budget.after` takes.  :func:`iter_frames` gives the same
    frames one at a time.  Raises ValueError for n < 2.
    """
    frames = []
    for k, out in enumerate(iter_frames(region_a, region_b, n, tol, method, cache)):
        frames.append(out)
        if progress is not None:
            progress(k)
    return frames


def iter_frames(region_a, region_b, n, tol, method="qac", cache=True):
    """The frames of :func:`morph_frames`, one at a time, in order: a writer can store
    each frame as it is done, holding one in memory."""
    if n < 2:
        raise ValueError("need at least 2 frames, got %r" % (n,))
    a = centered(region_a)
    b = centered(region_b)
    base = convolve.with_pair_table(convolve.gauss_pair_of(a, b)) if cache and n > 2 else None
    for alpha in np.linspace(0.0, 1.0, n):
        if alpha == 0.0 or alpha == 1.0:
            end = a if alpha == 0.0 else b
            yield Region._make(end, isinstance(end, Region) and end.validated, 0.0)
            continue
        pair = None if base is None else convolve.scaled_gauss_pair(base, 1.0 - alpha, alpha)
        yield minkowski_sum(scale_region(a, 1.0 - alpha), scale_region(b, alpha), tol,
                            method=method, gauss_pair=pair)


def frames_bbox(region_a, region_b):
    """The tight box of every frame together: the union of the boxes of centred A and
    B.  A box's sides are the support function h(u) = max <x, u> at the four axis
    directions, and h((1 - a) A ⊕ a B) = (1 - a) h(A) + a h(B) lies between h(A) and
    h(B); so a writer can fix the frame box before the first sum is done."""
    boxes = np.array([region_bbox(centered(r)) for r in (region_a, region_b)])
    return np.concatenate([boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)])
