"""Streaming font building for ``morph stroke``: memory that does not grow with the
outlines of the font.

A stroked glyph leaves its worker process as *compiled* data, not as point objects:
:func:`compile_outline` turns its integer contours (:mod:`morph.fonts.tables`) into
the bytes the font will hold, a Type 2 charstring (CFF, without its advance) or a
``glyf`` glyph (TrueType direction), with its bounding box.  The main process keeps
those bytes (a few bytes a point) and the glyph's *shell*: a ufoLib2 glyph without
contours (advance, unicodes, anchors, kept components, lib).  At the end ufo2ft
compiles the shells, as it compiled the whole font before, with an outline compiler
that takes the stored bytes (:func:`compile_stored`): the names, metrics, cmap, OS/2,
kerning and mark features, GDEF and post tables come from ufo2ft as they did; the
glyph programs are the bytes ufo2ft would have made from the same contours, because
they are made by the same pens in the same order:

- CFF: ``T2CharStringPen`` fed through the point round trip of a ufoLib2 glyph
  (``SegmentToPointPen`` -> ``PointToSegmentPen``), specialized (ufo2ft's
  ``optimizeCFF``); the advance is prepended when the font's nominal and default
  widths are known (:func:`width_prefix`, what the pen does);
- TrueType: ``TTGlyphPointPen`` behind ``Cu2QuPointPen`` reversing the direction,
  as ufo2ft's cubic-to-quadratic filter (the contours are quadratic already).

Composites: a TrueType glyph of components only stays a composite (ufo2ft draws its
shell); a glyph with components and contours, and every CFF glyph with components,
is decomposed here as ufo2ft's ``DecomposeComponentsFilter`` does it (the glyph's
own contours, then each component's nested components and then its contours,
transformed), from the stored outlines.

The source is read the same way (:class:`SkeletonSource`): one pass over the glyphs
for their shells, then each glyph's contours read again when its chunk is prepared,
and dropped.  A UFO output is written glyph by glyph (:class:`UfoGlyphWriter`): the
shells are saved first by ufoLib2 (info, kerning, groups, features, lib, layers,
data), then each stroked glyph's ``.glif`` is rewritten as it arrives.
"""

import copy
from types import SimpleNamespace

from .tables import draw_contours

__all__ = ["compile_outline", "width_prefix", "SkeletonSource", "compile_stored",
           "UfoGlyphWriter", "shell_glyph"]


# =========================================================================== worker side

#: the private dict a charstring without an advance is drawn with
_NO_WIDTHS = SimpleNamespace(defaultWidthX=0, nominalWidthX=0)


def compile_outline(contours, flavor):
    """``(data, bounds)`` of integer contours (:func:`morph.fonts.tables.contours_from_loops`)
    compiled as ufo2ft compiles them from a UFO glyph holding those contours.

    ``flavor``: ``"cff"`` (cubic contours; ``data`` the Type 2 charstring's bytes
    without the advance, see :func:`width_prefix`) or ``"glyf"`` (quadratic splines
    in the UFO's direction; ``data`` the compiled ``glyf`` glyph, reversed).
    ``bounds``: (xMin, yMin, xMax, yMax) as ufo2ft rounds them, None when empty.
    """
    from fontTools.pens.pointPen import PointToSegmentPen, SegmentToPointPen

    if flavor == "cff":
        from fontTools.misc.roundTools import otRound
        from fontTools.pens.t2CharStringPen import T2CharStringPen

        pen = T2CharStringPen(None, None, roundTolerance=0.5)
        draw_contours(SegmentToPointPen(PointToSegmentPen(pen)), contours, False)
        cs = pen.getCharString(_NO_WIDTHS, optimize=True)
        box = cs.calcBounds(None)
        box = None if box is None else tuple(otRound(v) for v in box)
        cs.compile()
        return bytes(cs.bytecode), (None if box == (0, 0, 0, 0) else box)
    from fontTools.misc.roundTools import otRound
    from fontTools.pens.cu2quPen import Cu2QuPointPen as _Cu2Qu
    from fontTools.pens.ttGlyphPen import TTGlyphPointPen

    pen = TTGlyphPointPen(None)
    draw_contours(SegmentToPointPen(_Cu2Qu(pen, 1.0, reverse_direction=True,
                                           all_quadratic=True)), contours, True)
    g = pen.glyph(dropImpliedOnCurves=False, round=otRound)
    if not g.numberOfContours:
        return b"", None
    g.recalcBounds(None)
    box = (g.xMin, g.yMin, g.xMax, g.yMax)
    return g.compile(None), (None if box == (0, 0, 0, 0) else box)


