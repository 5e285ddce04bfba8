"""Reading SVG documents and path data -> regions (what is filled) and paths (centre lines).

One SVG stack: svgelements reads the document (CSS ``<style>`` rules, ``style``
attributes, inherited presentation attributes, ``<use>``, nested ``<svg>`` viewports,
``display``, transforms); path data is read by the grammar here (SVG 1.1, 8.3), so
elliptical arcs become exact rational quadratics (:func:`morph.piece.ellipse_arc`)
from the endpoint parameters (SVG 1.1, F.6.5) and every transform is applied exactly
to the homogeneous control points.

Painting as a browser does it (SVG 1.1/2, 11.3-11.4):

- an element is *filled* unless its ``fill`` is ``none`` (attribute, ``style``, CSS
  rule, or inherited from ``<svg>``/``<g>``), a colour with alpha 0, or
  ``fill-opacity`` 0; it is *stroked* when ``stroke`` is not ``none`` and
  ``stroke-width`` > 0.  ``display: none`` and ``visibility: hidden|collapse``
  elements are not drawn; ``<defs>``, ``<symbol>`` (outside ``<use>``), ``<mask>``,
  ``<marker>``, ``<clipPath>`` and ``<pattern>`` content is not drawn.
- the fill of an open subpath is the fill of the subpath closed by a straight line
  (implicit close): ``<polyline>``, a path without ``Z``; a ``<line>`` fills nothing.
- ``fill-rule`` (attribute, style or CSS, inherited) orients each element; the filled
  region of a document is the union of its elements' fills.
- the root ``<svg>``'s user units are kept (its ``viewBox`` to ``width``/``height``
  scaling is not applied); nested ``<svg>`` and ``<use>`` map into them.

SVG coordinates have y pointing down; readers negate y (the map (x, y) -> (x, -y)),
so a region read from SVG is the mirror image of the drawing's user coordinates about
the x axis and looks upright in a y-up frame.

Every bad input raises :class:`morph.errors.ParseError` naming the input and element.
"""

import gzip
import io
import math
import os
import re
import warnings
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np

from .. import piece as pc
from ..errors import MorphWarning, ParseError, one_line
from ..limits import MAX_COORDINATE  # coordinates beyond it are refused (morph.limits)
from ..region import is_zero_length, orient_region, without_zero_length
from ..trim import fill_region

__all__ = [
    "SvgElement",
    "svg_elements",
    "svg_paths",
    "svg_region",
    "validate_path_data",
]

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_NUMBER_RE = re.compile(_NUMBER)
_FLAG_RE = re.compile(r"[01]")
_SEP_RE = re.compile(r"\s*,?\s*")
_WS_RE = re.compile(r"\s*")
_ARGS = {"M": "nn", "L": "nn", "T": "nn", "H": "n", "V": "n", "C": "nnnnnn",
         "S": "nnnn", "Q": "nnnn", "A": "nnnffnn", "Z": ""}


# =========================================================================== path data

def _path_commands(d):
    """Tokenise path data: list of (command letter, tuple of numbers), checked.

    Raises ParseError with the position and a snippet of the offending text.
    """
    def fail(pos, why):
        snippet = d[max(0, pos - 10):pos + 10]
        raise ParseError("malformed SVG path data at character %d (%s): ...%s..."
                         % (pos, why, snippet), d)

    out = []
    pos = _WS_RE.match(d, 0).end()
    if pos == len(d):
        return out
    if d[pos] not in "Mm":
        fail(pos, "path data must start with M or m")
    while pos < len(d):
        cmd = d[pos]
        if cmd.upper() not in _ARGS:
            fail(pos, "expected a command letter, found %r" % cmd)
        pos = _WS_RE.match(d, pos + 1).end()
        pattern = _ARGS[cmd.upper()]
        if not pattern:
            out.append((cmd, ()))
            continue
        groups = 0
        while True:
            start = pos
            args = []
            for k, kind in enumerate(pattern):
                if k > 0 or groups > 0:
                    pos = _SEP_RE.match(d, pos).end()
                m = (_NUMBER_RE if kind == "n" else _FLAG_RE).match(d, pos)
                if m is None:
                    if k == 0 and groups > 0:
                        pos = start
                        break
                    fail(pos, "command %s needs %d numbers" % (cmd, len(pattern)))
                args.append(float(m.group()))
                pos = m.end()
            else:
                # an implicit command after a moveto is a lineto (8.3.2)
                c = cmd if groups == 0 or cmd not in "Mm" else ("L" if cmd == "M" else "l")
                out.append((c, tuple(args)))
                groups += 1
                continue
            break
        pos = _WS_RE.match(d, pos).end()
    return out


