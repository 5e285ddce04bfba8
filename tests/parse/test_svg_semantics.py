"""SVG painting rules as a browser applies them, each checked on a small document
against an independent raster of the same SVG (cairosvg).

The reference is cairosvg's rendering of the document (what is painted, by its own
CSS, ``use``, viewport and fill-rule handling), thresholded to a coverage mask; morph's
region (:func:`morph.parse.svg_region`, y flipped back) is rasterised on the same
pixel grid by winding number at the pixel centres.  They must agree except on pixels
the boundary passes through (within one pixel of either mask's edge).
"""

import io

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph.errors import ParseError
from morph.parse import svg_elements, svg_paths, svg_region
from morph.polyline import polylines_cross
from morph.region import point_in_region

cairosvg = pytest.importorskip("cairosvg")
from PIL import Image  # noqa: E402 - only when cairosvg (the reference renderer) is installed

NS = 'xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"'
N = 100  # pixels per side; documents use a 0..100 user space with width=height=100


def doc(body, extra=""):
    return ('<svg %s width="%d" height="%d" viewBox="0 0 100 100" %s>%s</svg>'
            % (NS, N, N, extra, body))


def cairo_mask(svg):
    """Painted pixels (fill only: strokes are removed by the caller) of cairosvg."""
    png = cairosvg.svg2png(bytestring=svg.encode(), output_width=N, output_height=N)
    a = np.asarray(Image.open(io.BytesIO(png)).convert("RGBA"))[..., 3]
    return a > 127


def morph_mask(svg):
    """Pixel centres inside morph's region (y flipped back to SVG's y-down grid)."""
    try:
        region = svg_region(svg)
    except ParseError as exc:
        if "fills nothing" in str(exc) or "stroke-only" in str(exc) or "no path" in str(exc):
            return np.zeros((N, N), bool)
        raise
    ys, xs = np.mgrid[0:N, 0:N] + 0.5
    pts = np.c_[xs.ravel(), -ys.ravel()]
    return point_in_region(pts, region, 1e-3).reshape(N, N)


def near_edge(mask):
    m = np.pad(mask, 1, mode="edge")
    edge = np.zeros_like(mask)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            edge |= m[1 + dy:N + 1 + dy, 1 + dx:N + 1 + dx] != mask
    return edge


def assert_same_fill(svg, reference_svg=None, min_area=0):
    """morph's region of ``svg`` paints what cairosvg paints for ``reference_svg``
    (default: the same document), away from the boundary pixels."""
    ref = cairo_mask(reference_svg or svg)
    got = morph_mask(svg)
    assert ref.sum() >= min_area, "reference paints too little to test anything"
    bad = (ref != got) & ~near_edge(ref) & ~near_edge(got)
    assert not bad.any(), "morph and cairosvg differ on %d pixels" % bad.sum()
    return got


RING = "M50 10 A40 40 0 1 1 49.99 10 Z M50 30 A20 20 0 1 1 49.99 30 Z"


@pytest.mark.parametrize("body", [
    '<path d="M10 10 H90 V60 H10 Z"/>',                                       # default fill
    '<path d="%s"/>' % RING,                                                  # nonzero: disk
    '<path fill-rule="evenodd" d="%s"/>' % RING,                              # ring
    '<path style="fill-rule: evenodd" d="%s"/>' % RING,                       # style
    '<g fill-rule="evenodd"><path d="%s"/></g>' % RING,                       # inherited
    '<style>.r { fill-rule: evenodd }</style><path class="r" d="%s"/>' % RING,  # CSS
])
def test_fill_and_fill_rule(body):
    assert_same_fill(doc(body), min_area=1000)