def width_prefix(width, default, nominal):
    """The bytes a Type 2 charstring starts with for an advance ``width`` (nothing for
    the font's ``default`` width; else ``width - nominal``), as ``T2CharStringPen``
    writes it."""
    from fontTools.misc.psCharStrings import encodeIntT2
    from fontTools.misc.roundTools import otRound

    if width == default:
        return b""
    return encodeIntT2(otRound(width - nominal))


# =========================================================================== source

def shell_glyph(glyph):
    """A ufoLib2 glyph like ``glyph`` without its contours (advance, unicodes,
    anchors, guidelines, components, image, note, lib: copies)."""
    from ufoLib2.objects import Glyph

    return Glyph(glyph.name, width=glyph.width, height=glyph.height,
                 unicodes=list(glyph.unicodes), image=copy.deepcopy(glyph.image),
                 lib=copy.deepcopy(glyph.lib), note=glyph.note,
                 anchors=copy.deepcopy(glyph.anchors),
                 components=copy.deepcopy(glyph.components),
                 guidelines=copy.deepcopy(glyph.guidelines))


class _ShellPen:
    """A point pen that keeps a glyph's components and counts its contours."""

    def __init__(self, glyph):
        self.inner = glyph.getPointPen()
        self.contours = 0

    def beginPath(self, identifier=None, **kwargs):
        self.contours += 1

    def addPoint(self, *args, **kwargs):
        pass

    def endPath(self):
        pass

    def addComponent(self, base, transformation, identifier=None, **kwargs):
        self.inner.addComponent(base, transformation, identifier=identifier, **kwargs)


class SkeletonSource:
    """The glyphs of a skeleton UFO, read when asked and not kept.

    ``src``: a ``.ufo`` path (read with fontTools.ufoLib, glyph by glyph) or an open
    ``ufoLib2.Font`` (not modified).  ``source[name]`` is a fresh ufoLib2 glyph with
    its contours (from the open font: the font's own glyph); ``name in source``.
    :meth:`shell_font` is the font to write: the source's font data and layers with
    every default-layer glyph a shell (:func:`shell_glyph`), and ``contour_counts``
    how many contours each source glyph had.

    Raises:
        ParseError: a UFO that cannot be read, a glyph that does not parse.
    """

    def __init__(self, src):
        import ufoLib2

        from ..parse.ufo import load_ufo

        self.open_font = src if isinstance(src, ufoLib2.Font) else None
        self.font = self.open_font or load_ufo(src, lazy=True)
        self.path = None if self.open_font is not None else str(src)
        self._glyph_set = None
        if self.path is not None:
            from fontTools.ufoLib import UFOReader

            reader = UFOReader(self.path, validate=False)
            self._glyph_set = reader.getGlyphSet(self.font.layers.defaultLayer.name,
                                                 validateRead=False)
        self._names = set(self.font.keys())
        self.contour_counts = {}

    def keys(self):
        return list(self.font.keys())

    def __contains__(self, name):
        return name in self._names

    def __getitem__(self, name):
        if self.open_font is not None:
            return self.open_font[name]
        return self._read(name, None)[0]

    def _read(self, name, pen_of):
        from ufoLib2.objects import Glyph

        from ..errors import ParseError, one_line

        glyph = Glyph(name)
        pen = pen_of(glyph) if pen_of else glyph.getPointPen()
        try:
            self._glyph_set.readGlyph(name, glyph, pen, validate=False)
        except Exception as exc:  # glifLib raises several types for a bad .glif
            raise ParseError("cannot read glyph %r of %s: %s" % (name, self.path,
                                                                  one_line(exc)),
                             name) from exc
        return glyph, pen

    def shell_font(self):
        """The font to write (see the class docstring); read once, glyph by glyph."""
        import ufoLib2

        src = self.font
        if self.open_font is not None:
            from ufoLib2.objects import Layer, LayerSet

            src.unlazify()
            default = Layer(src.layers.defaultLayer.name)
            for g in src:
                default.insertGlyph(shell_glyph(g), copy=False)
                self.contour_counts[g.name] = len(g.contours)
            layers = [default if layer is src.layers.defaultLayer else copy.deepcopy(layer)
                      for layer in src.layers]
            return ufoLib2.Font(layers=LayerSet.from_iterable(layers, default.name),
                                info=copy.deepcopy(src.info),
                                features=copy.deepcopy(src.features),
                                groups=copy.deepcopy(src.groups),
                                kerning=copy.deepcopy(src.kerning),
                                lib=copy.deepcopy(src.lib), data=copy.deepcopy(src.data),
                                images=copy.deepcopy(src.images))
        font = src
        default = font.layers.defaultLayer
        for name in list(default.keys()):
            shell, pen = self._read(name, _ShellPen)
            default.insertGlyph(shell, overwrite=True, copy=False)
            self.contour_counts[name] = pen.contours
        return font