def validate_path_data(d):
    """Check an SVG path ``d`` string against the path grammar (SVG 1.1, 8.3.9).

    It must start with a moveto, every command needs whole groups of arguments
    (arcs: flags 0/1), nothing else may appear.

    Raises:
        ParseError: with the position and a snippet of the offending text.
    """
    _path_commands(d)


def _arc_pieces(p0, rx, ry, phi_deg, large, sweep, p1):
    """Exact pieces of an SVG arc command (SVG 1.1, F.6.5-F.6.6), SVG coordinates.

    An arc with equal end points is omitted (F.6.2, []); a zero radius makes it a line.
    """
    x0, y0 = p0
    x1, y1 = p1
    if x0 == x1 and y0 == y1:
        return []
    rx, ry = abs(rx), abs(ry)
    if rx == 0 or ry == 0:
        return [pc.line(p0, p1)]
    phi = math.radians(phi_deg % 360.0)
    c, s = math.cos(phi), math.sin(phi)
    dx, dy = (x0 - x1) / 2.0, (y0 - y1) / 2.0
    x1p, y1p = c * dx + s * dy, -s * dx + c * dy          # F.6.5.1
    lam = (x1p / rx) ** 2 + (y1p / ry) ** 2                # F.6.6.2: radii too small
    if lam > 1:
        k = math.sqrt(lam)
        rx, ry = rx * k, ry * k
    num = rx * rx * ry * ry - rx * rx * y1p * y1p - ry * ry * x1p * x1p
    den = rx * rx * y1p * y1p + ry * ry * x1p * x1p
    coef = math.sqrt(max(0.0, num / den)) if den > 0 else 0.0
    if large == sweep:
        coef = -coef
    cxp, cyp = coef * rx * y1p / ry, -coef * ry * x1p / rx  # F.6.5.2
    cx = c * cxp - s * cyp + (x0 + x1) / 2.0               # F.6.5.3
    cy = s * cxp + c * cyp + (y0 + y1) / 2.0
    theta = math.atan2((y1p - cyp) / ry, (x1p - cxp) / rx)  # F.6.5.5-6
    theta_end = math.atan2((-y1p - cyp) / ry, (-x1p - cxp) / rx)
    delta = theta_end - theta
    if sweep and delta < 0:
        delta += 2 * math.pi
    elif not sweep and delta > 0:
        delta -= 2 * math.pi
    if not all(map(math.isfinite, (cx, cy, rx, ry, theta, delta))):
        raise ValueError("non-finite arc")
    arcs = pc.ellipse_arc((cx, cy), rx, ry, phi, theta, delta)
    # the exact end points (the conic is exact; this removes rounding only)
    arcs[0] = pc.with_endpoints(arcs[0], p0, pc.end(arcs[0]))
    arcs[-1] = pc.with_endpoints(arcs[-1], pc.start(arcs[-1]), p1)
    return arcs


def _smooth_control(up, cur, last_ctrl, last_up):
    """First control point of S / T (SVG 1.1, 8.3.6, 8.3.7): the previous command's
    last control point reflected about ``cur`` when that command was of the same
    family (C/S for S, Q/T for T), else ``cur`` itself."""
    family = "CS" if up == "S" else "QT"
    if last_ctrl is not None and last_up in family:
        return 2 * cur - last_ctrl
    return cur.copy()


