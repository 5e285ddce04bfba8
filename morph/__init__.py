"""morph: Minkowski sums of curved planar shapes as exact-normal rational Bézier pieces.

Implements I.-K. Lee, M.-S. Kim, G. Elber, "Polynomial/Rational Approximation of
Minkowski Sum Boundary Curves" (1998).  Shapes are regions: lists of closed loops of
rational Bézier pieces ((n+1, 3) arrays of homogeneous control points), outer loops
counter-clockwise and holes clockwise (y up).
"""

__version__ = "0.1.0"
