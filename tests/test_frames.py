"""morph_frames and the glyph / sum / svg commands."""

import re

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image
pytest.importorskip("shapely")
from shapely.geometry import Point, Polygon
pytest.importorskip("svgpathtools")
from svgpathtools import parse_path

from morph import piece as pc
from morph import moments as mo
from morph.cli import main
from morph.frames import centered, frames_bbox, iter_frames, morph_frames, scale_region
from morph.region import region_bbox
from morph.parse import glyph_region
from morph.render import render_png
from tests.imagediff import assert_matches_golden


@pytest.fixture(scope="module")
def tm_frames():
    return morph_frames(glyph_region("T").region, glyph_region("M").region, 5, 0.1)


def test_end_frames_are_the_operands(tm_frames):
    t = centered(glyph_region("T").region)
    m = centered(glyph_region("M").region)
    assert abs(mo.region_area(tm_frames[0]) - mo.region_area(t)) < 1e-9
    assert abs(mo.region_area(tm_frames[-1]) - mo.region_area(m)) < 1e-9


def test_frames_obey_brunn_minkowski(tm_frames):
    """sqrt|(1-a)T ⊕ aM| >= (1-a) sqrt|T| + a sqrt|M| (any compact sets), strict here."""
    a = np.linspace(0, 1, 5)
    areas = np.array([mo.region_area(f) for f in tm_frames])
    bound = (1 - a) * np.sqrt(areas[0]) + a * np.sqrt(areas[-1])
    assert np.all(np.sqrt(areas[1:-1]) > bound[1:-1] * 1.01)


def test_scale_region_exact():
    r = [pc.circle([1.0, 2.0], 3.0)]
    assert abs(mo.region_area(scale_region(r, 0.5)) - np.pi * 1.5 ** 2) < 1e-12


def test_tm_frame_golden(tm_frames):
    """Frame 2 of T -> M (the paper's Fig. 6) against a golden image."""
    lo = np.min([np.min([pc.bbox(p)[:2] for l in f for p in l], axis=0) for f in tm_frames], axis=0)
    hi = np.max([np.max([pc.bbox(p)[2:] for l in f for p in l], axis=0) for f in tm_frames], axis=0)
    img = render_png([tm_frames[2]], size=200, bbox=(lo[0], lo[1], hi[0], hi[1]))
    assert_matches_golden(img, "tm_frame2")


def test_glyph_command_writes_frames_and_gif(tmp_path):
    out = tmp_path / "tm"
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", "3", "-o", str(out),
                                    "--size", "64"])
    assert res.exit_code == 0, res.output
    names = sorted(p.name for p in out.iterdir())
    assert names == ["frame-000.png", "frame-000.svg", "frame-001.png", "frame-001.svg",
                     "frame-002.png", "frame-002.svg", "morph.gif"]
    assert Image.open(out / "morph.gif").n_frames == 3
    # not clobbered without --force
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", "3", "-o", str(out)])
    assert res.exit_code == 2 and "force" in res.output


def test_glyph_command_writes_an_apng_on_request(tmp_path):
    """--animation apng: morph.apng, an animated PNG in full colour (anti-aliased edge
    levels kept, where the GIF has a palette), one image per frame."""
    out = tmp_path / "tm"
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", "3", "-o", str(out),
                                    "--size", "64", "--animation", "apng"])
    assert res.exit_code == 0, res.output
    assert "morph.apng" in res.output and not (out / "morph.gif").exists()
    im = Image.open(out / "morph.apng")
    assert im.format == "PNG" and im.is_animated and im.n_frames == 3
    assert im.mode in ("RGB", "RGBA")
    levels = set()
    for k in range(im.n_frames):
        im.seek(k)
        levels |= set(np.asarray(im.convert("L")).ravel().tolist())
    assert len(levels) > 16
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", "3", "-o", str(out),
                                    "--animation", "mp4"])
    assert res.exit_code == 2


@pytest.mark.parametrize("frames", ["0", "1", "-3", "1001", "100000"])
def test_glyph_command_rejects_bad_frame_counts(tmp_path, frames):
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", frames, "-o", str(tmp_path / "x")])
    assert res.exit_code == 2
    assert "frames" in res.output


