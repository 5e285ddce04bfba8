"""Configuration-space obstacles (paper Figs. 4 and 38).

A robot R translating in the plane, placed with its reference point at p, occupies
p + (R - ref).  It overlaps the obstacle O iff p ∈ O ⊕ (ref - R): the C-space
obstacle is the Minkowski sum of the obstacle with the robot reflected through its
reference point.  The reflection x -> 2 ref - x is a rotation by pi, so it keeps the
orientation of loops (outer CCW, holes CW) and the pieces stay exact.

The other way round, a robot that must stay inside a container C (a room) fits at p
iff p + (R - ref) ⊂ C: the free positions are the erosion C ⊖ (R - ref)
(:func:`free_space`, by :func:`morph.offset.erode_region`).
"""

import numpy as np

from .region import transform_region, translate_region

__all__ = ["reflect_region", "place_robot", "cspace_obstacle", "free_space"]


def reflect_region(loops, reference=(0.0, 0.0)):
    """``reference - R``: the region relative to ``reference``, negated.

    A rotation by pi (keeps orientation: outer loops stay CCW).
    """
    rx, ry = map(float, reference)
    return transform_region(loops, [[-1.0, 0.0, rx], [0.0, -1.0, ry]])


def place_robot(robot, position, reference=(0.0, 0.0)):
    """The robot translated so that its reference point lies at ``position``."""
    return translate_region(robot, np.asarray(position, float) - np.asarray(reference, float))


def cspace_obstacle(obstacle, robot, tol, reference=(0.0, 0.0), method="qac"):
    """C-space obstacle O ⊕ (−R) of a translating robot about its reference point.

    A position p of the reference point is a collision iff p lies in the returned
    region (within ``tol``, absolute, in the shapes' units; its ``bound`` the error
    achieved, see :func:`morph.minkowski.minkowski_sum`).
    """
    from .minkowski import minkowski_sum

    return minkowski_sum(obstacle, reflect_region(robot, reference), tol, method=method)


def free_space(container, robot, tol, reference=(0.0, 0.0), method="qac"):
    """Positions of the reference point where the robot lies inside the container:
    C ⊖ (R − ref), exact-normal curves within ``tol``; [] where the robot fits
    nowhere; its ``bound`` as :func:`cspace_obstacle`'s."""
    from .offset import erode_region

    relative = translate_region(robot, -np.asarray(reference, float))
    return erode_region(container, relative, tol, method=method)
