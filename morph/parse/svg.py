"""Reading SVG paths and documents (svgpathtools) -> regions.

SVG coordinates have y pointing down; readers negate y (the map (x, y) -> (x, -y)),
so a region read from SVG is the mirror image of the drawing's user coordinates
about the x axis, and looks upright in a y-up frame.  Arcs become exact rational
quadratics (:func:`morph.piece.ellipse_arc`).

Every bad input raises :class:`morph.errors.ParseError` naming the input.
"""

import contextlib
import math
import os
import re
import warnings
import xml.etree.ElementTree as ET

import numpy as np

from .. import piece as pc
from ..errors import ParseError
from ..region import is_zero_length, orient_region

__all__ = [
    "svg_region",
    "validate_path_data",
]


# =========================================================================== SVG

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_NUMBER_RE = re.compile(_NUMBER)
_FLAG_RE = re.compile(r"[01]")
_SEP_RE = re.compile(r"\s*,?\s*")
_WS_RE = re.compile(r"\s*")
_ARGS = {"M": "nn", "L": "nn", "T": "nn", "H": "n", "V": "n", "C": "nnnnnn",
         "S": "nnnn", "Q": "nnnn", "A": "nnnffnn", "Z": ""}


def validate_path_data(d):
    """Check an SVG path ``d`` string against the path grammar (SVG 1.1, 8.3.9).

    svgpathtools accepts some malformed strings silently (``"L 1 x 1"`` reads as a
    line to (1, 1)), so path data is checked here first: it must start with a moveto,
    every command needs whole groups of arguments (arcs: flags 0/1), nothing else may
    appear.

    Raises:
        ParseError: with the position and a snippet of the offending text.
    """
    def fail(pos, why):
        snippet = d[max(0, pos - 10):pos + 10]
        raise ParseError("malformed SVG path data at character %d (%s): ...%s..."
                         % (pos, why, snippet), d)

    pos = _WS_RE.match(d, 0).end()
    if pos == len(d):
        return
    if d[pos] not in "Mm":
        fail(pos, "path data must start with M or m")
    while pos < len(d):
        cmd = d[pos]
        if cmd.upper() not in _ARGS:
            fail(pos, "expected a command letter, found %r" % cmd)
        pos = _WS_RE.match(d, pos + 1).end()
        pattern = _ARGS[cmd.upper()]
        if not pattern:
            continue
        groups = 0
        while True:
            start = pos
            for k, kind in enumerate(pattern):
                if k > 0 or groups > 0:
                    pos = _SEP_RE.match(d, pos).end()
                m = (_NUMBER_RE if kind == "n" else _FLAG_RE).match(d, pos)
                if m is None:
                    if k == 0 and groups > 0:
                        pos = start
                        break
                    fail(pos, "command %s needs %d numbers" % (cmd, len(pattern)))
                pos = m.end()
            else:
                groups += 1
                continue
            break
        pos = _WS_RE.match(d, pos).end()


@contextlib.contextmanager
def _omit_closed_arcs():
    """SVG 1.1 F.6.2: an arc whose end point equals its start point is omitted.

    svgpathtools asserts on such an arc in ``Arc.__init__``; while parsing, its
    parser builds a zero-length line there instead (dropped later with the other
    zero-length segments).
    """
    import svgpathtools.path as svp

    arc = svp.Arc

    class OmittedIfClosed(arc):
        def __new__(cls, start, *args, **kwargs):
            end = args[4] if len(args) > 4 else kwargs.get("end")
            if start == end:
                return svp.Line(start, end)
            return super().__new__(cls)

    svp.Arc = OmittedIfClosed
    try:
        yield
    finally:
        svp.Arc = arc


