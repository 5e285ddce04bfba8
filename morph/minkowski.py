"""Minkowski sums of regions: convolution (Secs. 3-5) trimmed to the boundary (Sec. 6).

(The module is not called ``sum`` so as not to shadow the builtin.)
"""

import numpy as np

from .convolve import chain, convolution
from .errors import TopologyError
from .limits import check_tolerance
from .trim import boundary
from .trim.holes import Membership, deepest_point

# shares of tol: convolution error, flattening, grid rounding (grid / sqrt 2),
# contraction of tiny runs; they add up to 1
CONV_SHARE = 0.75
FLAT_SHARE = 0.1
GRID_SHARE = 0.1
CONTRACT_SHARE = 0.05


def minkowski_sum(region_a, region_b, tol, method="qac", return_debug=False, gauss_pair=None):
    """Boundary of A ⊕ B as a region of rational Bézier pieces (Secs. 3-6).

    Every output point lies within ``tol`` of the exact boundary of A ⊕ B (tol
    absolute, in input units), split as: convolution pieces within 0.75 tol of the
    exact convolution curve (a-priori bound of :func:`morph.qac.qac_error_bound`,
    QAC; other methods of ``morph.methods.METHODS`` are sampled, not bounded),
    topology decided on polylines within 0.1 tol on a grid of 0.1·sqrt(2) tol
    (:func:`morph.trim.boundary`), runs shorter than 0.05 tol contracted.  Holes
    of the winding-number result are tested exactly, x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅,
    at their deepest point.  Where the exact sum has a hole or a gap narrower than
    about 1.5 tol (twice the convolution share), the approximated pieces may
    overlap across it and close it: there the exact boundary can be up to that
    width from the output (a sweep case at tol = 0.074 x the size shows it).
    Likewise where two pieces cross at a small angle theta (the tip of a wedge of
    the sum's boundary, narrower than that width), the crossing of the
    approximations can slide along the wedge by up to 0.75 tol / sin(theta / 2)
    (a sweep case: 1.7 tol at the tip of a hairline counter).  Normals are exact
    on QAC pieces.  Outer loops counter-clockwise, holes clockwise.  Raises LimitError (a ValueError) for a tolerance the operands
    cannot support (:func:`morph.limits.check_tolerance`), ValueError for an empty region,
    TopologyError if the convolution pieces do not close into loops.  ``gauss_pair``:
    the operands' Gauss maps when known already (:class:`morph.convolve.GaussPair`).
    """
    if not region_a or not region_b:
        raise ValueError("both regions must have at least one loop")
    check_tolerance(tol, region_a, region_b, operation="minkowski sum")
    conv = convolution(region_a, region_b, CONV_SHARE * tol, keep_type3=True, method=method,
                       gauss_pair=gauss_pair)
    pieces = [c.piece for c in conv]
    # ends of consecutive pieces agree to rounding in most places, but where a
    # tangent angle is solved at high curvature they can be a few 1e-9 of the size
    # apart: ends within a hundredth of tol are joined (inside the contraction share)
    loops = chain(pieces, 0.01 * tol)
    grid = GRID_SHARE * np.sqrt(2.0) * tol
    member = _HoleTest(region_a, region_b, tol)
    out = boundary(loops, FLAT_SHARE * tol, grid, "positive", member, CONTRACT_SHARE * tol)
    if return_debug:
        return out, {"convolution": conv, "loops": loops, "holes": member.log}
    return out


class _HoleTest:
    """hole_test for :func:`morph.trim.boundary`: the exact predicate at the hole's
    deepest point (A and B flattened within a tenth of max(depth, tol))."""

    def __init__(self, region_a, region_b, tol):
        self.a, self.b, self.tol = region_a, region_b, tol
        self.cache = {}
        self.log = []

    def __call__(self, ring, islands):
        x, depth = deepest_point(ring, islands)
        # flattenings fine enough for the depth, never coarser than tol, reused
        key = self.tol * 2.0 ** np.clip(np.floor(np.log2(max(depth, 1e-300) / self.tol)), -3, 0)
        if key not in self.cache:
            self.cache[key] = Membership(self.a, self.b, key)
        filled = self.cache[key](x)
        self.log.append((x, depth, filled))
        return filled


__all__ = ["minkowski_sum", "TopologyError"]
