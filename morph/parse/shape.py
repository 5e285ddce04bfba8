"""The loaded-shape type every reader returns: a region and where it came from."""

import re
from dataclasses import dataclass, field

__all__ = ["Shape", "DEFAULT_RELATIVE_TOL", "em_to_units"]

#: the default tolerance of a shape, relative to its size: 1e-4 em for a glyph,
#: 1e-4 of the drawing's size for SVG (:meth:`Shape.tolerance`)
DEFAULT_RELATIVE_TOL = 1e-4


def em_to_units(value, units_per_em):
    """A length (a tolerance, a radius) in em as a length in font units: ``value``
    times ``units_per_em``; as it is when ``units_per_em`` is None (SVG user units).

    The library's ``tol`` is in the shapes' own units (font units for a glyph), the
    command line's ``--tol`` in em for glyphs: ``minkowski_sum(glyph.region, nib,
    em_to_units(1e-4, glyph.units_per_em))`` sums within 1e-4 em, as ``morph sum
    --tol 1e-4`` does (0.1 unit at 1000 units per em).
    """
    return value * units_per_em if units_per_em else value


@dataclass(frozen=True)
class Shape:
    """A shape read from a font or an SVG source, y up.

    ``region``: oriented loops (outer counter-clockwise, holes clockwise) in the
    source's units: font units for a glyph, user units for SVG.  ``name``: the glyph
    name, or the SVG file's stem (``"path"`` for path data, ``"svg"`` for a document
    string).  ``source``: what was asked for (the character or glyph name, the file
    path, the document or path data).  ``units_per_em``: the font's, None for SVG.
    ``advance_width`` and ``lsb``: the glyph's ``hmtx`` metrics; for SVG the width
    and the left edge of the region's bounding box.
    """

    region: list = field(repr=False)
    name: str
    source: str
    units_per_em: int = None
    advance_width: float = 0.0
    lsb: float = 0.0

    @property
    def kind(self):
        """"glyph" (read from a font) or "svg"."""
        return "glyph" if self.units_per_em else "svg"

    @property
    def slug(self):
        """File-name-safe name (glyph name or SVG file stem)."""
        return re.sub(r"[^A-Za-z0-9._-]+", "_", self.name) or "shape"

    def em_to_units(self, value):
        """A length given in em for a glyph (times units per em) or in user units for
        SVG (as it is), in the shape's own units.  The library's ``tol`` is in the
        shapes' own units, the command line's ``--tol`` in em for glyphs: this is the
        conversion (``morph sum g o --tol 1e-4`` sums at ``glyph.em_to_units(1e-4)``,
        0.1 unit at 1000 units per em)."""
        return em_to_units(value, self.units_per_em)

    def size(self, *others):
        """The larger side of the bounding box of this shape's region and of
        ``others`` (regions), in the shape's units: the drawing's size."""
        from ..region import region_bbox

        sides = [0.0]
        for loops in (self.region,) + others:
            if loops:
                x0, y0, x1, y1 = region_bbox(loops)
                sides.append(max(x1 - x0, y1 - y0))
        return float(max(sides))

    def tolerance(self, tol=None, *others, relative=DEFAULT_RELATIVE_TOL):
        """A tolerance in the shape's units.

        ``tol`` given: absolute, in em for a glyph (:meth:`em_to_units`), in user
        units for SVG.  ``tol`` None, the default: ``relative`` (1e-4) of a size, em
        for a glyph (1e-4 em = 0.1 unit at 1000 units per em), the drawing's
        :meth:`size` with ``others`` (regions combined with it) for SVG, so that a
        drawing is computed as finely as a glyph whatever its units.
        """
        if tol is not None:
            return self.em_to_units(tol)
        if self.units_per_em:
            return relative * self.units_per_em
        return relative * (self.size(*others) or 1.0)
