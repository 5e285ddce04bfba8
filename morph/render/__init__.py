"""Rendering regions: SVG path data (:mod:`.svg`), anti-aliased PNG, GIF, APNG (:mod:`.png`)
and figures composed of several shapes (:mod:`.figures`).

Both writers take *shapes*: a region (a :class:`morph.region.Region` or a list of loops),
or a list whose items are regions or ``(loops, style)`` pairs.  ``style`` is a dict
with optional keys ``fill``, ``stroke``, ``stroke_width`` (output pixels) and
``opacity`` overriding the writer's defaults.  Several shapes share one frame (the
union of their bounding boxes unless ``bbox=`` fixes it, e.g. across animation
frames).  Regions are y-up; the writers flip to the image's y-down axis.
"""

import numpy as np

from ..region import Region, region_bbox

__all__ = ["frame_bbox", "normalize_shapes", "render_png", "write_png", "frames_to_gif",
           "save_animation", "svg_document", "svg_path_data", "write_svg", "cspace_figure",
           "write_frames", "write_frame_stream", "gif_frame"]


def _is_loop(obj):
    return isinstance(obj, (list, tuple)) and len(obj) > 0 and all(
        isinstance(p, np.ndarray) and p.ndim == 2 for p in obj)


def _is_region(obj):
    if isinstance(obj, Region):
        return True
    return isinstance(obj, (list, tuple)) and len(obj) > 0 and all(_is_loop(l) for l in obj)


def normalize_shapes(shapes):
    """Shapes in any accepted form -> list of (loops, style dict).

    Raises ValueError for anything else (or an empty list).
    """
    if _is_region(shapes):
        shapes = [shapes]
    out = []
    for item in shapes:
        style = {}
        if (isinstance(item, tuple) and len(item) == 2 and isinstance(item[1], dict)):
            item, style = item
        if not _is_region(item):
            raise ValueError("a shape is a region (list of loops of (n+1, 3) arrays) or "
                             "(region, style), got %r" % (type(item),))
        out.append((list(item), dict(style)))
    if not out:
        raise ValueError("nothing to render: no shapes")
    return out


def frame_bbox(shapes, bbox=None, margin=0.05):
    """The drawing frame (xmin, ymin, xmax, ymax), y up.

    ``bbox`` (or the union of the shapes' tight boxes) grown on every side by
    ``margin`` times its larger side.  Zero-size frames get a unit extent.
    """
    if bbox is None:
        boxes = np.array([region_bbox(loops) for loops, _ in normalize_shapes(shapes)])
        bbox = [boxes[:, 0].min(), boxes[:, 1].min(), boxes[:, 2].max(), boxes[:, 3].max()]
    x0, y0, x1, y1 = (float(v) for v in bbox)
    side = max(x1 - x0, y1 - y0)
    if not side > 0:
        side = 1.0
    m = margin * side
    return np.array([x0 - m, y0 - m, x1 + m, y1 + m])


# the writers, imported on first use (PEP 562): an SVG command never loads Pillow
_WRITERS = {"frames_to_gif": "png", "render_png": "png", "save_animation": "png",
            "write_png": "png", "svg_document": "svg", "svg_path_data": "svg",
            "write_svg": "svg", "cspace_figure": "figures", "write_frames": "figures",
            "write_frame_stream": "figures", "gif_frame": "png"}


def __getattr__(name):
    if name in _WRITERS or name in ("png", "svg", "figures"):
        import importlib

        module = importlib.import_module("." + _WRITERS.get(name, name), __name__)
        value = module if name in ("png", "svg", "figures") else getattr(module, name)
        globals()[name] = value
        return value
    raise AttributeError("module 'morph.render' has no attribute %r" % (name,))


def __dir__():
    return sorted(set(globals()) | set(_WRITERS))
