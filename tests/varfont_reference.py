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
