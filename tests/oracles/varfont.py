"""Independent references for the untrimmed convolutions of morph.compatible and the
variable fonts of morph.fonts.variable: plain numpy winding numbers of flattened
loops, the exact membership predicate x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ for an elliptical
nib (an ellipse-metric distance), and Clipper sums of finely flattened inputs
compared with filled outlines by boundary distances.  Nothing here calls morph's
geometry."""

import numpy as np


def bezier_points(ctrl, k):
    """k + 1 points of a Bézier (n+1, 2) from t = 0 to 1 (Bernstein form)."""
    from math import comb

    ctrl = np.asarray(ctrl, float)
    n = len(ctrl) - 1
    t = np.linspace(0.0, 1.0, k + 1)[:, None]
    return sum(comb(n, i) * t ** i * (1 - t) ** (n - i) * ctrl[i] for i in range(n + 1))


def flatten_cubics(loop, k=48):
    """A closed polyline (m, 2) through a loop of cubics ((n, 4, 2)), k chords each."""
    return np.vstack([bezier_points(c, k)[:-1] for c in loop])


def winding_numbers(points, polylines):
    """Winding numbers of closed polylines around points (the crossing rule of a ray
    to +x: upward edges +1, downward -1)."""
    points = np.asarray(points, float)
    w = np.zeros(len(points), int)
    for poly in polylines:
        p, q = poly, np.roll(poly, -1, axis=0)
        for start in range(0, len(points), 2000):
            x = points[start:start + 2000, None, :]
            cross = (q[:, 0] - p[:, 0]) * (x[..., 1] - p[:, 1]) - \
                    (q[:, 1] - p[:, 1]) * (x[..., 0] - p[:, 0])
            up = (p[:, 1] <= x[..., 1]) & (q[:, 1] > x[..., 1]) & (cross > 0)
            down = (q[:, 1] <= x[..., 1]) & (p[:, 1] > x[..., 1]) & (cross < 0)
            w[start:start + 2000] += up.sum(axis=1) - down.sum(axis=1)
    return w


def ellipse_matrix(width, height, angle_deg):
    a = np.radians(angle_deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]]) @ np.diag([width / 2.0, height / 2.0])


def segment_distances(points, segments):
    """Distance of each point to the nearest of the segments ((m, 2, 2))."""
    points = np.asarray(points, float)
    out = np.full(len(points), np.inf)
    a, b = segments[:, 0], segments[:, 1]
    d = b - a
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    for start in range(0, len(points), 1000):
        x = points[start:start + 1000, None, :]
        t = np.clip(np.einsum("kij,ij->ki", x - a, d) / dd, 0.0, 1.0)
        near = a + t[..., None] * d
        out[start:start + 1000] = np.linalg.norm(x - near, axis=-1).min(axis=1)
    return out


def ellipse_metric_distance(points, polylines, width, height, angle_deg):
    """min over the polylines' points p of |M⁻¹ (x − p)|: x is in (polylines) ⊕ nib
    exactly when this is <= 1 (the nib M (unit disk) centred on the pen point)."""
    inv = np.linalg.inv(ellipse_matrix(width, height, angle_deg))
    segs = np.concatenate([np.stack([pl[:-1], pl[1:]], axis=1) for pl in polylines])
    return segment_distances(np.asarray(points) @ inv.T, segs @ inv.T)


def classify_against_predicate(points, loops, skeleton_lines, nib, margin, region=None):
    """(checked, wrong) counts: points whose membership in skeleton ⊕ nib (or region ⊕
    nib: ``region`` as closed polylines, ``skeleton_lines`` its boundary) is decided by
    more than ``margin`` font units, against the nonzero fill of the loops (cubic
    loops, (n, 4, 2))."""
    width, height, angle = nib
    d = ellipse_metric_distance(points, skeleton_lines, width, height, angle)
    inside = d <= 1.0
    if region is not None:
        inside |= winding_numbers(points, region) != 0
    clear = np.abs(d - 1.0) * min(width, height) / 2.0 > margin
    if region is not None:      # deep inside the region: decided
        clear |= (winding_numbers(points, region) != 0)
    w = winding_numbers(points, [flatten_cubics(lp) for lp in loops])
    filled = w != 0
    negative = int((w < 0).sum())
    return int(clear.sum()), int((filled != inside)[clear].sum()), negative