def _segment_pieces(seg):
    """svgpathtools segment -> list of pieces in the segment's own coordinates."""
    from svgpathtools import Arc, CubicBezier, Line, QuadraticBezier

    def xy(z):
        return (z.real, z.imag)

    if isinstance(seg, Line):
        return [pc.line(xy(seg.start), xy(seg.end))]
    if isinstance(seg, QuadraticBezier):
        return [pc.quadratic(*(xy(z) for z in seg.bpoints()))]
    if isinstance(seg, CubicBezier):
        return [pc.cubic(*(xy(z) for z in seg.bpoints()))]
    if isinstance(seg, Arc):
        rx, ry = abs(seg.radius.real), abs(seg.radius.imag)
        if not (rx > 0 and ry > 0) or not np.all(np.isfinite([rx, ry])):
            return [pc.line(xy(seg.start), xy(seg.end))]
        arcs = pc.ellipse_arc(xy(seg.center), rx, ry, math.radians(seg.rotation),
                              math.radians(seg.theta), math.radians(seg.delta))
        # the arc's exact end points (the conic is exact; this removes rounding only)
        arcs[0] = pc.with_endpoints(arcs[0], xy(seg.start), pc.end(arcs[0]))
        arcs[-1] = pc.with_endpoints(arcs[-1], pc.start(arcs[-1]), xy(seg.end))
        return arcs
    raise ParseError("unsupported SVG segment %r" % (seg,), str(seg))


def _path_loops(path, label, close_tol):
    """Split an svgpathtools Path into closed loops of pieces (SVG coordinates).

    A subpath ends where a segment returns to the subpath's first point (within
    ``close_tol``) or where the next segment does not start at the current point.
    An unclosed subpath raises ParseError naming ``label`` and the subpath index.
    """
    loops, current, start, current_end, open_ = [], [], None, None, False

    def open_error():
        return ParseError("%s: subpath %d is open (ends at (%g, %g), starts at (%g, %g))"
                          % (label, len(loops), current_end.real, current_end.imag,
                             start.real, start.imag), label)

    for seg in path:
        s, e = complex(seg.start), complex(seg.end)
        pieces = [] if not np.isfinite([s.real, s.imag, e.real, e.imag]).all() \
            else _segment_pieces(seg)
        if not pieces or not all(np.all(np.isfinite(p)) for p in pieces):
            raise ParseError("%s: subpath %d has a non-finite coordinate (NaN or inf)"
                             % (label, len(loops)), label)
        if open_ and abs(s - current_end) > close_tol:
            if current:
                raise open_error()
            open_ = False  # a subpath of zero length only: drop it
        if not open_:
            start, current, open_ = s, [], True
        current.extend(p for p in pieces if not is_zero_length(p))
        current_end = e
        if current and abs(e - start) <= close_tol:
            loops.append(current)
            open_ = False
    if open_ and current:
        raise open_error()
    return loops


def _fill_rule(element, parents):
    """fill-rule of an element: its attribute or style, else inherited, else nonzero."""
    while element is not None:
        style = element.get("style") or ""
        m = re.search(r"fill-rule\s*:\s*([a-z]+)", style)
        value = m.group(1) if m else element.get("fill-rule")
        if value in ("evenodd", "nonzero"):
            return value
        element = parents.get(element)
    return "nonzero"


def _flip_y(pieces):
    return [pc.transform(p, [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]) for p in pieces]