@pytest.mark.parametrize("body", [
    '<path fill="none" stroke="black" d="M10 10 H90 V60 H10 Z"/>',
    '<g fill="none" stroke="black"><path d="M10 10 H90 V60 H10 Z"/></g>',
    '<path style="fill:none;stroke:red" d="M10 10 H90 V60 H10 Z"/>',
    '<style>.o { fill: none; stroke: blue }</style><path class="o" d="M10 10 H90 V60 H10 Z"/>',
    '<path fill="transparent" stroke="black" d="M10 10 H90 V60 H10 Z"/>',
])
def test_no_fill_is_no_region(body):
    """Stroke-only elements fill nothing; a region command names the element."""
    svg = doc(body)
    nostroke = svg.replace('stroke="black"', "").replace("stroke:red", "").replace(
        "stroke: blue", "")
    assert cairo_mask(nostroke).sum() == 0
    with pytest.raises(ParseError, match="<path.*stroke-only") as info:
        svg_region(svg)
    # the library names the fault; the advice of a command is the command line's
    assert info.value.kind == "stroke" and "morph stroke" not in str(info.value)
    (pieces, closed), = svg_paths(svg)
    assert closed and abs(abs(mo.loop_area(pieces)) - 80 * 50) < 1e-9


def test_no_fill_inherited_from_svg_root():
    svg = doc('<path d="M10 10 H90 V60 H10 Z"/><rect x="20" y="70" width="10" height="10" '
              'fill="black"/>', extra='fill="none" stroke="black"')
    got = assert_same_fill(svg, svg.replace('stroke="black"', ""), min_area=50)
    assert got.sum() < 200  # only the rect


@pytest.mark.parametrize("hidden", ['display="none"', 'visibility="hidden"',
                                    'style="display:none"'])
def test_display_none_and_hidden(hidden):
    svg = doc('<rect x="10" y="10" width="30" height="30"/>'
              '<g %s><rect x="50" y="50" width="40" height="40"/></g>' % hidden)
    got = assert_same_fill(svg, min_area=800)
    assert abs(got.sum() - 900) < 150


def test_visible_child_of_hidden_group_is_drawn():
    svg = doc('<g visibility="hidden"><rect x="10" y="10" width="30" height="30"/>'
              '<rect visibility="visible" x="50" y="50" width="40" height="40"/></g>')
    got = assert_same_fill(svg, min_area=1500)
    assert abs(got.sum() - 1600) < 200


@pytest.mark.parametrize("body", [
    '<path d="M10 10 L90 10 L90 90"/>',                   # no Z: closed by a line
    '<polyline points="10 10 90 10 90 90 50 95"/>',
    '<path d="M10 10 L90 10 L90 90 L10.03 10.02"/>',      # ends 0.03 short of its start
    '<path d="M10 10 H40 V40 M60 60 H90 V90 Z"/>',        # open then closed subpath
])
def test_implicit_close(body):
    assert_same_fill(doc(body), min_area=800)


def test_polyline_stays_open_as_centre_line():
    svg = doc('<polyline fill="none" stroke="black" points="10 10 90 10 90 90"/>')
    (pieces, closed), = svg_paths(svg)
    assert not closed and len(pieces) == 2
    assert np.allclose(pc.start(pieces[0]), (10, -10)) and np.allclose(pc.end(pieces[-1]),
                                                                       (90, -90))


def test_use_and_transforms():
    body = ('<defs><path id="tri" d="M0 0 L20 0 L0 20 Z"/></defs>'
            '<use href="#tri" x="10" y="10"/>'
            '<use xlink:href="#tri" transform="translate(60 60) rotate(30) scale(1.5 1)"/>'
            '<g transform="skewX(20)"><circle cx="40" cy="70" r="12"/></g>')
    got = assert_same_fill(doc(body), min_area=600)
    assert got.sum() > 600


def test_nested_svg_viewport():
    body = ('<svg x="20" y="20" width="60" height="30" viewBox="0 0 10 10">'
            '<rect width="10" height="10"/><circle cx="5" cy="5" r="3" fill="none"/></svg>')
    # preserveAspectRatio xMidYMid meet: a 30x30 square centred in the 60x30 viewport
    got = assert_same_fill(doc(body), min_area=800)
    assert abs(got.sum() - 900) < 150


def test_root_viewbox_keeps_user_units():
    svg = ('<svg %s width="400" height="400" viewBox="0 0 100 100">'
           '<rect x="10" y="10" width="20" height="30"/></svg>' % NS)
    assert abs(mo.region_area(svg_region(svg)) - 600) < 1e-9