def _draw_segment(up, a, cur, base, smooth):
    """One drawing command from ``cur``: (pieces, end point, last control point).

    ``up``: the command letter in upper case (L H V C S Q T A); ``a``: its numbers;
    ``base``: the origin of its coordinates (``cur`` for a relative command, 0
    otherwise); ``smooth``: the first control point of S / T (:func:`_smooth_control`).
    The last control point is None for lines and arcs.  Raises ValueError for an arc
    with non-finite parameters.
    """
    if up in "LHV":
        if up == "L":
            nxt = base + a[:2]
        elif up == "H":
            nxt = np.array([base[0] + a[0], cur[1]])
        else:
            nxt = np.array([cur[0], base[1] + a[0]])
        return [pc.line(cur, nxt)], nxt, None
    if up == "C":
        c1, c2, nxt = base + a[0:2], base + a[2:4], base + a[4:6]
        return [pc.cubic(cur, c1, c2, nxt)], nxt, c2
    if up == "S":
        c2, nxt = base + a[0:2], base + a[2:4]
        return [pc.cubic(cur, smooth, c2, nxt)], nxt, c2
    if up == "Q":
        c1, nxt = base + a[0:2], base + a[2:4]
        return [pc.quadratic(cur, c1, nxt)], nxt, c1
    if up == "T":
        nxt = base + a[0:2]
        return [pc.quadratic(cur, smooth, nxt)], nxt, smooth
    nxt = base + a[5:7]  # A
    arcs = _arc_pieces(tuple(cur), a[0], a[1], a[2], a[3] != 0, a[4] != 0, tuple(nxt))
    return arcs, nxt, None


def _end_subpath(out, pieces, cur, start, closed):
    """Append (pieces, closed, start) to ``out``: a closing line added when a closed
    subpath ends away from its start, zero-length pieces dropped, nothing appended
    when nothing is left."""
    if closed and pieces and not np.array_equal(cur, start):
        pieces = pieces + [pc.line(cur, start)]
    kept = without_zero_length(pieces)
    if kept:
        out.append((kept, closed, start.copy()))


def _path_data_subpaths(d):
    """Path data -> list of (pieces, closed, start point), SVG coordinates.

    ``closed`` is True for a subpath ended by Z/z (a closing line is added when its
    last point differs from its first).  Zero-length segments are dropped; subpaths
    with nothing left are dropped.

    Raises:
        ParseError: malformed path data; a non-finite coordinate.
    """
    out, pieces = [], []
    cur = start = np.zeros(2)
    last_ctrl, last_up = None, ""
    for cmd, a in _path_commands(d):
        up = cmd.upper()
        base = cur if cmd != up else np.zeros(2)
        if up in "MZ":
            _end_subpath(out, pieces, cur, start, closed=up == "Z")
            pieces, last_ctrl = [], None
            cur = start = base + a[:2] if up == "M" else start
        else:
            smooth = _smooth_control(up, cur, last_ctrl, last_up)
            try:
                new, cur, last_ctrl = _draw_segment(up, a, cur, base, smooth)
            except (ValueError, OverflowError, ZeroDivisionError):
                _nonfinite(d)
            pieces.extend(new)
        if not np.all(np.isfinite(cur)):
            _nonfinite(d)
        last_up = up
    _end_subpath(out, pieces, cur, start, closed=False)
    return out


def _nonfinite(source):
    raise ParseError("SVG path has a non-finite coordinate (NaN or inf): %s"
                     % _shorten(str(source)), source)


# =========================================================================== documents

@dataclass
class SvgElement:
    """One drawn element of an SVG document, in y-up coordinates.

    ``subpaths`` is a list of (pieces, closed) with the element's transform applied
    and y flipped; ``closed`` is True for subpaths ended by ``Z`` (and for the closed
    shapes rect, circle, ellipse, polygon).  ``filled`` / ``stroked`` say how the
    element is painted, ``fill_rule`` is "nonzero" or "evenodd".
    """

    label: str
    subpaths: list = field(repr=False)
    filled: bool
    stroked: bool
    fill_rule: str = "nonzero"