def svg_region(source, fill_rule=None, close_tol=None):
    """Region (y up) of an SVG file, an SVG document string or a path ``d`` string.

    ``source`` is a file path (str or Path) of an SVG document, a string starting
    with ``<`` (an SVG document) or path data (``"M 0 0 L 10 0 ..."``).  For documents
    every ``path``, ``rect``, ``circle``, ``ellipse``, ``polygon``, ``polyline`` and
    ``line`` element is read with ``svgpathtools.Document(...).paths()``, which applies
    the ``transform`` attributes of the element and its groups.  Each element is
    oriented with its own ``fill-rule`` (attribute or style, inherited from its
    groups; default nonzero) unless ``fill_rule`` overrides it, and the loops of all
    elements are concatenated (overlapping elements are not merged).

    Lines, quadratics and cubics become polynomial pieces; elliptical arcs exact
    rational quadratics.  Zero-length segments are removed.  The y axis is flipped
    ((x, y) -> (x, -y)) so that the region is y-up.  A subpath must end where it
    starts (within ``close_tol``, default 1e-9 of the path's size).

    Raises:
        ParseError: unreadable file or XML; malformed path data; an open subpath
            (message names the file and subpath index); NaN or inf coordinates; no
            path with positive area at all.
    """
    from svgpathtools import Document, parse_path

    if fill_rule not in (None, "nonzero", "evenodd"):
        raise ValueError("fill_rule must be None, 'nonzero' or 'evenodd', got %r" % (fill_rule,))
    items = []  # (label, svgpathtools Path, fill rule)
    text = os.fspath(source) if isinstance(source, os.PathLike) else source
    if not isinstance(text, str):
        raise ParseError("an SVG source is a path or a string, got %r" % (source,), source)
    is_file = isinstance(source, os.PathLike) or (
        not text.lstrip().startswith("<") and (text.lower().endswith(".svg") or os.path.exists(text)))
    if is_file or text.lstrip().startswith("<"):
        label = text if is_file else "SVG document"
        where = text if is_file else "document"
        try:
            with warnings.catch_warnings(), _omit_closed_arcs():
                warnings.simplefilter("ignore")
                if is_file:
                    if not os.path.isfile(text):
                        raise ParseError("cannot read SVG file %s: no such file" % text, text)
                    doc = Document(text)
                else:
                    doc = Document.from_svg_string(text)
                doc.strict_transform_parsing = True  # bad transforms raise, not skip
                root = doc.tree.getroot() if hasattr(doc.tree, "getroot") else doc.tree
                for el in root.iter():
                    if el.tag.split("}")[-1] == "path":
                        validate_path_data(el.get("d") or "")
                paths = doc.paths()
        except ParseError as exc:
            if exc.source is not None and exc.source != text and is_file:
                raise ParseError("%s: %s" % (text, exc), text) from exc
            raise
        except (ET.ParseError, OSError, UnicodeDecodeError) as exc:
            raise ParseError("cannot read SVG %s: %s" % (where, _one_line(exc)), text) from exc
        except Exception as exc:
            raise ParseError("cannot parse SVG %s: %s" % (where, _one_line(exc)), text) from exc
        parents = {c: p for p in root.iter() for c in p}
        for k, path in enumerate(paths):
            el = getattr(path, "element", None)
            rule = fill_rule or (_fill_rule(el, parents) if el is not None else "nonzero")
            items.append(("%s (element %d)" % (label, k) if len(paths) > 1 else label,
                          path, rule))
    else:
        validate_path_data(text)
        try:
            with warnings.catch_warnings(), _omit_closed_arcs():
                warnings.simplefilter("ignore")
                path = parse_path(text)
        except Exception as exc:
            raise ParseError("malformed SVG path data: %s" % _one_line(exc), text) from exc
        items.append(("path data %r" % _shorten(text), path, fill_rule or "nonzero"))

    loops = []
    for label, path, rule in items:
        if len(path) == 0:
            continue
        pts = np.array([[complex(z).real, complex(z).imag] for seg in path
                        for z in (seg.start, seg.end)])
        with np.errstate(invalid="ignore"):
            size = float(np.nanmax(np.abs(pts))) if np.isfinite(pts).any() else 1.0
        tol = close_tol if close_tol is not None else 1e-9 * (size if size > 0 else 1.0)
        raw = _path_loops(path, label, tol)
        loops.extend(orient_region([_flip_y(loop) for loop in raw], rule))
    if not items:
        raise ParseError("SVG %s has no path" % (text if is_file else "document"), text)
    if not loops:
        raise ParseError("SVG %s has no closed path with positive area"
                         % (text if is_file else items[0][0]), text)
    return loops


# =========================================================================== helpers

def _one_line(exc):
    return " ".join(str(exc).split()) or type(exc).__name__


def _shorten(text, n=40):
    return text if len(text) <= n else text[:n - 3] + "..."