def test_line_is_a_centre_line_not_a_region():
    svg = doc('<line x1="10" y1="10" x2="90" y2="50" stroke="black"/>')
    with pytest.raises(ParseError, match="<line.*stroke-only"):
        svg_region(svg)
    (pieces, closed), = svg_paths(svg)
    assert not closed and np.allclose(pc.cartesian(pieces[0]), [[10, -10], [90, -50]])
    both = doc('<line x1="10" y1="10" x2="90" y2="50" stroke="black"/>'
               '<rect x="10" y="60" width="20" height="20"/>')
    assert abs(mo.region_area(svg_region(both)) - 400) < 1e-9  # the line fills nothing


@pytest.mark.parametrize("body,what", [
    ('<circle cx="50" cy="50" r="-5"/>', "negative r"),
    ('<rect width="-10" height="5"/>', "negative width"),
    ('<ellipse cx="5" cy="5" rx="3" ry="-1"/>', "negative ry"),
])
def test_negative_sizes_are_errors(body, what):
    with pytest.raises(ParseError, match=what):
        svg_region(doc(body))


@pytest.mark.parametrize("d,rule", [
    # lobes of opposite directions meeting at a joint: both filled under nonzero
    ("M50 50 C 100 0 100 100 50 50 C 0 0 0 100 50 50 Z", "nonzero"),     # figure-8
    ("M5 50 C 20 80 35 80 50 50 S 80 20 95 50 Z", "nonzero"),             # S of cubics
    ("M5 50 Q 27 95 50 50 T 95 50 Z", "nonzero"),                          # S of quadratics
    ("M5 50 L 27 90 L 50 50 L 72 10 L 95 50 Z", "nonzero"),                # closing line
    ("M5 50 L 27 90 L 50 50 L 72 10 L 95 50 Z", "evenodd"),                # through a vertex
    # overlapping squares sharing collinear edges, in one path and in two
    ("M5 20 L 55 20 L 55 80 L 5 80 Z M30 20 L 95 20 L 95 80 L 30 80 Z", "nonzero"),
    ("M5 20 L 55 20 L 55 80 L 5 80 Z M30 20 L 95 20 L 95 80 L 30 80 Z", "evenodd"),
    ("M5 20 L 55 20 L 55 80 L 5 80 Z M55 20 L 95 20 L 95 80 L 55 80 Z", "nonzero"),  # abut
    # a zero-width spike (L 90 20 then back): no area, so nothing of it is filled
    ("M10 20 L 90 20 L 50 20 L 90 80 L 10 80 Z", "nonzero"),
])
def test_loops_meeting_at_joints_or_along_edges_fill_as_rendered(d, rule):
    # a touch that is no proper crossing of two polyline edges (a joint, a vertex, a
    # collinear overlap) must reach the general fill, as crossings do
    body = '<path fill-rule="%s" d="%s"/>' % (rule, d)
    got = assert_same_fill(doc(body), min_area=1000)
    region = svg_region(doc(body))
    ref = cairo_mask(doc(body))
    assert abs(got.sum() - ref.sum()) < 0.05 * ref.sum()
    # every loop of the region is simple and the outer ones are counter-clockwise
    for loop in region:
        assert not polylines_cross(loop, 1e-6)
    if "L 90 20 L 50 20" in d:  # the spike's tip is no boundary point
        assert not point_in_region(np.array([[89.0, -20.0]]), region, 0.5)[0]


def test_sum_of_lobes_meeting_at_a_joint_keeps_both():
    # the S of two opposite lobes summed with a disk: before the touch test the loop
    # was taken as one simple loop (its signed area, the lobes' difference) and the
    # sum lost the lower lobe.  Reference: the exact region's polygon buffered by r
    from morph.minkowski import minkowski_sum
    from tests.oracles.reference import hausdorff, region_to_shapely

    region = svg_region(doc('<path d="M5 50 C 20 80 35 80 50 50 S 80 20 95 50 Z"/>'))
    r, tol = 4.0, 1e-3
    got = minkowski_sum(region, [pc.circle((0.0, 0.0), r)], tol)
    ref = region_to_shapely(region, tol / 100).buffer(r, quad_segs=256)
    assert hausdorff(region_to_shapely(got, tol / 100), ref) < 2 * tol
    assert abs(mo.region_area(got) - ref.area) < 1e-3 * ref.area