def _length(value):
    """Float of a length attribute value (units ignored), None if absent/unreadable."""
    if value is None:
        return None
    m = _NUMBER_RE.match(str(value).strip())
    return float(m.group()) if m else None


def _check_xml(root, label):
    """Checks on the raw XML before svgelements reads it: path data grammar, negative
    sizes, clipping/masking (not supported).  Returns the tree with ``<symbol>``,
    ``<mask>`` and ``<marker>`` moved into a ``<defs>`` (they are only drawn through
    a reference)."""
    parents = {c: p for p in root.iter() for c in p}
    moved = []
    for el in root.iter():
        tag = el.tag.split("}")[-1]
        name = _element_name(el, tag)
        if tag == "path" and el.get("d") is None:
            el.set("d", "")  # no path data: not rendered (SVG 1.1, 8.3.2), as d=""
        if tag == "path":
            try:
                _path_commands(el.get("d") or "")
            except ParseError as exc:
                raise ParseError("%s: %s: %s" % (label, name, exc), exc.source) from exc
        sizes = {"circle": ("r",), "ellipse": ("rx", "ry"),
                 "rect": ("width", "height", "rx", "ry")}.get(tag, ())
        for attr in sizes:
            v = _length(el.get(attr))
            if v is not None and v < 0:
                raise ParseError("%s: %s has a negative %s (%s): an error in SVG"
                                 % (label, name, attr, el.get(attr)), label)
        if el.get("viewBox") is not None:
            _check_viewbox(el.get("viewBox"), "%s: %s" % (label, name), label)
        if el.get("transform") is not None:
            _check_transform(el.get("transform"), "%s: %s" % (label, name))
        style = el.get("style") or ""
        if el.get("clip-path") or el.get("mask") or re.search(r"(clip-path|mask)\s*:", style):
            if not re.search(r"(clip-path|mask)\s*:\s*none", style) and \
                    (el.get("clip-path") or el.get("mask") or "none") != "none":
                raise ParseError("%s: %s is clipped or masked (clip-path/mask): not supported"
                                 % (label, name), label)
        if tag in ("symbol", "mask", "marker") and el in parents:
            moved.append(el)
    if moved:
        defs = ET.SubElement(root, "{http://www.w3.org/2000/svg}defs")
        for el in moved:
            parents[el].remove(el)
            defs.append(el)
    return root


_TRANSFORM_RE = re.compile(r"\s*(?:(?:matrix|translate|scale|rotate|skewX|skewY)\s*\(\s*%s"
                           r"(?:\s*,?\s*%s)*\s*\)\s*,?\s*)*$" % (_NUMBER, _NUMBER))


def _check_viewbox(value, where, source):
    """A viewBox of zero width or height disables rendering (SVG 1.1, 7.7) and a
    negative one is an error: both refused (nothing to sum), not divided by."""
    nums = [float(v) for v in re.findall(_NUMBER, value)]
    if len(nums) == 4 and (nums[2] <= 0 or nums[3] <= 0 or not np.all(np.isfinite(nums))):
        raise ParseError("%s has a viewBox %r of %s width or height: nothing is drawn"
                         % (where, _shorten(value), "zero" if min(nums[2:]) == 0
                            else "negative or non-finite"), source)


def _check_transform(value, where):
    """A transform list must follow the grammar (SVG 1.1, 7.6) and be finite."""
    import svgelements as se

    if not _TRANSFORM_RE.match(value):
        raise ParseError("%s has a malformed transform %r" % (where, _shorten(value)), value)
    m = se.Matrix(value)
    if not np.all(np.isfinite([m.a, m.b, m.c, m.d, m.e, m.f])):
        raise ParseError("%s has a non-finite transform %r" % (where, _shorten(value)), value)