def test_sum_command_with_method(tmp_path):
    for method in ("qac", "lsc"):
        out = tmp_path / ("om-%s.svg" % method)
        res = CliRunner().invoke(main, ["sum", "O", "M", "--method", method, "-o", str(out)])
        assert res.exit_code == 0, res.output
        assert out.read_text().startswith("<")


def test_sum_command_missing_glyph_is_one_line(tmp_path):
    res = CliRunner().invoke(main, ["sum", "O", "\u4e2d", "-o", str(tmp_path / "x.png")])
    assert res.exit_code == 2
    assert len(res.output.strip().splitlines()) == 1


@pytest.mark.parametrize("a, b, cff", [("T", "M", False), ("S", "g", True)])
def test_cached_gauss_maps_give_the_same_frames(a, b, cff):
    """morph_frames computes the Gauss maps and compatible pairs once (cache=True;
    here each frame summed alone, batch=False, and approximated on its own,
    blend=False: test_packed_frames_... checks the packed sums, test_blended_...
    the blended convolution).  The convolution pieces are those of independent sums to rounding (1e-12 of the
    size); the trimmed frames agree to 1e-6 of the size: cutting at near-tangent
    crossings amplifies that rounding (a shift e becomes e / sin(angle))."""
    from morph import convolve
    from morph.frames import centered, scale_region
    from morph.parse import cubic_test_font_path
    font = cubic_test_font_path() if cff else None
    ra, rb = centered(glyph_region(a, font).region), centered(glyph_region(b, font).region)
    alpha = 0.4
    sa, sb = scale_region(ra, 1 - alpha), scale_region(rb, alpha)
    base = convolve.with_pair_table(convolve.gauss_pair_of(ra, rb))
    plain_conv = convolve.convolution(sa, sb, 1.0)
    cached_conv = convolve.convolution(sa, sb, 1.0,
                                       gauss_pair=convolve.scaled_gauss_pair(base, 1 - alpha, alpha))
    pts = np.concatenate([pc.cartesian(c.piece) for c in plain_conv])
    size = float(np.ptp(pts, axis=0).max())
    assert len(plain_conv) == len(cached_conv)
    for c0, c1 in zip(plain_conv, cached_conv):
        assert c0.piece.shape == c1.piece.shape
        assert np.abs(pc.cartesian(c0.piece) - pc.cartesian(c1.piece)).max() <= 1e-12 * size
    plain = morph_frames(ra, rb, 4, 1.0, cache=False)
    cached = morph_frames(ra, rb, 4, 1.0, cache=True, batch=False, blend=False)
    assert len(plain) == len(cached)
    for f0, f1 in zip(plain, cached):
        assert [len(loop) for loop in f0] == [len(loop) for loop in f1]
        for p, q in zip([p for loop in f0 for p in loop], [q for loop in f1 for q in loop]):
            assert p.shape == q.shape
            assert np.abs(pc.cartesian(p) - pc.cartesian(q)).max() <= 1e-6 * size

def _bundled(name):
    from pathlib import Path

    import morph
    from morph.parse import svg_region

    return svg_region(str(Path(morph.__file__).parent / "data" / name))


def _chain_gaps(conv, ref):
    """The largest gap of each table row's chain of pieces in ``conv`` (between
    consecutive pieces, and between its first start and last end and those of the
    same row in ``ref``: the exact sums of the pair's end points)."""
    worst = 0.0
    for r in np.unique(ref.row):
        ends = []
        for c in (conv, ref):
            idx = np.flatnonzero(c.row == r)
            starts = np.array([pc.start(c.pieces[k]) for k in idx])
            stops = np.array([pc.end(c.pieces[k]) for k in idx])
            worst = max(worst, float(np.abs(starts[1:] - stops[:-1]).max(initial=0.0)))
            ends.append(np.concatenate([starts[0], stops[-1]]))
        worst = max(worst, float(np.abs(ends[0] - ends[1]).max()))
    return worst


