"""morph: Minkowski sums of curved planar shapes as exact-normal rational Bézier pieces.

Implements I.-K. Lee, M.-S. Kim, G. Elber, "Polynomial/Rational Approximation of
Minkowski Sum Boundary Curves" (1998).  Shapes are regions: sequences of closed loops
of rational Bézier pieces ((n+1, 3) arrays of homogeneous control points), outer loops
counter-clockwise and holes clockwise (y up).  Results are :class:`Region` objects
(immutable; ``validated``, and ``bound``: the error achieved); ``morph.budget``
splits a tolerance between the stages, ``morph.errors`` holds the exceptions.
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
    "Region": "region", "Shape": "parse", "MorphError": "errors", "OperandError": "errors",
}
#: submodules reachable as attributes after a plain ``import morph``
_MODULES = ("budget", "errors")

__all__ = sorted(_PUBLIC) + list(_MODULES)


def __getattr__(name):
    import importlib

    if name in _PUBLIC:
        value = getattr(importlib.import_module("." + _PUBLIC[name], __name__), name)
    elif name in _MODULES:
        value = importlib.import_module("." + name, __name__)
    else:
        raise AttributeError("module 'morph' has no attribute %r" % (name,))
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_PUBLIC) | set(_MODULES))
