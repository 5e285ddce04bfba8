"""ufo2ft's outline compilers taking the stored outlines of a streamed font
(:func:`morph.fonts.stream.compile_stored`): the glyph programs are the bytes the
workers compiled (:func:`morph.fonts.stream.compile_outline`), the glyphs with
components decomposed here as ufo2ft decomposes them; everything else is ufo2ft's.
Imported only when a font is compiled (ufo2ft is a heavy import)."""

__all__ = ["StoredCFF", "StoredGlyf", "StoredPostProcessor", "parsed_feature_compiler"]

from types import SimpleNamespace

from fontTools.misc.psCharStrings import T2CharString
from fontTools.misc.roundTools import otRound
from fontTools.pens.pointPen import PointToSegmentPen, SegmentToPointPen
from fontTools.pens.recordingPen import RecordingPointPen
from fontTools.pens.transformPen import TransformPointPen
from fontTools.pens.ttGlyphPen import TTGlyphPointPen
from fontTools.ttLib import newTable
from fontTools.ttLib.tables._g_l_y_f import Glyph
from ufo2ft.outlineCompiler import BoundingBox, OutlineOTFCompiler, OutlineTTFCompiler
from ufo2ft.postProcessor import PostProcessor

from .cff_encoding import (_NO_WIDTHS, BoundedCharString, as_bounded, bound_charstrings,
                           bounded_t2_pen, is_bounded, subroutinize, width_prefix)
from .glyf_headers import Expanded, HeaderFont, glyf_boxes


class Stored:
    """The part both flavors share: ``store`` (glyph name -> (data, bounds)) and
    the decomposition of a glyph from the stored outlines, in the order of
    ufo2ft's DecomposeComponentsFilter (fontTools' DecomposingFilterPointPen)."""

    store = {}
    _drawn = None   # glyph name -> its stored contours recorded, while compiling

    def shell(self, name):
        return self.ufo[name] if name in self.ufo else None

    def draw_own(self, name, pen):
        """``name``'s stored contours, decoded once per compilation (a base glyph
        is drawn into every composite using it)."""
        if self._drawn is None:
            self._drawn = {}
        rec = self._drawn.get(name)
        if rec is None:
            rec = self._drawn[name] = RecordingPointPen()
            self.draw_stored(name, rec)
        rec.replay(pen)

    def decomposed(self, name, pen):
        """``name``'s own stored contours, then its components decomposed."""
        self.draw_own(name, pen)
        for c in self.shell(name).components:
            self.nested(c.baseGlyph, TransformPointPen(pen, tuple(c.transformation)))

    def nested(self, name, pen):
        """A component's base as fontTools' decomposing point pen draws it:
        its own contours, then its components, recursively."""
        if self.shell(name) is not None:
            self.decomposed(name, pen)


class StoredCFF(Stored, OutlineOTFCompiler):
    """CFF: a stored charstring gets the advance prepended (the widths ufo2ft chose);
    a glyph with components is decomposed and drawn with ufo2ft's pen."""

    def draw_stored(self, name, pen):
        if name in self.store:
            cs = T2CharString(bytecode=self.store[name][0], private=_NO_WIDTHS,
                              globalSubrs=[])
            cs.draw(SegmentToPointPen(pen))

    #: glyph name -> the bounds of its charstring (every glyph's, as compiled),
    #: shared with :class:`StoredPostProcessor`
    bounds = {}

    def compileGlyphs(self):
        default, nominal = self.getDefaultAndNominalWidths()
        private = SimpleNamespace(defaultWidthX=default, nominalWidthX=nominal)
        out = {}
        for name in self.glyphOrder:
            glyph, shell = self.allGlyphs[name], self.shell(name)
            if shell is not None and shell.components:
                width = None if glyph.width == default else otRound(glyph.width - nominal)
                pen = bounded_t2_pen(width, self.allGlyphs, roundTolerance=self.roundTolerance)
                self.decomposed(name, PointToSegmentPen(pen))
                out[name] = as_bounded(
                    pen.getCharString(private, None, optimize=self.optimizeCFF),
                    pen.bounds.bounds)
            elif name in self.store:
                out[name] = BoundedCharString(
                    bytecode=width_prefix(glyph.width, default, nominal)
                    + self.store[name][0])
                out[name].bounds = self.store[name][1]
            else:
                out[name] = self.getCharStringForGlyph(glyph, private)
        self._drawn = None
        for name, cs in out.items():     # each glyph's bounds computed once
            if not is_bounded(cs):
                as_bounded(cs, cs.calcBounds(out))
            self.bounds[name] = cs.bounds
        return out

    def makeGlyphsBoundingBoxes(self):
        """ufo2ft's rounded boxes, from each charstring's bounds (stored or
        computed for the decomposed and ufo2ft's own)."""
        boxes = {}
        charstrings = self.getCompiledGlyphs()
        for name, cs in charstrings.items():
            box = cs.calcBounds(charstrings)  # ufo2ft's rounding of its bounds
            box = None if box is None else tuple(otRound(v) for v in box)
            box = None if box == (0, 0, 0, 0) else box
            boxes[name] = None if box is None else BoundingBox(*box)
        return boxes