@pytest.mark.parametrize("case", ["bird-butterfly", "S-g", "arc-bird"])
def test_blended_convolution_is_each_frames_convolution(case, monkeypatch):
    """The first round of packed frames blends every frame's convolution pieces
    from two sets made once on the unit operands (morph.frames._Blend): frame a's
    piece is ((1 - a) X_A + a X_B + W o, W), o its offset.  For three frames moved
    apart, against the convolution of their own Gauss maps (each pair subdivided at
    its frame's scale): every table row has pieces, of its type and edges, chained
    end to start between the same end points (the exact sums of the pair's end
    points), each within its row's tolerance.  And every sub-pair the unit
    operands accepted, scaled and moved to a frame and made by morph.qac's own
    piece_nodes, is the blended piece (the same points at 9 parameters, to
    1e-9 of the size): the weights depend on tangent directions only and the
    points are linear in the operands'.  Bird and butterfly (polynomial cubics,
    the bundled morph), a CFF S and g, an SVG with elliptic arcs (rational conics)
    and the bird.  Blends taken at a + 0.03, or with the two terms swapped, fail."""
    from morph import convolve, qac
    from morph import frames as fr
    from morph.parse import cubic_test_font_path, svg_region

    if case == "bird-butterfly":
        ra, rb = _bundled("bird.svg"), _bundled("butterfly.svg")
    elif case == "S-g":
        font = cubic_test_font_path()
        ra, rb = glyph_region("S", font).region, glyph_region("g", font).region
    else:
        ra = svg_region('<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 A 50 30 20 '
                        '1 1 60 40 L 30 80 Z"/></svg>')
        rb = _bundled("bird.svg")
    ra, rb = centered(ra), centered(rb)
    base = convolve.with_pair_table(convolve.gauss_pair_of(ra, rb))
    alphas = np.array([0.2, 0.55, 0.9])
    size = float(max(np.ptp(region_bbox(ra)), np.ptp(region_bbox(rb))))
    offsets = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]]) * size
    pair = fr._packed_gauss_pair(base, alphas, offsets)
    tol = 1e-3 * size
    row_tol = np.full(len(pair.table[0]), tol)
    accepted = []
    real = convolve.subdivide_nodes     # the driver convolve.qac_batches calls

    def keep(*args, **kwargs):
        out = real(*args, **kwargs)
        accepted.append(out[0])
        return out

    monkeypatch.setattr(convolve, "subdivide_nodes", keep)
    got = fr._Blend(base, alphas).frames(row_tol, alphas, offsets, pair)
    monkeypatch.setattr(convolve, "subdivide_nodes", real)
    assert accepted
    want = convolve.convolution(None, None, row_tol, keep_type3=True, gauss_pair=pair)
    assert np.array_equal(np.unique(got.row), np.unique(want.row))
    assert np.all(got.bound <= row_tol[got.row])
    for field in ("type", "source"):
        g, w = getattr(got, field), getattr(want, field)
        for r in np.unique(want.row):
            assert (g[got.row == r] == w[want.row == r][0]).all(), field
    assert _chain_gaps(got, want) <= 1e-9 * size
    wrong = fr._Blend(base, alphas + 0.03).frames(row_tol, alphas + 0.03, offsets, pair)
    assert _chain_gaps(wrong, want) > 1e-3 * size

    def moved(stack, f, o):
        out = stack * [f, f, 1.0]
        out[..., :2] += o * stack[..., 2:]
        return out

    t = np.linspace(0.0, 1.0, 9)
    for swap_terms in (False, True):
        worst = 0.0
        for nodes in accepted:
            terms = fr._node_sets(nodes)
            for alpha, o in zip(alphas, offsets):
                fa, fb = 1.0 - alpha, alpha
                scaled = dict(nodes, ca=moved(nodes["ca"], fa, o), cb=moved(nodes["cb"], fb, 0.0))
                on_a = nodes["swap"][:, None, None]   # C2 (replaced by q2) is A's piece
                scaled["q2"] = np.where(on_a, fa * nodes["q2"] + o, fb * nodes["q2"])
                for h, own in zip(terms, qac.piece_nodes(scaled)):
                    assert (h is None) == (own is None)
                    if h is None:
                        continue
                    xa, xb = (h[:, 2:4], h[:, 0:2]) if swap_terms else (h[:, 0:2], h[:, 2:4])
                    blend = np.column_stack([fa * xa + fb * xb + o * h[:, 4:], h[:, 4]])
                    worst = max(worst, float(np.abs(pc.evaluate(blend, t)
                                                    - pc.evaluate(own, t)).max()))
        assert (worst > 1e-3 * size) if swap_terms else (worst <= 1e-9 * size), worst