def _element_name(el, tag=None):
    tag = tag or el.tag.split("}")[-1]
    ident = el.get("id")
    return "<%s id=%r>" % (tag, ident) if ident else "<%s>" % tag


def _painted(values, key):
    """Is ``fill`` / ``stroke`` of these svgelements values a visible paint?"""
    import svgelements as se

    paint = str(values.get(key, "black" if key == "fill" else "none")).strip()
    if paint.lower() in ("none", ""):
        return False
    opacity = _length(values.get(key + "-opacity"))
    if opacity is not None and opacity <= 0:
        return False
    if paint.startswith("url("):
        return True
    try:
        color = se.Color(paint)
    except Exception:
        return True
    if color.value is None:
        return False
    return color.alpha != 0


def _own_length(raw, name, parsed):
    """An element's own attribute ``name`` in user units: plain numbers (or px) as
    written in ``raw`` (the attributes); other units and percentages as svgelements
    resolved them (``parsed``).  Absent: 0, SVG's initial value (svgelements lets
    x/y leak from <svg>)."""
    if name not in raw:
        return 0.0
    text = str(raw[name]).strip()
    m = re.fullmatch(r"(%s)(px)?" % _NUMBER, text)
    return float(m.group(1)) if m else (float(parsed) if parsed is not None else 0.0)


def _rect_subpaths(x, y, w, h, rx, ry):
    """A rectangle, its corners rounded by (rx, ry) (SVG 2 rect path: clockwise on
    screen from (x + rx, y), radii clamped to half the sides); [] for an empty one."""
    if w <= 0 or h <= 0:
        return []
    rx, ry = (rx if rx is not None else ry), (ry if ry is not None else rx)
    rx, ry = min(abs(rx or 0.0), w / 2), min(abs(ry or 0.0), h / 2)
    if rx <= 0 or ry <= 0:
        pts = [(x, y), (x + w, y), (x + w, y + h), (x, y + h)]
        return [([pc.line(pts[i], pts[(i + 1) % 4]) for i in range(4)], True)]
    corners = [((x + w - rx, y + ry), -math.pi / 2), ((x + w - rx, y + h - ry), 0.0),
               ((x + rx, y + h - ry), math.pi / 2), ((x + rx, y + ry), math.pi)]
    pieces = []
    for c, a0 in corners:
        arc = pc.ellipse_arc(c, rx, ry, 0.0, a0, math.pi / 2)
        if pieces:
            pieces.append(pc.line(pc.end(pieces[-1]), pc.start(arc[0])))
        pieces.extend(arc)
    pieces.append(pc.line(pc.end(pieces[-1]), pc.start(pieces[0])))
    return [(without_zero_length(pieces), True)]


def _polyline_subpaths(pts, closed):
    """Lines through points (a polygon closed back to its first point); [] if none."""
    pts = list(pts)
    if closed and len(pts) > 1 and pts[0] != pts[-1]:
        pts.append(pts[0])
    pieces = [pc.line(pts[i], pts[i + 1]) for i in range(len(pts) - 1)]
    pieces = without_zero_length(pieces)
    return [(pieces, closed)] if pieces else []


def _local_subpaths(el, label):
    """An svgelements shape -> list of (pieces, closed) in its own user coordinates."""
    import svgelements as se

    raw = el.values.get("attributes") or {}

    def num(name, parsed):
        return _own_length(raw, name, parsed)

    if isinstance(el, se.Path):
        return [(p, c) for p, c, _ in _path_data_subpaths(el.values.get("d") or "")]
    if isinstance(el, se.Rect):
        x, y, w, h = (num(k, getattr(el, k)) for k in ("x", "y", "width", "height"))
        return _rect_subpaths(x, y, w, h, _length(raw.get("rx")), _length(raw.get("ry")))
    if isinstance(el, (se.Circle, se.Ellipse)):
        rx, ry = ((num("r", el.rx),) * 2 if isinstance(el, se.Circle)
                  else (num("rx", el.rx), num("ry", el.ry)))
        if not (rx > 0 and ry > 0):
            return []
        centre = (num("cx", el.cx), num("cy", el.cy))
        return [(pc.ellipse_arc(centre, rx, ry, 0.0, 0.0, 2 * math.pi), True)]
    if isinstance(el, se.SimpleLine):
        line = pc.line((num("x1", el.x1), num("y1", el.y1)), (num("x2", el.x2), num("y2", el.y2)))
        return [] if is_zero_length(line) else [([line], False)]
    if isinstance(el, (se.Polyline, se.Polygon)):
        return _polyline_subpaths([(float(p.x), float(p.y)) for p in el.points],
                                  isinstance(el, se.Polygon))
    return []