@pytest.mark.parametrize("box,what", [("0 0 0 0", "zero"), ("0 0 100 0", "zero"),
                                      ("0 0 100 -5", "negative"), ("0 0 1e400 10", "negative or non-finite")])
def test_degenerate_viewbox_is_refused(box, what):
    # SVG 1.1 7.7: zero width or height disables rendering, negative is an error; the
    # viewport transform would divide by it (a ZeroDivisionError from svgelements)
    svg = ('<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50" viewBox="%s">'
           '<rect x="10" y="10" width="50" height="30"/></svg>' % box)
    with pytest.raises(ParseError, match="viewBox .* of %s" % what):
        svg_region(svg)
    ok = svg.replace('viewBox="%s"' % box, 'viewBox="0 0 200 100"')
    assert abs(mo.region_area(svg_region(ok)) - 1500) < 1e-9  # user units are kept


def test_symbol_and_mask_content_not_drawn_directly():
    body = ('<symbol id="s"><rect width="50" height="50"/></symbol>'
            '<mask id="m"><rect width="100" height="100" fill="white"/></mask>'
            '<rect x="60" y="60" width="30" height="30"/>')
    got = assert_same_fill(doc(body), min_area=800)
    assert abs(got.sum() - 900) < 150


def test_overlapping_elements_are_united():
    body = '<rect x="10" y="10" width="50" height="50"/><rect x="30" y="30" width="50" height="50"/>'
    region = svg_region(doc(body))
    assert len(region) == 1 and abs(mo.region_area(region) - (2 * 2500 - 900)) < 1e-6
    assert_same_fill(doc(body), min_area=3000)


def test_windings_that_cancel_are_empty():
    """The same square traced both ways paints nothing; morph refuses it as empty
    (not a zero-width frame)."""
    svg = doc('<path d="M10 10 H90 V90 H10 Z M10 10 V90 H90 V10 Z"/>')
    assert cairo_mask(svg).sum() == 0
    with pytest.raises(ParseError, match="windings cancel"):
        svg_region(svg)


# a blob of four cubics and a round hole of four cubics inside it, as path data traced
# from any segment, either way, with one segment split in two: the same curves in
# different parametrisations
BLOB = [((20, 50), (20, 20), (45, 12), (60, 15)), ((60, 15), (85, 20), (90, 40), (85, 60)),
        ((85, 60), (80, 85), (50, 92), (35, 80)), ((35, 80), (20, 70), (20, 60), (20, 50))]
HOLE = [((40, 50), (40, 39), (49, 30), (55, 30)), ((55, 30), (66, 30), (70, 44), (70, 50)),
        ((70, 50), (70, 61), (61, 70), (55, 70)), ((55, 70), (44, 70), (40, 61), (40, 50))]


def _traced(segments, start, backwards, split):
    segs = segments[start:] + segments[:start]
    if backwards:
        segs = [tuple(reversed(s)) for s in reversed(segs)]
    p0, p1, p2, p3 = (np.asarray(p, float) for p in segs[split])
    a, b, c = (p0 + p1) / 2, (p1 + p2) / 2, (p2 + p3) / 2
    d, e = (a + b) / 2, (b + c) / 2
    m = (d + e) / 2
    segs = segs[:split] + [(p0, a, d, m), (m, e, c, p3)] + segs[split + 1:]
    text = "M%g %g " % tuple(segs[0][0])
    return text + " ".join("C%g %g %g %g %g %g" % (*s[1], *s[2], *s[3]) for s in segs) + " Z"