def _frame_faults(frame, a, b, tol, rng):
    """How many of a frame's boundary samples (24, mid-piece) have no point of the
    exact sum (1 - a) A ⊕ a B, or no point outside it, within tol (probed at the two
    normal points and 24 around, tests.oracles.membership.straddle), plus how many of
    20 random points in its box the exact membership predicate x ∈ A ⊕ B ⇔
    A ∩ (x − B) ≠ ∅ places on the other side of the frame's boundary."""
    from tests.oracles.membership import Oracle, boundary_samples, inside, straddle

    oracle = Oracle(a, b, 1e-3)
    pts, nrm = boundary_samples(frame)
    pick = rng.choice(len(pts), min(24, len(pts)), replace=False)
    probes = straddle(oracle, pts[pick], nrm[pick], tol)
    box = region_bbox(frame)
    x = rng.uniform(box[:2] - 20 * tol, box[2:] + 20 * tol, size=(20, 2))
    return int(np.sum(probes.all(axis=1) | ~probes.any(axis=1))
               + np.sum(inside(frame, x) != oracle(x)))


@pytest.mark.parametrize("a, b, tol, cff", [("T", "M", 1.0, False), ("S", "g", 0.5, True)])
def test_packed_frames_are_the_frames_summed_one_by_one(a, b, tol, cff, monkeypatch):
    """iter_frames sums the inner frames together, moved apart (one packed sum of
    up to FRAME_GROUP frames).  Each packed frame k is (1 - a) A ⊕ a B at its own a
    by the exact membership predicate (:func:`_frame_faults`: its boundary within tol
    of the exact one, random points on the right side), and it is the frame summed
    alone: the same loops of as many pieces, the same achieved bound, and within
    the two bounds of each other (Hausdorff; each is within its bound of the exact
    frame).  Not to rounding: the integer grid on which the trimming decides the
    topology has another phase in the packed sum (its origin is the centre of all
    the frames' polylines), so where two convolution segments nearly coincide (the
    horizontal stems of T and M) the junction between them can move along them,
    within the trimming's shares (0.13 tol here).  The check fails a frame moved by
    2 tol, and a frame checked at its neighbour's a.  Groups of 3 frames
    (FRAME_GROUP is 8) keep the oracle's work small: 7 frames are the two
    operands, a group of 3 and one of 2."""
    from morph import frames
    from morph.parse import cubic_test_font_path
    from morph.region import translate_region
    from tests.oracles.reference import hausdorff, region_to_shapely

    font = cubic_test_font_path() if cff else None
    ra, rb = glyph_region(a, font).region, glyph_region(b, font).region
    monkeypatch.setattr(frames, "FRAME_GROUP", 3)
    n = 7
    packed = morph_frames(ra, rb, n, tol)
    alone = morph_frames(ra, rb, n, tol, batch=False)
    ca, cb = centered(ra), centered(rb)
    operands = [(scale_region(ca, 1.0 - t), scale_region(cb, t))
                for t in np.linspace(0.0, 1.0, n)]
    rng = np.random.default_rng(7)
    for k in range(1, n - 1):
        f, g = packed[k], alone[k]
        assert _frame_faults(f, *operands[k], tol, rng) == 0, k
        assert [len(loop) for loop in f] == [len(loop) for loop in g], k
        assert abs(f.bound - g.bound) <= 1e-9 * tol, k
        # sampled every tol / 2: at most tol / 4 short of the distance
        assert hausdorff(region_to_shapely(f, tol / 20), region_to_shapely(g, tol / 20),
                         spacing=tol / 2) <= f.bound + g.bound, k
    assert _frame_faults(translate_region(packed[3], (2 * tol, 0.0)), *operands[3], tol,
                         rng) > 0
    assert _frame_faults(packed[4], *operands[3], tol, rng) > 0