# ------------------------------------------------- Clipper sums and filled outlines

_CLIP = 1000.0      # Clipper integer units per font unit


def skeleton_polylines(paths, k=48):
    """Open polylines of skeleton paths ((pieces, closed), pieces homogeneous or
    cartesian control arrays), k chords per piece."""
    out = []
    for pieces, _ in paths:
        pts = [bezier_points(np.asarray(p, float)[:, :2] / (np.asarray(p, float)[:, 2:]
                                                              if np.shape(p)[1] == 3 else 1.0),
                             k) for p in pieces]
        out.append(np.vstack(pts))
    return out


def clipper_stroke(polylines, nib, arc_tol=0.002):
    """skeleton ⊕ elliptical nib by Clipper: the space mapped so that the nib is a
    disk (M⁻¹), the open polylines offset with round ends and joins (the sum with a
    disk, within ``arc_tol`` font units), mapped back.  Closed polygons (y up)."""
    import pyclipper

    width, height, angle = nib
    m = ellipse_matrix(width, height, angle)
    r = min(width, height) / 2.0 * _CLIP          # disk radius in integer units
    to = np.linalg.inv(m) * r
    off = pyclipper.PyclipperOffset()
    off.ArcTolerance = arc_tol * _CLIP
    dots = []
    for pl in polylines:
        q = np.round(pl @ to.T).astype(np.int64)
        if len(np.unique(q, axis=0)) < 2:
            dots.append(pl[0])
            continue
        # segment by segment: the sum distributes over a union, and one offset of a
        # path that closes or crosses itself has the convolution's own winding
        # (0 inside a loop the nib covers): a convex stadium each is always right
        keep = np.ones(len(q), bool)
        keep[1:] = np.any(q[1:] != q[:-1], axis=1)
        q = q[keep]
        off.AddPaths([q[i:i + 2].tolist() for i in range(len(q) - 1)], pyclipper.JT_ROUND,
                     pyclipper.ET_OPENROUND)
    polys = [np.asarray(p, float) @ np.linalg.inv(to).T for p in off.Execute(r)] \
        if off is not None else []
    ang = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    for d in dots:
        polys.append(d + np.column_stack([np.cos(ang), np.sin(ang)]) @ m.T)
    return union(polys)


