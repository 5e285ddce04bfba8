"""morph: Minkowski sums of curved planar shapes as exact-normal rational Bézier pieces.

Implements I.-K. Lee, M.-S. Kim, G. Elber, "Polynomial/Rational Approximation of
Minkowski Sum Boundary Curves" (1998).  Shapes are regions: lists of closed loops of
rational Bézier pieces ((n+1, 3) arrays of homogeneous control points), outer loops
counter-clockwise and holes clockwise (y up).
"""

__version__ = "0.1.0"

# the public names below come after __version__, which the CLI imports (E402 on purpose)

from .cspace import cspace_obstacle  # noqa: E402
from .export import loop_to_cubics, piece_to_cubics, piece_to_quadratics  # noqa: E402
from .frames import morph_frames  # noqa: E402
from .minkowski import minkowski_sum  # noqa: E402
from .offset import offset_region  # noqa: E402
from .parse import glyph_region, load_shape, svg_paths, svg_region  # noqa: E402
from .render import write_png, write_svg  # noqa: E402
from .stroke import stroke_paths  # noqa: E402
from .trim import fill_region  # noqa: E402

__all__ = ["cspace_obstacle", "fill_region", "glyph_region", "load_shape", "loop_to_cubics",
           "minkowski_sum", "morph_frames", "offset_region", "piece_to_cubics",
           "piece_to_quadratics", "stroke_paths", "svg_paths", "svg_region", "write_png",
           "write_svg"]