def test_packed_frames_test_holes_at_their_own_scale():
    """(1 - a) R ⊕ a D of a ring R (radii 10 and 4) and a disk D (radius 3) is a ring
    of radii 10 (1 - a) + 3 a and 4 (1 - a) - 3 a, or a disk once a >= 4/7: the
    disk's convolution with the hole leaves a cell of winding 0 that the exact
    membership test fills (Sec. 6).  Every packed frame has its hole exactly when
    it should, and its area (within tol times the perimeters): each hole is
    tested with its own frame's operands, not another frame's."""
    from morph.region import reverse_loop

    ring = [pc.circle((0.0, 0.0), 10.0), reverse_loop(pc.circle((0.0, 0.0), 4.0))]
    disk = [pc.circle((0.0, 0.0), 3.0)]
    n, tol = 7, 1e-3
    for f, a in zip(morph_frames(ring, disk, n, tol), np.linspace(0.0, 1.0, n)):
        outer, inner = 10.0 * (1 - a) + 3.0 * a, 4.0 * (1 - a) - 3.0 * a
        assert len(f) == (2 if inner > 0 else 1), a
        area = np.pi * (outer ** 2 - max(inner, 0.0) ** 2)
        assert abs(mo.region_area(f) - area) <= tol * 2 * np.pi * (outer + max(inner, 0.0))


def test_frames_report_the_error_each_achieved(tm_frames):
    """Each frame's bound: 0 for the operands, (0, tol] for the sums."""
    frames = morph_frames(glyph_region("T").region, glyph_region("M").region, 5, 0.1)
    bounds = [f.bound for f in frames]
    assert [mo.region_area(f) for f in frames] == [mo.region_area(f) for f in tm_frames]
    assert bounds[0] == bounds[-1] == 0.0
    assert all(0.0 < e <= 0.1 for e in bounds[1:-1])


def test_svg_frames_are_within_tol_of_the_exact_frames(tmp_path):
    """`morph svg square.svg disk.svg`: frame k is (1 - a) S ⊕ a D, a rounded square
    whose boundary lies a r from (1 - a) S.  Every written frame, its export given
    the rest of --tol beyond what its sum achieved, stays within --tol (sampled
    points of the written Béziers, distances to the scaled square by shapely)."""
    (tmp_path / "s.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg">'
                                    '<rect x="-50" y="-50" width="100" height="100"/></svg>')
    (tmp_path / "d.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg">'
                                    '<circle cx="0" cy="0" r="30"/></svg>')
    tol, n = 1e-3, 4
    res = CliRunner().invoke(main, ["svg", str(tmp_path / "s.svg"), str(tmp_path / "d.svg"),
                                    "--frames", str(n), "--tol", str(tol), "-o",
                                    str(tmp_path / "f"), "--size", "64"])
    assert res.exit_code == 0, res.output
    t = np.linspace(0.0, 1.0, 41)
    for k, a in enumerate(np.linspace(0.0, 1.0, n)):
        d = re.search(r' d="([^"]*)"', (tmp_path / "f" / ("frame-%03d.svg" % k)).read_text())
        pts = np.array([seg.point(u) for seg in parse_path(d.group(1)) for u in t])
        h = 50.0 * (1.0 - a)
        square = Polygon([(-h, -h), (h, -h), (h, h), (-h, h)]).exterior
        dist = np.array([square.distance(Point(p.real, p.imag)) for p in pts]) if h > 0 \
            else np.abs(pts)
        assert np.abs(dist - 30.0 * a).max() <= tol, (k, np.abs(dist - 30.0 * a).max())


def test_frames_bbox_holds_every_frame(tm_frames):
    """frames_bbox (from the operands' boxes alone, before any sum) is the union of
    the computed frames' tight boxes, to the sums' tol (0.1 units here)."""
    box = frames_bbox(glyph_region("T").region, glyph_region("M").region)
    boxes = np.array([region_bbox(f) for f in tm_frames])
    union = np.concatenate([boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)])
    assert np.abs(box - union).max() <= 0.1
    # the inner frames' boxes are the interpolated operand boxes
    a = np.linspace(0.0, 1.0, 5)[:, None]
    assert np.abs(boxes - ((1 - a) * boxes[0] + a * boxes[-1])).max() <= 0.1