def _matrix(m):
    """svgelements Matrix -> 2x3 affine [[a, c, e], [b, d, f]] followed by the y flip."""
    return np.array([[m.a, m.c, m.e], [-m.b, -m.d, -m.f]], float)


def _read_document(text, is_file, label):
    """svgelements SVG of a file or document string, after the raw-XML checks."""
    import svgelements as se

    where = text if is_file else "document"
    try:
        if is_file:
            if not os.path.isfile(text):
                why = ("it is a folder" if os.path.isdir(text) else
                       "it is not a regular file" if os.path.exists(text) else "no such file")
                raise ParseError("cannot read SVG file %s: %s" % (text, why), text)
            with open(text, "rb") as fh:
                data = fh.read()
            if data[:2] == b"\x1f\x8b":  # .svgz: gzip-compressed SVG
                data = gzip.decompress(data)
        else:
            data = text.encode("utf-8")
        root = ET.fromstring(data)
    except ParseError:
        raise
    except (ET.ParseError, OSError, UnicodeDecodeError, ValueError, EOFError) as exc:
        raise ParseError("cannot read SVG %s: %s" % (where, one_line(exc)), text) from exc
    if root.tag.split("}")[-1] != "svg":
        raise ParseError("SVG %s: the root element is <%s>, not <svg>"
                         % (where, root.tag.split("}")[-1]), text)
    root = _check_xml(root, label)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return se.SVG.parse(io.BytesIO(ET.tostring(root)), reify=False)
    except ParseError:
        raise
    except RecursionError:
        raise ParseError("cannot parse SVG %s: its elements or <use> references nest too "
                         "deeply (or refer to themselves)" % where, text) from None
    except Exception as exc:
        raise ParseError("cannot parse SVG %s: %s" % (where, one_line(exc)), text) from exc


def _source_kind(source):
    """(text, kind) of an SVG source: kind "file", "document" or "path data".

    Raises:
        ParseError: neither a path nor a string.
    """
    text = os.fspath(source) if isinstance(source, os.PathLike) else source
    if not isinstance(text, str):
        raise ParseError("an SVG source is a path or a string, got %r" % (source,), source)
    if text.lstrip().startswith("<"):
        return text, "document"
    if isinstance(source, os.PathLike) or text.lower().endswith((".svg", ".svgz")) or os.path.exists(text):
        return text, "file"
    return text, "path data"


def _path_data_element(text):
    """Path data as one filled element (nonzero rule), y flipped up."""
    flip = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    sub = [([pc.transform(p, flip) for p in pieces], closed)
           for pieces, closed, _ in _path_data_subpaths(text)]
    return SvgElement("path data %r" % _shorten(text), sub, True, False, "nonzero")