def union(polylines):
    """Closed polylines united under the nonzero rule (Clipper), as closed polygons."""
    import pyclipper

    pc = pyclipper.Pyclipper()
    paths = [np.round(np.asarray(p) * _CLIP).astype(np.int64).tolist() for p in polylines
             if len(p) >= 3]
    if not paths:
        return []
    pc.AddPaths(paths, pyclipper.PT_SUBJECT, True)
    out = pc.Execute(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    return [np.asarray(p, float) / _CLIP for p in out]


class FlattenPen:
    """A fontTools pen recording a glyph's contours as closed polylines (curves cut
    into chords no longer than ``step`` along their control polygon)."""

    def __init__(self, step=0.5):
        self.step = step
        self.polys, self.cur = [], None

    def moveTo(self, p):
        self.cur = [np.asarray(p, float)]

    def lineTo(self, p):
        self.cur.append(np.asarray(p, float))

    def _curve(self, ctrl):
        ctrl = np.asarray(ctrl, float)
        length = np.linalg.norm(np.diff(ctrl, axis=0), axis=1).sum()
        k = max(2, int(np.ceil(length / self.step)))
        self.cur.extend(bezier_points(ctrl, k)[1:])

    def curveTo(self, *pts):
        from fontTools.pens.basePen import decomposeSuperBezierSegment

        if len(pts) == 3:
            self._curve([self.cur[-1], *pts])
            return
        for seg in decomposeSuperBezierSegment(pts):
            self._curve([self.cur[-1], *seg])

    def qCurveTo(self, *pts):
        from fontTools.pens.basePen import decomposeQuadraticSegment

        if pts[-1] is None:
            raise ValueError("closed quadratic contours without on-curve points")
        for seg in decomposeQuadraticSegment(pts):
            self._curve([self.cur[-1], *seg])

    def closePath(self):
        if self.cur is not None and len(self.cur) >= 3:
            self.polys.append(np.vstack(self.cur))
        self.cur = None

    endPath = closePath

    def addComponent(self, name, transform):
        raise ValueError("decompose components first (use a glyph set)")


def glyph_polygons(glyph_set, name, step=0.25):
    """The nonzero fill of a glyph of a fontTools glyph set, as Clipper polygons."""
    from fontTools.pens.recordingPen import DecomposingRecordingPen

    rec = DecomposingRecordingPen(glyph_set)
    glyph_set[name].draw(rec)
    pen = FlattenPen(step)
    rec.replay(pen)
    return union(pen.polys)


def _densify(polys, spacing):
    out = []
    for p in polys:
        q = np.roll(p, -1, axis=0)
        n = np.maximum(1, np.ceil(np.linalg.norm(q - p, axis=1) / spacing)).astype(int)
        for a, b, k in zip(p, q, n):
            t = np.arange(k)[:, None] / k
            out.append(a + t * (b - a))
    return np.vstack(out) if out else np.zeros((0, 2))


def boundary_distance(polys_a, polys_b, spacing=0.02):
    """Hausdorff distance between the boundaries of two polygon sets (densified at
    ``spacing``: exact within spacing / 2); inf when one is empty and not the other."""
    from tests.oracles import need

    need("scipy", "nearest boundary points")
    from scipy.spatial import cKDTree

    a, b = _densify(polys_a, spacing), _densify(polys_b, spacing)
    if len(a) == 0 or len(b) == 0:
        return 0.0 if len(a) == len(b) else float("inf")
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


def _offset(polys, d):
    import pyclipper

    off = pyclipper.PyclipperOffset()
    off.ArcTolerance = 0.001 * _CLIP
    off.AddPaths([np.round(p * _CLIP).astype(np.int64).tolist() for p in polys],
                 pyclipper.JT_ROUND, pyclipper.ET_CLOSEDPOLYGON)
    return [np.asarray(p, float) / _CLIP for p in off.Execute(d * _CLIP)]


def _difference_area(a, b):
    """Area of the largest polygon of a \\ b (font units²), polygons as Clipper
    returns them."""
    import pyclipper

    if not a:
        return 0.0
    pc = pyclipper.Pyclipper()
    pc.AddPaths([np.round(p * _CLIP).astype(np.int64).tolist() for p in a],
                pyclipper.PT_SUBJECT, True)
    if b:
        pc.AddPaths([np.round(p * _CLIP).astype(np.int64).tolist() for p in b],
                    pyclipper.PT_CLIP, True)
    out = pc.Execute(pyclipper.CT_DIFFERENCE, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    return max((abs(pyclipper.Area(p)) for p in out), default=0.0) / _CLIP ** 2


def within(filled, exact, d, strict=False, area=1.0):
    """Do the filled outline F and the exact sum S differ only within d of their
    boundaries: erode(S, d) ⊆ dilate(F, d) and erode(F, d) ⊆ dilate(S, d) (every
    point of F Δ S within d of ∂S or ∂F: a missing feature counts by its half-width,
    a sliver pinhole too)?  ``strict``: within d of ∂S alone, erode(S, d) ⊆ F ⊆
    dilate(S, d) (a pinhole counts by its depth).  ``area``: leftover parts of the
    differences smaller than this many units² each are ignored: Clipper's rounding,
    and the pinholes that the fit and the integer rounding open where the
    overlapping outline turns back at a swallowtail's cusp (a cusp moved by delta
    becomes a loop about delta wide; 1 unit² is 1e-6 em²); :func:`pinholes` lists
    them."""
    if strict:
        return (_difference_area(filled, _offset(exact, d)) <= area and
                _difference_area(_offset(exact, -d), filled) <= area)
    return (_difference_area(_offset(exact, -d), _offset(filled, d)) <= area and
            _difference_area(_offset(filled, -d), _offset(exact, d)) <= area)


def sum_distance(filled, exact, hi=4.0, step=0.01, strict=False, area=1.0):
    """The least d (to ``step``) for which :func:`within` holds; ``hi`` when even
    that does not hold."""
    if not within(filled, exact, hi, strict, area):
        return hi
    lo = 0.0
    while hi - lo > step:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if within(filled, exact, mid, strict, area) else (mid, hi)
    return hi


def pinholes(filled, exact, depth=1.0):
    """Areas (units²) of the parts of the exact sum that the filled outline leaves
    open deeper than ``depth`` inside it: the cusp pinholes of an overlapping
    outline."""
    import pyclipper

    inner = _offset(exact, -depth)
    if not inner:
        return []
    pc = pyclipper.Pyclipper()
    pc.AddPaths([np.round(p * _CLIP).astype(np.int64).tolist() for p in inner],
                pyclipper.PT_SUBJECT, True)
    if filled:
        pc.AddPaths([np.round(p * _CLIP).astype(np.int64).tolist() for p in filled],
                    pyclipper.PT_CLIP, True)
    out = pc.Execute(pyclipper.CT_DIFFERENCE, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    return sorted(abs(pyclipper.Area(p)) / _CLIP ** 2 for p in out)


def skeleton_designspace(folder, source, glyphs, slant=0.15, widen=0.25):
    """A small compatible skeleton designspace made from a skeleton UFO: ``glyphs``
    of ``source`` as the Regular master (wdth 100) and the same centre lines mapped
    by x' = (1 + widen) x + slant y as the Wide master (wdth 125, advances and
    anchors mapped too): the same structure, points moved.  Returns the path; at
    wdth = 100 + 25 u the skeleton is the map with u widen and u slant."""
    import copy

    import ufoLib2
    from fontTools.designspaceLib import (AxisDescriptor, DesignSpaceDocument,
                                          InstanceDescriptor, SourceDescriptor)

    from pathlib import Path

    folder = Path(folder)
    base = ufoLib2.Font.open(str(source))
    keep = set(glyphs)
    for g in base:
        keep.update(c.baseGlyph for c in g.components if g.name in glyphs)
    for name in list(base.keys()):
        if name not in keep:
            del base[name]
    base.features.text = ""
    base.kerning.clear()
    base.groups.clear()
    base.info.styleName = "Regular"
    wide = copy.deepcopy(base)
    wide.info.styleName = "Wide"
    for g in wide:
        for c in g.contours:
            for p in c.points:
                p.x = (1 + widen) * p.x + slant * p.y
        for a in g.anchors:
            a.x = (1 + widen) * a.x + slant * a.y
        for c in g.components:
            xx, xy, yx, yy, dx, dy = tuple(c.transformation)
            c.transformation = (xx, xy, yx, yy, (1 + widen) * dx + slant * dy, dy)
        g.width = round((1 + widen) * g.width)
    base.save(str(folder / "Skel-Regular.ufo"), overwrite=True)
    wide.save(str(folder / "Skel-Wide.ufo"), overwrite=True)
    doc = DesignSpaceDocument()
    ax = AxisDescriptor()
    ax.tag, ax.name, ax.minimum, ax.default, ax.maximum = "wdth", "Width", 100, 100, 125
    doc.addAxis(ax)
    for fn, v, style in (("Skel-Regular.ufo", 100, "Regular"), ("Skel-Wide.ufo", 125, "Wide")):
        s = SourceDescriptor()
        s.filename, s.location, s.styleName = fn, {"Width": v}, style
        s.familyName = base.info.familyName
        doc.addSource(s)
    inst = InstanceDescriptor()
    inst.familyName, inst.styleName, inst.location = base.info.familyName, "SemiWide", \
        {"Width": 112.5}
    doc.addInstance(inst)
    path = folder / "Skel.designspace"
    doc.write(str(path))
    return path


def clipper_region_sum(polygons, nib, arc_tol=0.002):
    """region ⊕ elliptical nib by Clipper: the region (closed polygons, nonzero) mapped
    so that the nib is a disk, offset outward with round joins (the sum with a disk
    within ``arc_tol`` font units), mapped back."""
    import pyclipper

    width, height, angle = nib
    m = ellipse_matrix(width, height, angle)
    r = min(width, height) / 2.0 * _CLIP
    to = np.linalg.inv(m) * r
    off = pyclipper.PyclipperOffset()
    off.ArcTolerance = arc_tol * _CLIP
    off.AddPaths([np.round(p @ to.T).astype(np.int64).tolist() for p in polygons],
                 pyclipper.JT_ROUND, pyclipper.ET_CLOSEDPOLYGON)
    return union([np.asarray(p, float) @ np.linalg.inv(to).T for p in off.Execute(r)])
