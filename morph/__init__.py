"""morph: Minkowski sums of curved planar shapes as exact-normal rational Bézier pieces.

Implements I.-K. Lee, M.-S. Kim, G. Elber, "Polynomial/Rational Approximation of
Minkowski Sum Boundary Curves" (1998).  Shapes are regions: lists of closed loops of
rational Bézier pieces ((n+1, 3) arrays of homogeneous control points), outer loops
counter-clockwise and holes clockwise (y up).
"""

__version__ = "0.1.0"

# public names, imported on first use (PEP 562) so that ``import morph`` and the
# command line load only the modules a command needs
_PUBLIC = {
    "cspace_obstacle": "cspace", "loop_to_cubics": "export", "piece_to_cubics": "export",
    "piece_to_quadratics": "export", "morph_frames": "frames", "minkowski_sum": "minkowski",
    "minkowski_sums": "minkowski", "stroke_many": "stroke",
    "offset_region": "offset", "inset_region": "offset", "glyph_region": "parse",
    "load_shape": "parse",
    "svg_paths": "parse", "svg_region": "parse", "write_png": "render", "write_svg": "render",
    "stroke_paths": "stroke", "fill_region": "trim", "loops_to_beziers": "export",
    "ellipse_nib": "nib", "brush_font": "fonts.brush", "stroke_ufo": "fonts.stroke",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name):
    if name in _PUBLIC:
        import importlib

        value = getattr(importlib.import_module("." + _PUBLIC[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError("module 'morph' has no attribute %r" % (name,))


def __dir__():
    return sorted(set(globals()) | set(_PUBLIC))