def _drawn_element(el, name, label, unview, source):
    """An svgelements shape -> :class:`SvgElement` (y up, its transform applied), or
    None when it draws nothing.  ``unview``: the inverse of the root viewBox
    transform (the root's user units are kept).

    Raises:
        ParseError: as :func:`_local_subpaths`; a non-finite transform.
    """
    import svgelements as se

    try:
        local = _local_subpaths(el, name)
    except ParseError as exc:
        raise ParseError("%s: %s: %s" % (label, name, exc), source) from exc
    if not local:
        return None
    m = _matrix(el.transform * unview)
    if not np.all(np.isfinite(m)):
        raise ParseError("%s: %s has a non-finite transform" % (label, name), source)
    sub = [([pc.transform(p, m) for p in pieces], closed) for pieces, closed in local]
    values = el.values
    rule = str(values.get("fill-rule", "nonzero")).strip()
    stroke_width = _length(values.get("stroke-width"))
    stroked = _painted(values, "stroke") and (stroke_width is None or stroke_width > 0)
    filled = _painted(values, "fill") and not isinstance(el, se.SimpleLine)
    return SvgElement("%s: %s" % (label, name), sub, filled, stroked,
                      rule if rule in ("nonzero", "evenodd") else "nonzero")


def svg_elements(source):
    """Every drawn element of an SVG document (or of one path data string).

    ``source`` is a file path (str or Path) of an SVG document, a string starting
    with ``<`` (an SVG document) or path data (``"M 0 0 L 10 0 ..."``, read as one
    filled path with the nonzero rule).  Returns a list of :class:`SvgElement`
    (y up), hidden elements left out (see the module docstring for the rules).

    Raises:
        ParseError: unreadable file or XML; malformed path data; a negative radius,
            width or height; clip-path/mask; NaN, inf or coordinates beyond
            ``MAX_COORDINATE`` after the transforms.
    """
    import svgelements as se

    text, kind = _source_kind(source)
    if kind == "path data":
        elements = [_path_data_element(text)]
        _check_finite(elements, text)
        return elements
    label = text if kind == "file" else "SVG document"
    doc = _read_document(text, kind == "file", label)
    vp = getattr(doc, "viewbox_transform", None) if isinstance(doc, se.SVG) else None
    unview = ~se.Matrix(vp) if vp else se.Matrix()
    elements = []
    for k, el in enumerate(doc.elements() if isinstance(doc, se.Group) else []):
        if not isinstance(el, se.Shape):
            continue
        if str(el.values.get("visibility", "visible")).strip() in ("hidden", "collapse"):
            continue
        tag = el.values.get("tag", type(el).__name__.lower())
        name = "<%s id=%r>" % (tag, el.id) if el.id else "<%s> (element %d)" % (tag, k)
        element = _drawn_element(el, name, label, unview, text)
        if element is not None:
            elements.append(element)
    _check_finite(elements, text)
    return elements


def _check_finite(elements, source):
    for e in elements:
        for pieces, _ in e.subpaths:
            for p in pieces:
                with np.errstate(all="ignore"):
                    big = not np.all(np.isfinite(p)) or np.max(np.abs(p)) > MAX_COORDINATE
                if big:
                    what = ("a non-finite coordinate (NaN or inf)" if not np.all(np.isfinite(p))
                            else "a coordinate beyond %g (the largest morph computes with)"
                            % MAX_COORDINATE)
                    raise ParseError("%s has %s" % (e.label, what), source)


def _close(pieces, tol):
    """A subpath closed as SVG fills it: a straight line back to its start, or the
    last end snapped onto the start when the gap is within ``tol``."""
    a, b = pc.start(pieces[0]), pc.end(pieces[-1])
    gap = float(np.hypot(*(a - b)))
    if gap == 0:
        return list(pieces)
    if gap <= tol:
        return list(pieces[:-1]) + [pc.with_endpoints(pieces[-1], pc.start(pieces[-1]), a)]
    return list(pieces) + [pc.line(b, a)]


def _element_size(subpaths):
    pts = np.concatenate([pc.cartesian(p) for pieces, _ in subpaths for p in pieces])
    return float(np.max(np.abs(pts))) if len(pts) else 1.0