class StoredPostProcessor(PostProcessor):
    """ufo2ft's post-processor; after the subroutinizer has replaced the CFF
    table (every charstring rewritten by ``tx`` from its path), the new
    charstrings answer ``calcBounds`` with their glyphs' bounds as compiled
    (:attr:`StoredCFF.bounds`, the same paths): the saves that follow (the font
    reloaded for production glyph names) set the font box, head and hhea from
    them instead of decompiling and drawing every glyph twice."""

    bounds = {}

    @classmethod
    def _subroutinize_with_cffsubr(cls, otf, cffVersion):
        """cffsubr's subroutinizer given the font without its layout tables
        (:func:`morph.fonts.cff_encoding.subroutinize`)."""
        if "CFF " not in otf or cffVersion != 1:
            return super()._subroutinize_with_cffsubr(otf, cffVersion)
        subroutinize(otf, cls.bounds)

    def process_cff(self, **kwargs):
        super().process_cff(**kwargs)
        bound_charstrings(self.otf, self.bounds)


class StoredGlyf(Stored, OutlineTTFCompiler):
    """TrueType: a stored glyph stays its bytes (a ``Glyph`` not expanded, whose
    bytes the ``glyf`` table writes as they are: the font is saved without
    recomputing the boxes, set here from the stored headers as fontTools would);
    a composite of components only is ufo2ft's; one with contours too is
    decomposed here.  Expanded glyphs cost ~30 bytes a point (coordinate and flag
    arrays) until the font is saved, the bytes ~4."""

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
                ttglyphs[name] = Glyph(self.store[name][0])
        self._drawn = None
        return ttglyphs

    def makeGlyphsBoundingBoxes(self):
        """ufo2ft's boxes: a stored glyph's from its header, the others'
        recomputed (a composite's from its bases, stored ones decoded apart)."""
        return glyf_boxes(self.getCompiledGlyphs(), BoundingBox)

    def setupTable_glyf(self):
        """ufo2ft's glyf table (:meth:`OutlineTTFCompiler.setupTable_glyf`) with the
        stored glyphs kept as bytes: glyph instructions (a source glyph's TrueType
        program or overlap flag) compiled for ufo2ft's glyphs and for a stored
        glyph whose source asks for them (expanded then), maxp from the
        headers."""
        if not {"glyf", "loca"}.issubset(self.tables):
            return
        self.otf["loca"] = newTable("loca")
        self.otf["glyf"] = glyf = newTable("glyf")
        glyf.glyphs = {}
        glyf.glyphOrder = self.glyphOrder
        ttglyphs = self.getCompiledGlyphs()
        depths = self.getMaxComponentDepths()
        for name in sorted(self.glyphOrder, key=lambda n: depths.get(n, 0)):
            g = ttglyphs[name]
            if hasattr(g, "data") and _asks_for_instructions(self.shell(name)):
                g.expand(glyf)
            if not hasattr(g, "data"):
                self.instructionCompiler.compileGlyphInstructions(g, name)
            glyf.glyphs[name] = g
        if "maxp" in self.otf:
            self.otf["maxp"].recalc(HeaderFont(self.otf, Expanded(glyf.glyphs)))


def _asks_for_instructions(shell):
    from ufo2ft.constants import TRUETYPE_INSTRUCTIONS_KEY, TRUETYPE_OVERLAP_KEY

    return shell is not None and (TRUETYPE_INSTRUCTIONS_KEY in shell.lib
                                  or TRUETYPE_OVERLAP_KEY in shell.lib)


def parsed_feature_compiler(font, tree):
    """ufo2ft's feature compiler class for ``font`` whose feature file is the feaLib
    tree ``tree`` (as ufo2ft would parse it, parsed already where its anchors were
    moved): ufo2ft's feature writers complete that tree instead of one parsed again.
    The tables are built as ufo2ft builds them, from the completed tree written out
    and parsed (built from the tree itself, mark classes come out otherwise).  None
    where ufo2ft would not use its feature compiler (MTI feature files)."""
    from ufo2ft.constants import MTI_FEATURES_PREFIX
    from ufo2ft.featureCompiler import (FeatureCompiler, describe_ufo,
                                        warn_about_miscased_insertion_markers)

    if any(fn.startswith(MTI_FEATURES_PREFIX) and fn.endswith(".mti")
           for fn in font.data.fileNames):
        return None

    class ParsedFeatureCompiler(FeatureCompiler):
        def setupFeatures(self):
            """ufo2ft's ``setupFeatures`` on the tree given (the font's own, when an
            include directory is asked for or no writer runs)."""
            if self.feaIncludeDir is not None or not self.featureWriters:
                return super().setupFeatures()
            if any(writer.mode == "skip" for writer in self.featureWriters):
                markers = {writer.insertFeatureMarker for writer in self.featureWriters
                           if writer.insertFeatureMarker is not None}
                warn_about_miscased_insertion_markers(describe_ufo(self.ufo), tree, markers)
            for writer in self.featureWriters:
                writer.write(self.ufo, tree, compiler=self)
            self.features = tree.asFea()

    return ParsedFeatureCompiler
