"""Figures composed of several shapes: C-space pictures, frame sequences.

These build *shapes* lists (see :mod:`morph.render`) or write several files; the
commands (:mod:`morph.cli`) and the gallery call them.
"""

import re
from pathlib import Path

import numpy as np

from .. import piece as pc
from .. import moments as mo
from .. import polyline as pl
from . import frame_bbox

__all__ = ["cspace_figure", "write_frame_stream", "write_frames", "FRAME_FILE",
           "frame_file_names", "stale_frame_files"]

CSPACE_STYLE = {"fill": "#f2c894", "stroke": "#b3541e", "stroke_width": 1.5}
OBSTACLE_STYLE = {"fill": "#404040"}
ROBOT_STYLE = {"fill": None, "stroke": "#1f5fa8", "stroke_width": 1.2}


def _boundary_points(loop, tol, count):
    """``count`` points spread evenly by arc length along a loop (on its polyline
    within ``tol``, interpolated along its segments), starting at the loop's start."""
    poly = pl.flatten_loop(loop, tol)
    closed = np.vstack([poly, poly[:1]])
    seg = np.hypot(*np.diff(closed, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    at = np.arange(count) * cum[-1] / count
    idx = np.clip(np.searchsorted(cum, at, side="right") - 1, 0, len(poly) - 1)
    u = (at - cum[idx]) / np.where(seg[idx] > 0, seg[idx], 1.0)
    return closed[idx] + u[:, None] * (closed[idx + 1] - closed[idx])


def cspace_figure(obstacle, robot, cspace, tol, samples=8, reference=(0.0, 0.0),
                  inside=False):
    """Shapes of a C-space picture (paper Figs. 4, 38): the C-space region (light),
    the obstacle (dark), the robot's outline placed with its reference point at
    ``samples`` points spread along the C-space boundary's largest loop (touching
    the obstacle there), and a dot at each of those points.  ``tol``: flattening of
    that loop, in the shapes' units.  ``inside``: the obstacle is a container and
    ``cspace`` its free space (:func:`morph.cspace.free_space`), drawn on top of it."""
    from ..cspace import place_robot

    shapes = [(cspace, dict(CSPACE_STYLE)), (obstacle, dict(OBSTACLE_STYLE))]
    if inside:
        shapes.reverse()
    if not cspace or samples <= 0:
        return shapes
    outer = max(cspace, key=lambda loop: abs(mo.loop_area(loop)))
    box = frame_bbox([cspace], margin=0.0)
    dot = 0.012 * max(box[2] - box[0], box[3] - box[1])
    for p in _boundary_points(outer, tol, samples):
        shapes.append((place_robot(robot, p, reference), dict(ROBOT_STYLE)))
        shapes.append(([pc.circle(p, dot)], {"fill": ROBOT_STYLE["stroke"]}))
    return shapes


def write_frames(folder, regions, size=512, tol=None, duration=120, animation="gif"):
    """Write a frame sequence into ``folder``: ``frame-000.svg``/``.png`` ... (one
    frame box for all, so the shapes stay in place) and the animation ``morph.gif``
    (``animation="apng"``: ``morph.apng``, full colour) with ``duration`` ms per
    frame.  ``tol``: the SVG export's tolerance (region units), one for all frames
    or a sequence of one per frame.  Returns the folder."""
    regions = list(regions)
    tols = list(tol) if hasattr(tol, "__len__") else [tol] * len(regions)
    if len(tols) != len(regions):
        raise ValueError("%d tolerances for %d frames" % (len(tols), len(regions)))
    bbox = frame_bbox([r for r in regions if r], margin=0.0)
    return write_frame_stream(folder, zip(regions, tols), bbox, size, duration, animation)


#: the names of the files :func:`write_frame_stream` writes: frame-000.svg/.png ...
#: and morph.gif or morph.apng
FRAME_FILE = re.compile(r"frame-[0-9]{3,}\.(svg|png)|morph\.(gif|apng)")


def frame_file_names(count, animation="gif"):
    """The names of the files a sequence of ``count`` frames is written as."""
    return {"frame-%03d.%s" % (k, ext) for k in range(count) for ext in ("svg", "png")} | \
        {"morph." + animation}


def stale_frame_files(folder, count, animation="gif"):
    """The files in ``folder`` named as :func:`write_frame_stream` names its files
    (:data:`FRAME_FILE`) that a sequence of ``count`` frames does not write: what an
    earlier, longer run (or one with the other animation) left behind."""
    keep = frame_file_names(count, animation)
    return sorted(p for p in Path(folder).iterdir()
                  if p.is_file() and FRAME_FILE.fullmatch(p.name) and p.name not in keep)


#: :func:`write_frame_stream` converts the SVG curves of this many frames at a time
#: in one batch (:func:`morph.render.svg.fitted_regions`), and holds at most as many
#: regions besides the animation's images
FRAME_BATCH = 16


def write_frame_stream(folder, frames, bbox, size=512, duration=120, animation="gif"):
    """:func:`write_frames` of (region, tol) pairs from any iterable (e.g. from
    :func:`morph.frames.iter_frames`, in the box of :func:`morph.frames.frames_bbox`),
    written in groups of :data:`FRAME_BATCH` frames as they arrive, each group's
    SVG curves fitted in one batch: a long sequence is on disk as far as it got
    (a sequence that raises has the frames before it written first), and only the
    animation's frames stay in memory (palette images for a GIF) besides one
    group's regions.  Returns the folder."""
    folder = Path(folder)
    images = []
    frames, group = iter(frames), []
    while True:
        try:
            group.append(next(frames))
        except StopIteration:
            break
        except BaseException:
            _write_group(folder, len(images), group, bbox, size, animation)
            raise
        if len(group) == FRAME_BATCH:
            images += _write_group(folder, len(images), group, bbox, size, animation)
            group = []
    images += _write_group(folder, len(images), group, bbox, size, animation)
    from .png import save_animation

    save_animation(images, str(folder / ("morph." + animation)), duration=duration)
    return folder


def _write_group(folder, first, group, bbox, size, animation):
    """Write frames ``first``, ... of (region, tol) pairs ``group`` (their curves
    fitted in one batch, their images drawn in one batch); returns their animation
    images.  A frame's PNG is its
    palette image (:func:`morph.render.png.render_palettes`: one fill on a white
    background has supersample**2 + 1 colours, a byte a pixel), which is also its
    GIF frame; an APNG frame is its RGB image, the same pixels."""
    from .png import render_palettes
    from .svg import document_tol, fitted_regions, write_svg

    tols = [document_tol([region], t, bbox=bbox) for region, t in group]
    regions = [r for r, _ in group]
    images = []
    for k, (t, fitted, image) in enumerate(
            zip(tols, fitted_regions(regions, tols),
                render_palettes(regions, size=size, bbox=bbox) if group else []), first):
        stem = folder / ("frame-%03d" % k)
        write_svg(str(stem) + ".svg", [fitted], bbox=bbox, size=size, tol=t)
        image.save(str(stem) + ".png")
        images.append(image if animation == "gif" else image.convert("RGB"))
    return images