def svg_region(source, fill_rule=None, close_tol=None):
    """Filled region (y up) of an SVG file, an SVG document string or path data.

    What a browser fills (module docstring): each filled element's subpaths closed
    (an open one by a straight line to its start; an end within ``close_tol`` of the
    start, default 1e-9 of the element's size, is snapped onto it), oriented with its
    own ``fill-rule`` unless ``fill_rule`` overrides it; the region is the union of
    the elements' fills (nonzero of the oriented loops, so overlapping elements are
    merged).  Stroke paint is not part of the region (:func:`svg_paths` gives the
    centre lines).  Lines, quadratics and cubics become polynomial pieces; elliptical
    arcs exact rational quadratics; zero-length segments are removed; tiny loops of
    positive area are kept.

    Raises:
        ParseError: as :func:`svg_elements`; a document that fills nothing (no shape,
            only stroke-only elements -- the message names one --, or loops whose
            windings cancel).
    """
    if fill_rule not in (None, "nonzero", "evenodd"):
        raise ValueError("fill_rule must be None, 'nonzero' or 'evenodd', got %r" % (fill_rule,))
    elements = [e for e in svg_elements(source) if e.subpaths]
    text, kind = _source_kind(source)
    where = {"document": "SVG document", "file": "SVG file %s" % text,
             "path data": "SVG path data %r" % _shorten(text)}[kind]
    filled = [e for e in elements if e.filled]
    if not filled:
        stroke_only = [e for e in elements if e.stroked]
        if stroke_only:
            raise ParseError("%s is stroke-only (fill none): a centre line encloses no "
                             "region" % stroke_only[0].label, text, kind="stroke")
        raise ParseError("%s has no path or shape that is drawn" % where, text)
    parts = []
    for e in filled:
        size = _element_size(e.subpaths)
        tol = close_tol if close_tol is not None else 1e-9 * (size if size > 0 else 1.0)
        loops = [_close(pieces, tol) for pieces, _ in e.subpaths]
        oriented = orient_region(loops, fill_rule or e.fill_rule, on_crossing=fill_region)
        if oriented:
            parts.append(oriented)
    if len(parts) > 1:
        loops = orient_region([loop for part in parts for loop in part], "nonzero",
                              on_crossing=fill_region)
    else:
        loops = parts[0] if parts else []
    stroked = [e for e in elements if e.stroked]
    if not loops:
        raise ParseError("%s fills nothing: no closed path with positive area, or loops "
                         "whose windings cancel%s" % (where, _strokes_note(stroked)), text,
                         kind="stroke" if stroked else None)
    if stroked:
        warnings.warn(MorphWarning(
            "%s is stroked: stroke paint is not part of the region (only fills are)"
            % _labels(stroked), kind="stroke"),
            stacklevel=2)
    return loops


def _labels(elements):
    """The first element's label, and how many more."""
    more = len(elements) - 1
    return elements[0].label + (" (and %d more element%s)" % (more, "s" if more > 1 else "")
                                if more else "")


def _strokes_note(stroked):
    """What the error of a document that fills nothing says about its strokes."""
    if not stroked:
        return ""
    return "; what it draws is stroke paint (%s)" % _labels(stroked)


def svg_paths(source, stroked=None):
    """Every drawn path's subpaths as centre lines: list of (pieces, closed), y up.

    Open subpaths stay open (``closed`` False: no implicit close, as SVG strokes
    them); subpaths ended by ``Z`` and closed shapes (rect, circle, ellipse,
    polygon) have ``closed`` True and end where they start.  ``stroked``: None for
    every drawn element, True only elements with a stroke paint, False only those
    without.  Coordinates as :func:`svg_region` (transforms applied, y flipped).

    Raises:
        ParseError: as :func:`svg_elements`; nothing drawn.
    """
    out = []
    for e in svg_elements(source):
        if not (e.filled or e.stroked):
            continue
        if stroked is not None and e.stroked != stroked:
            continue
        out.extend((list(pieces), bool(closed)) for pieces, closed in e.subpaths)
    if not out:
        raise ParseError("SVG %s draws no path" % _shorten(str(os.fspath(source))), source)
    return out


# =========================================================================== helpers

def _shorten(text, n=40):
    return text if len(text) <= n else text[:n - 3] + "..."
