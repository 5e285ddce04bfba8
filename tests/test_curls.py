"""Tiny self-crossing curls in real contours (handwriting fonts have them): a curl is
part of the glyph's fill, filled by the nonzero rule as a renderer fills it, and the
sums take what is filled; no glyph is refused for one and the brush does not fall
back.  The curls are generated at random sizes (1e-4 to 3 units of a 1000-unit
glyph), shapes (from round loops to near-cusps whose lobe is 1e-8 of its length
wide), sides (inside or outside the glyph) and places."""

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph.minkowski import minkowski_sum
from morph.region import orient_region, region_bbox
from morph.trim import fill_region
from tests.oracles import reference as R
from tests.fontfixtures import finish_tables


def _blob(rng, n=8):
    """A simple closed loop of ``n`` cubics round (500, 500), radius 300-450."""
    ang = np.sort(rng.uniform(0, 2 * np.pi, n) + np.arange(n) * 2 * np.pi / n) % (2 * np.pi)
    ang = np.sort(ang)
    rad = rng.uniform(300, 450, n)
    pts = np.column_stack([500 + rad * np.cos(ang), 500 + rad * np.sin(ang)])
    tang = np.column_stack([-np.sin(ang), np.cos(ang)])
    loop = []
    for k in range(n):
        a, b = pts[k], pts[(k + 1) % n]
        h = 0.3 * np.linalg.norm(b - a)
        loop.append(pc.cubic(a, a + h * tang[k], b - h * tang[(k + 1) % n], b))
    return loop


def _with_curl(rng, loop, size, height, side):
    """``loop`` with a looping cubic of length ``size`` inserted in a random piece at a
    random place: it leaves the contour along its tangent, loops to the left
    (``side`` 1, inside a counter-clockwise glyph) or the right (-1, outside) with
    its lobe ``height`` times as high as it is long, and goes on."""
    k = int(rng.integers(len(loop)))
    t = rng.uniform(0.2, 0.8)
    left, right = pc.split(loop[k], t)
    p = pc.end(left)
    d = np.ravel(pc.derivative(loop[k], t))[:2]
    d = d / np.hypot(*d)
    n = np.array([-d[1], d[0]])
    s, e = size, side * height
    curl = pc.cubic(p, p + s * (2 * d + e * n), p + s * (-d + e * n), p + s * d)
    right = pc.with_endpoints(right, p + s * d, pc.end(right))
    return loop[:k] + [left, curl, right] + loop[k + 1:]


def _curled(seed):
    rng = np.random.default_rng(seed)
    loop = _blob(rng)
    for _ in range(int(rng.integers(1, 4))):
        loop = _with_curl(rng, loop, 10 ** rng.uniform(-4, 0.5), 10 ** rng.uniform(-8, 0.3),
                          rng.choice([-1, 1]))
    return [loop]


def _nonzero_fill(loops, tol):
    """Clipper's nonzero fill of the loops flattened within tol (the renderer's)."""
    return R.region_to_shapely(loops, tol)


@pytest.mark.parametrize("seed", range(40))
def test_curls_are_filled_and_summed(seed):
    """The parser's normalisation (orient_region with fill_region, as every reader
    calls it) fills the curls by the nonzero rule: the region's area is the
    renderer's; the sum with a disk is not refused and matches the fill grown by
    the disk."""
    raw = _curled(seed)
    region = orient_region(raw, "nonzero", on_crossing=fill_region)
    fill = _nonzero_fill(raw, 1e-3)
    assert abs(mo.region_area(region) - fill.area) <= 1e-3 * fill.length
    r, tol = 20.0, 0.05
    got = minkowski_sum(region, [pc.circle((0.0, 0.0), r)], tol)
    ours = R.region_to_shapely(got, 1e-3)
    exact = fill.buffer(r, quad_segs=256)
    assert exact.boundary.hausdorff_distance(ours.boundary) <= 2 * tol


def _curled_font(path, seeds):
    """A CFF font whose glyphs a, b, ... are curled blobs (:func:`_curled`)."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.pens.t2CharStringPen import T2CharStringPen

    names = [chr(ord("a") + k) for k in range(len(seeds))]
    fb = FontBuilder(1000, isTTF=False)
    fb.setupGlyphOrder([".notdef"] + names)
    fb.setupCharacterMap({ord(n): n for n in names})
    charstrings = {".notdef": T2CharStringPen(500, None).getCharString()}
    for name, seed in zip(names, seeds):
        pen = T2CharStringPen(1000, None, roundTolerance=0)
        for loop in _curled(seed):
            pen.moveTo(tuple(pc.start(loop[0])))
            for p in loop:
                c = pc.cartesian(p)
                pen.curveTo(*map(tuple, c[1:])) if len(c) == 4 else pen.lineTo(tuple(c[-1]))
            pen.closePath()
        charstrings[name] = pen.getCharString()
    fb.setupCFF("Curls", {"FullName": "Curls"}, charstrings, {})
    finish_tables(fb, [".notdef"] + names, "Curls", 1000, 900, -100)
    fb.save(str(path))
    return names


CURLED_SEEDS = (12, 13, 17)  # refused (TopologyError, SelfCrossingError) before the fill
# unfolded flat curls and dropped sliver holes (a CFF font keeps 16.16 coordinates)


def test_curled_glyphs_through_the_commands(tmp_path):
    """Font glyphs with curls: `morph offset` and `morph sum` exit 0, and `morph
    brush` writes every glyph by the exact sum (no fallback)."""
    from click.testing import CliRunner

    from morph.cli import main

    font = tmp_path / "Curls.otf"
    names = _curled_font(font, CURLED_SEEDS)
    runner = CliRunner()
    for n in names:
        res = runner.invoke(main, ["offset", n, "--font", str(font), "--radius", "0.02",
                                   "-o", str(tmp_path / ("o%s.png" % n)), "--size", "32"])
        assert res.exit_code == 0, res.output
    res = runner.invoke(main, ["brush", str(font), "-o", str(tmp_path / "B.otf"), "--jobs", "1",
                               "--sample", "abc"])
    assert res.exit_code == 0, res.output
    assert "fell back" not in res.output


# =========================================================================== tiny islands

@pytest.mark.parametrize("side", [1e-6, 1e-5, 1e-3])
@pytest.mark.parametrize("crossing", [False, True])
def test_tiny_closed_subpath_is_kept(side, crossing):
    """A tiny square next to a 50-unit square (with ``crossing``, the big one drawn as
    two overlapping squares, so the region goes through the fill) is part of the
    region: an island is small only until something is added, and `morph offset
    --radius 3` of it is a 3-unit disk beside the grown square."""
    from morph.parse import svg_region

    big = "M0 0H50V50H0Z" + (" M10 10H60V60H10Z" if crossing else "")
    d = "%s M70 0h%r v%r h-%r Z" % (big, side, side, side)
    region = svg_region(d)
    areas = sorted(mo.loop_area(loop) for loop in region)
    assert len(region) == 2 and areas[0] == pytest.approx(side * side, rel=1e-6)
    got = minkowski_sum(region, [pc.circle((0.0, 0.0), 3.0)], 1e-3)
    island = [loop for loop in got if region_bbox([loop])[0] > 65]
    assert len(island) == 1
    assert mo.loop_area(island[0]) == pytest.approx(np.pi * 9 + 4 * 3 * side, abs=1e-2)