def test_iter_frames_gives_morph_frames_one_at_a_time(tm_frames):
    it = iter_frames(glyph_region("T").region, glyph_region("M").region, 5, 0.1)
    first = next(it)
    assert first.bound == 0.0 and mo.region_area(first) == mo.region_area(tm_frames[0])
    rest = list(it)
    assert [mo.region_area(f) for f in rest] == [mo.region_area(f) for f in tm_frames[1:]]


def test_frames_are_written_as_they_are_done(tmp_path):
    """write_frame_stream stores each frame when it arrives: a sequence that stops
    (here a generator failing at its third frame) leaves its first frames on disk."""
    from morph.render import write_frame_stream

    def frames():
        for r in (1.0, 2.0):
            yield [pc.circle((0.0, 0.0), r)], 1e-3
        raise RuntimeError("stopped")

    with pytest.raises(RuntimeError):
        write_frame_stream(tmp_path, frames(), (-3.0, -3.0, 3.0, 3.0), size=32)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "frame-000.png", "frame-000.svg", "frame-001.png", "frame-001.svg"]


def test_frame_curves_are_fitted_in_batches(tmp_path, monkeypatch):
    """write_frame_stream converts the curves of FRAME_BATCH frames in one batch (a
    round's array calls serve all of them): 20 frames, two batches of 16 and 4
    frames' loops; every frame written."""
    from morph.render import figures, svg, write_frame_stream

    calls = []
    real = svg.loops_to_beziers

    def counted(loops, *args, **kwargs):
        calls.append(len(loops))
        return real(loops, *args, **kwargs)

    monkeypatch.setattr(svg, "loops_to_beziers", counted)
    frames = [([pc.circle((0.0, 0.0), 1.0 + k / 10)], 1e-3) for k in range(20)]
    write_frame_stream(tmp_path, iter(frames), (-3.0, -3.0, 3.0, 3.0), size=32)
    # (each frame's writer then meets its fitted Béziers: one loop, written as it is)
    assert [n for n in calls if n > 1] == [figures.FRAME_BATCH, 20 - figures.FRAME_BATCH]
    assert len(list(tmp_path.glob("frame-*.svg"))) == 20


def test_glyph_command_refuses_an_animation_beyond_memory(tmp_path, monkeypatch):
    """The animation's frames stay in memory: frames x size^2 bytes (GIF) against a
    quarter of the memory budget (here 1 GB); one line, nothing written."""
    monkeypatch.setattr("morph.limits.memory_budget_bytes", lambda: 2 ** 30)
    out = tmp_path / "x"
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", "300", "--size", "1024",
                                    "-o", str(out)])
    assert res.exit_code == 2 and len(res.output.strip().splitlines()) == 1
    assert "0.3 GB" in res.output and "--frames" in res.output and not out.exists()
    res = CliRunner().invoke(main, ["glyph", "T", "M", "--frames", "3", "--size", "1024",
                                    "--animation", "apng", "-o", str(out)])
    assert res.exit_code == 0, res.output


def test_a_frame_that_raises_comes_after_the_frames_before_it(monkeypatch):
    """When a packed group of frames raises, its frames are summed one by one: the
    frames before the one that fails still arrive, then its own error."""
    from morph import frames
    from morph.errors import LimitError

    def packed_fails(*args):
        raise LimitError("the packed sum failed")

    real = frames._one_frame

    def third_fails(a, b, t, *args):
        if abs(t - 3 / 7) < 1e-12:
            raise LimitError("frame 3 failed")
        return real(a, b, t, *args)

    monkeypatch.setattr(frames, "_split_frames", packed_fails)
    monkeypatch.setattr(frames, "_one_frame", third_fails)
    got = []
    with pytest.raises(LimitError, match="frame 3"):
        for f in iter_frames(glyph_region("T").region, glyph_region("M").region, 8, 1.0):
            got.append(f)
    assert len(got) == 3 and got[0].bound == 0.0 and all(f.bound > 0 for f in got[1:])
