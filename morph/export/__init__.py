"""Export: rational pieces -> polynomial cubic / quadratic Béziers with a certified bound.

SVG path data and font outlines hold polynomial cubics (CFF, SVG) or quadratics
(TrueType); the pipeline's pieces are rational.  Each rational piece is covered by
few cubics, fitted by kurbo's method (:mod:`.fit`) and every one *certified* against
the exact piece, never only sampled (:mod:`.certify`); the segments are found by a
greedy search run for all pieces of all loops in lockstep (:mod:`.search`,
:mod:`.greedy`; then one segment fewer where it may fit, :mod:`.refine`), on the
pieces of the whole batch held as one array per degree (:mod:`.bank`); loops
are split at corners only so that cubics span smooth joins (:mod:`.loops`), and
TrueType quadratics come from the cubics by cu2qu (:mod:`.quadratic`).  Writers pass
the export share of a user's tolerance (:func:`morph.budget.plan`).
"""

from .certify import CubicFit, cubic_bound
from .loops import loops_to_beziers
from .quadratic import loops_to_quadratics
from .search import piece_to_cubics
# the one-loop and one-piece forms and the chain search, importable here too
from .certify import fit_cubic  # noqa: F401
from .loops import JOIN_ANGLE, loop_to_beziers, loop_to_cubics, smooth_runs  # noqa: F401
from .quadratic import loop_to_quadratics, piece_to_quadratics  # noqa: F401
from .search import chain_segments, cubic_segments  # noqa: F401

__all__ = ["CubicFit", "cubic_bound", "piece_to_cubics", "loops_to_beziers",
           "loops_to_quadratics"]
