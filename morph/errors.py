"""The project's exceptions: one base class, errors that keep the failing data.

Every public function raises a subclass of :class:`MorphError` for bad geometry or
input, and :class:`ValueError` (or a subclass of both, such as :class:`LimitError`
and :class:`NibError`) for bad arguments.  Each error keeps what failed as
attributes (``source``, ``piece``, ``achieved``, ``loops``, ``nib``, ``suggestion``),
as fontTools' ``cu2qu`` errors do.

The command line (:mod:`morph.cli`) prints one line ``morph: error: ...`` for every
error: :class:`ParseError`, :class:`DegenerateCurveError`, :class:`LimitError`,
:class:`NibError` and :class:`OperandError` are bad input (exit status 2);
:class:`TopologyError`, :class:`ToleranceNotMetError` and anything else are internal
failures (exit 1).
"""


class MorphError(Exception):
    """Base class of every error this package raises on purpose."""


class ParseError(MorphError):
    """Input (font, glyph, SVG file or path string) could not be read as a shape.

    ``source`` names the input (file path, glyph, path string) the message is about;
    ``kind`` what is wrong, for a caller's advice (e.g. "stroke": it draws only
    stroke paint, centre lines).
    """

    def __init__(self, message, source=None, kind=None):
        super().__init__(message)
        self.source = source
        self.kind = kind


class DegenerateCurveError(MorphError):
    """A curve piece has no usable tangent (zero length, cusp, NaN coordinates).

    ``piece`` keeps the offending control points.
    """

    def __init__(self, message, piece=None):
        super().__init__(message)
        self.piece = piece


class ToleranceNotMetError(MorphError):
    """An approximation did not reach its tolerance within the allowed splits.

    ``piece`` keeps the input that failed and ``achieved`` the best error reached;
    ``rows``: where a batch of approximations failed, the rows that did (indices
    into the table of pairs of :func:`morph.convolve.convolution`; None: unknown).
    """

    def __init__(self, message, piece=None, achieved=None, rows=None):
        super().__init__(message)
        self.piece = piece
        self.achieved = achieved
        self.rows = rows


class TopologyError(MorphError):
    """Closed boundary loops could not be assembled (from convolution curves, trimmed
    or filled pieces).

    ``loops`` keeps the input that failed (loops or pieces being assembled, when the
    raiser has them) and ``point`` where it failed (None when unknown).
    """

    def __init__(self, message, loops=None, point=None):
        super().__init__(message)
        self.loops = loops
        self.point = point


class NibError(MorphError, ValueError):
    """A nib (the convex pen of brush and stroke) that cannot be used: not one convex
    loop, or an ellipse without positive width and height.  ``nib`` keeps it (the
    region, or the ellipse's ``(width, height, angle)``)."""

    def __init__(self, message, nib=None):
        super().__init__(message)
        self.nib = nib


class OperandError(MorphError, ValueError):
    """An operand of a sum that is no region: not a list of closed loops of (n+1, 3)
    pieces with positive weights, a negative area, a loop winding the wrong way
    (:func:`morph.operands.check_operand`).  Bad input (exit status 2)."""


class SelfCrossingError(OperandError):
    """An operand loop that crosses itself so that it bounds no region: its own
    winding number beside the crossing is neither 0 nor its orientation's sign (a
    curl undone by a counter-curl, :func:`morph.operands.winding_fault`), or its
    tangent does not turn exactly once (a figure-8, a pentagram, a part of zero
    width crossing the rest of the loop: :func:`morph.convolve.gauss_pair_of`).
    ``loop`` is its index in its operand."""

    def __init__(self, message, loop=None):
        super().__init__(message)
        self.loop = loop


class LimitError(MorphError, ValueError):
    """The request is outside what morph computes reliably or within its budgets: a
    tolerance finer than the coordinates' floating-point resolution or the relative
    floor, coarser than the shapes, or work beyond the point/memory budget
    (:mod:`morph.limits`).  ``suggestion`` is a tolerance that would work, if any."""

    def __init__(self, message, suggestion=None):
        super().__init__(message)
        self.suggestion = suggestion


class MorphWarning(UserWarning):
    """Input was read, but part of what it draws is left out on purpose (stroke paint
    of an SVG whose fills make the region).  The command line prints it as one line
    ``morph: warning: ...`` on stderr and goes on.  ``kind`` as :class:`ParseError`'s."""

    def __init__(self, message, kind=None):
        super().__init__(message)
        self.kind = kind


def one_line(exc):
    """The message of an exception on one line (its type name when it has none)."""
    return " ".join(str(exc).split()) or type(exc).__name__
