"""The loaded-shape type every reader returns: a region and where it came from."""

import re
from dataclasses import dataclass, field

__all__ = ["Shape"]


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
        SVG (as it is), in the shape's own units."""
        return value * self.units_per_em if self.units_per_em else value