@pytest.mark.parametrize("seed", range(6))
def test_coincident_paths_add_their_windings(seed):
    """Copies of one curve, traced from any point either way, add their windings as
    any renderer adds them: a blob drawn k times one way and m times the other, with
    a hole drawn some times either way, painted as cairosvg paints it under both fill
    rules (a doubled blob with one opposite hole keeps the hole filled under nonzero;
    three copies, one reversed, still fill)."""
    rng = np.random.default_rng(seed)
    for rule in ("nonzero", "evenodd"):
        paths = []
        for shape, counts in ((BLOB, rng.integers(0, 4, 2)), (HOLE, rng.integers(0, 3, 2))):
            for backwards, count in enumerate(counts):
                paths += [_traced(shape, int(rng.integers(4)), bool(backwards),
                                  int(rng.integers(4))) for _ in range(count)]
        rng.shuffle(paths)
        assert_same_fill(doc('<path fill-rule="%s" d="%s"/>' % (rule, " ".join(paths))))


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
@pytest.mark.parametrize("ways", ["++-", "+-+", "++--", "+++-", "++-+--"])
def test_copies_either_way_add_up(ways, rule):
    """Copies of the blob drawn each way in the order given (winding 1, 1, 0, 2, 0),
    all from one point: painted as cairosvg paints them (pairwise cancelling made
    ++- empty and ++-- filled under nonzero)."""
    paths = [_traced(BLOB, 0, way == "-", 0) for way in ways]
    assert_same_fill(doc('<path fill-rule="%s" d="%s"/>' % (rule, " ".join(paths))))


def test_many_copies_of_a_path_are_one_loop():
    """300 copies of a path, 200 one way and 100 the other (net 100 under nonzero: one
    loop), read as the single blob; each copy is compared with one representative."""
    paths = [_traced(BLOB, k % 4, k % 3 == 2, (k // 3) % 4) for k in range(300)]
    region = svg_region(doc('<path d="%s"/>' % " ".join(paths)))
    single = svg_region(doc('<path d="%s"/>' % _traced(BLOB, 0, False, 0)))
    assert len(region) == 1
    assert abs(mo.region_area(region) - mo.region_area(single)) < 1e-9 * mo.region_area(single)


def test_bow_tie_with_equal_lobes_is_two_triangles():
    svg = doc('<path d="M10 10 L90 90 L90 10 L10 90 Z"/>')
    region = assert_same_fill(svg, min_area=2000)
    assert abs(mo.region_area(svg_region(svg)) - 3200) < 1e-6


def test_tiny_island_is_kept():
    """An island of area 1e-12 of size^2 is a copy of B in A ⊕ B: never dropped."""
    region = svg_region("M0 0 H1000 V1000 H0 Z M2000 0 h1e-3 v1e-3 h-1e-3 Z")
    assert len(region) == 2
    assert min(abs(mo.loop_area(l)) for l in region) == pytest.approx(1e-6, rel=1e-6)


def test_elements_report_paint():
    svg = doc('<path id="a" d="M0 0 H10 V10 Z"/><path id="b" fill="none" stroke="red" '
              'd="M0 0 H10"/><path id="c" fill="none" d="M0 0 H10 V10 Z"/>')
    els = {e.label.split("id=")[1][1]: e for e in svg_elements(svg)}
    assert (els["a"].filled, els["a"].stroked) == (True, False)
    assert (els["b"].filled, els["b"].stroked) == (False, True)
    assert (els["c"].filled, els["c"].stroked) == (False, False)
    # svg_paths gives what is drawn: a (filled) and b (stroked), not c
    assert len(svg_paths(svg)) == 2 and len(svg_paths(svg, stroked=True)) == 1


def test_arcs_are_exact_under_transforms():
    """An arc under a skew stays an exact conic: points on the skewed circle."""
    svg = doc('<path transform="matrix(1 0.3 0.5 1 7 3)" d="M10 0 A10 10 0 1 1 -10 0 '
              'A10 10 0 1 1 10 0 Z"/>')
    (loop,) = svg_region(svg)
    m = np.array([[1, 0.5], [0.3, 1]])
    for p in loop:
        xy = pc.evaluate(p, np.linspace(0, 1, 7))
        xy[:, 1] = -xy[:, 1]
        local = np.linalg.solve(m, (xy - (7, 3)).T).T
        assert np.allclose(np.hypot(*local.T), 10, atol=1e-12)