# =========================================================================== compiled font

def _stored_compilers():
    """ufo2ft's outline compilers, taking stored outlines (built lazily: ufo2ft is
    imported only when a font is compiled)."""
    from fontTools.misc.psCharStrings import T2CharString
    from fontTools.misc.roundTools import otRound
    from fontTools.pens.pointPen import PointToSegmentPen, SegmentToPointPen
    from fontTools.pens.recordingPen import RecordingPointPen
    from fontTools.pens.t2CharStringPen import T2CharStringPen
    from fontTools.pens.transformPen import TransformPointPen
    from fontTools.pens.ttGlyphPen import TTGlyphPointPen
    from fontTools.misc.transform import Identity
    from fontTools.ttLib.tables._g_l_y_f import Glyph
    from ufo2ft.outlineCompiler import OutlineOTFCompiler, OutlineTTFCompiler

    class Stored:
        """The part both flavors share: ``store`` (glyph name -> (data, bounds)) and
        the decomposition of a glyph from the stored outlines, in the order of
        ufo2ft's DecomposeComponentsFilter."""

        store = {}

        def shell(self, name):
            return self.ufo[name] if name in self.ufo else None

        def decomposed(self, name, pen):
            """``name``'s own stored contours, then its components decomposed."""
            self.draw_stored(name, pen)
            for c in self.shell(name).components:
                self.nested(c.baseGlyph, TransformPointPen(pen, tuple(c.transformation)))

        def nested(self, name, pen):
            shell = self.shell(name)
            if shell is None:
                return
            for c in shell.components:
                self.nested(c.baseGlyph, TransformPointPen(pen, tuple(c.transformation)))
            self.draw_stored(name, pen)

    class StoredCFF(Stored, OutlineOTFCompiler):
        def draw_stored(self, name, pen):
            if name in self.store:
                cs = T2CharString(bytecode=self.store[name][0], private=_NO_WIDTHS,
                                  globalSubrs=[])
                cs.draw(SegmentToPointPen(pen))

        def compileGlyphs(self):
            default, nominal = self.getDefaultAndNominalWidths()
            private = SimpleNamespace(defaultWidthX=default, nominalWidthX=nominal)
            out = {}
            for name in self.glyphOrder:
                glyph, shell = self.allGlyphs[name], self.shell(name)
                if shell is not None and shell.components:
                    rec = RecordingPointPen()
                    self.decomposed(name, rec)
                    width = None if glyph.width == default else otRound(glyph.width - nominal)
                    pen = T2CharStringPen(width, self.allGlyphs,
                                          roundTolerance=self.roundTolerance)
                    rec.replay(PointToSegmentPen(pen))
                    out[name] = pen.getCharString(private, None, optimize=self.optimizeCFF)
                elif name in self.store:
                    out[name] = T2CharString(
                        bytecode=width_prefix(glyph.width, default, nominal)
                        + self.store[name][0])
                else:
                    out[name] = self.getCharStringForGlyph(glyph, private)
            return out

        def makeGlyphsBoundingBoxes(self):
            from ufo2ft.outlineCompiler import BoundingBox

            boxes = {}
            charstrings = self.getCompiledGlyphs()
            for name, cs in charstrings.items():
                shell = self.shell(name)
                if name in self.store and not (shell is not None and shell.components):
                    box = self.store[name][1]
                else:
                    box = cs.calcBounds(charstrings)
                    box = None if box is None else tuple(otRound(v) for v in box)
                    box = None if box == (0, 0, 0, 0) else box
                boxes[name] = None if box is None else BoundingBox(*box)
            return boxes

    class StoredGlyf(Stored, OutlineTTFCompiler):
        def draw_stored(self, name, pen):
            if name in self.store and self.store[name][0]:
                g = Glyph(self.store[name][0])
                g.expand(None)
                g.drawPoints(pen, None)

        def compileGlyphs(self):
            ttglyphs = super().compileGlyphs()  # shells: components, empty glyphs
            for name in self.glyphOrder:
                shell = self.shell(name)
                if not self.store.get(name, (b"",))[0]:  # no contours: ufo2ft's own
                    continue
                if shell is not None and shell.components:  # mixed: decomposed
                    pen = TTGlyphPointPen(self.allGlyphs)
                    self.decomposed(name, pen)
                    ttglyphs[name] = pen.glyph(dropImpliedOnCurves=self.dropImpliedOnCurves,
                                               round=otRound)
                else:
                    g = Glyph(self.store[name][0])
                    g.expand(None)
                    ttglyphs[name] = g
            return ttglyphs

    del Identity
    return StoredCFF, StoredGlyf


def compile_stored(font, store, kind, **options):
    """The ``TTFont`` ufo2ft compiles from ``font`` (shells, see the module docstring)
    with the stored outlines ``store`` (glyph name -> :func:`compile_outline`'s
    ``(data, bounds)``, of the flavor of ``kind``: ``.otf`` CFF, ``.ttf`` glyf);
    ``options`` go to ufo2ft's ``compileOTF`` / ``compileTTF``."""
    import ufo2ft

    cff, glyf = _stored_compilers()
    base = cff if kind == ".otf" else glyf
    compiler = type(base.__name__, (base,), {"store": store})
    if kind == ".otf":
        return ufo2ft.compileOTF(font, outlineCompilerClass=compiler, **options)
    return ufo2ft.compileTTF(font, outlineCompilerClass=compiler, **options)


# =========================================================================== UFO output

class UfoGlyphWriter:
    """A UFO written glyph by glyph: ``font`` (the shells, every glyph's final
    advance, anchors and components) is saved to ``path`` by ufoLib2 at once; then
    :meth:`write` rewrites one glyph's ``.glif`` with its contours, which are not
    kept; :meth:`finish` writes the font info again (changed since)."""

    def __init__(self, font, path):
        from fontTools.ufoLib import UFOWriter

        font.save(str(path), overwrite=True)
        self.font = font
        self.writer = UFOWriter(str(path), validate=False)
        self.glyph_set = self.writer.getGlyphSet(validateWrite=False)

    def write(self, name, contours):
        """Glyph ``name``'s shell with integer cubic ``contours`` drawn in, as ufoLib2
        writes a glyph (contours, then components)."""
        g = self.font[name]
        draw_contours(g.getPen(), contours, False)
        try:
            self.glyph_set.writeGlyph(name, glyphObject=g, drawPointsFunc=g.drawPoints)
        finally:
            g.clearContours()

    def finish(self):
        self.writer.writeInfo(self.font.info)
