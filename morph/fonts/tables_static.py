"""The tables of a static font compiled from a UFO without ufo2ft: the tables
ufo2ft's ``compileOTF`` / ``compileTTF`` write through
:func:`morph.fonts.stream.compile_stored`, for the fonts read by
:mod:`morph.parse.light_ufo` that need nothing else of ufo2ft
(:func:`left_to_ufo2ft`): a CFF font, or a TrueType font whose components
:mod:`morph.fonts.glyf_static` writes as ufo2ft does, whose feature file ufo2ft's
feature writers would leave as it is (:mod:`morph.fonts.writers_static`) or
complete with a kern feature that :mod:`morph.fonts.kern_static` writes, and mark
and mkmk features that :mod:`morph.fonts.mark_static` writes, as they do.  The
others are compiled by ufo2ft from the ufoLib2 font of the same shells (:func:`compile_static`).

ufo2ft's import costs a fifth of a second (its ``__init__`` loads its variable-font
compilers and fontTools.varLib; ufoLib2 comes with it), more than the strokes of a
hundred-glyph font.  What it does for such a font is table building from the font
info with fallbacks, and that is done here with fontTools' tables, in ufo2ft's order
and with its arithmetic (ufo2ft 3's ``outlineCompiler``, ``fontInfoData``,
``instructionCompiler``, ``postProcessor``; MIT licence):

- :func:`morph.fonts.fontinfo.info_value` is ufo2ft's ``getAttrWithFallback`` (the same fallbacks);
- head, hmtx, hhea, name, maxp, cmap, OS/2, post, then CFF or glyf / loca (and gasp
  from the info); the glyph programs are the stored bytes of
  :func:`morph.fonts.stream.compile_outlines`, the other glyphs (the ``.notdef``
  ufo2ft adds, empty glyphs) drawn as ufo2ft's pens draw them;
- the CFF table is subroutinized by cffsubr's ``tx`` as ufo2ft has it done; the
  table ``tx`` reads is written here and its output kept as ``tx`` wrote it
  (:meth:`_Compiler._cff`), the boxes fontTools would recompute from it before
  ``tx`` set as it sets them; the table goes from the stored outlines to a
  temporary file, to ``tx`` and from ``tx``'s output file to the font's file
  (:func:`morph.fonts.stream.save_font`), never whole in memory;
- the name table is written here where all its records are Windows Unicode ones;
- composites are decomposed into CFF charstrings as ufo2ft's compiler of the
  stored outlines decomposes them (:class:`morph.fonts.static_glyphs._Decomposer`);
  glyphs the lib names in ``public.skipExportGlyphs`` are drawn into the glyphs that
  use them and left out;
  ``public.postscriptNames`` rename the glyphs in the CFF charset or the post table
  as ufo2ft's post-processor does (:func:`production_names`);
- the feature file is parsed, completed with the kern, mark and mkmk features
  where ufo2ft's writers would write them, and built by feaLib from that tree,
  which is the one ufo2ft builds from (it writes the tree out and parses it
  again) where the glyph names the two parses know do not change it
  (:meth:`_Compiler._same_parse`; else written out and parsed as ufo2ft does).

So for such a font without composites (whose CFF programs fontTools' charstring pen
specializes) and layout features, neither fontTools.cffLib nor fontTools'
OpenType layout table classes (which its name table module loads) are imported:
another tenth of a second.  Every table is byte for byte ufo2ft's but the CFF table, which equals
ufo2ft's as decompiled (ttx): ufo2ft's is fontTools' re-encoding of the same
``tx`` output.  tests/fonts/test_tables_static.py and test_tables_features.py
compile fonts both ways and compare them so.
"""

import math
import os
from functools import partial
import struct

from .cff_encoding import (NOT_FOR_TX, BoundedCharString, _CffDictWriter, _index,
                           _index_head, optimize_widths, subroutinize, width_prefix)
from .fontinfo import (_date_now, _int_list_to_num, _ot_round, _time_value, full_name,
                       info_value, normalize_for_postscript)
from .glyf_headers import Box, Expanded, HeaderFont, glyf_boxes
from .static_glyphs import _ENDCHAR, _Decomposer, _Notdef, _Programs

__all__ = ["compile_static", "left_to_ufo2ft"]

# =========================================================================== compile

def _tx_runner():
    """A function running cffsubr's ``tx`` on a font file as cffsubr's
    ``_tx_subroutinize`` runs it on a font's bytes (path -> the CFF table's bytes),
    None where this cffsubr has no ``tx`` runner (:func:`morph.fonts.subrs.tx_runner`:
    the executable found without importing cffsubr)."""
    from .subrs import tx_runner

    run = tx_runner()
    return None if run is None else partial(_run_tx, run)


def _run_tx(run, path):
    """``tx`` (``run``: cffsubr's runner) on the font file ``path`` with cffsubr's
    arguments, its output written to a file (cffsubr's way on Windows) not a pipe:
    the subroutinized CFF table, a :func:`morph.fonts.stream.file_table` of an unnamed
    temporary file.  A failure raises cffsubr's error with ``tx``'s message."""
    import subprocess
    import tempfile

    from .stream import file_table

    out = tempfile.NamedTemporaryFile(prefix="tx-", delete=False)
    out.close()
    try:
        run("-cff", "+S", "+b", "-o", out.name, str(path), check=True,
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        table = file_table("CFF ", open(out.name, "rb"))
    except subprocess.CalledProcessError as exc:
        import cffsubr

        raise cffsubr.Error(exc.stderr.decode(errors="replace")) from exc
    finally:
        os.remove(out.name)      # the open table's file stays readable until it closes
    return table


def _font_file(font):
    """``font``'s tables written to a new temporary file (table by table, no copy of
    the font in memory: :func:`morph.fonts.stream.write_tables`); its path (the caller
    removes it)."""
    import tempfile

    from .stream import write_tables

    with tempfile.NamedTemporaryFile(prefix="tx-", delete=False) as f:
        write_tables(font, f)
    return f.name


def _raw_font_class():
    """fontTools' ``TTFont`` that saves a table held as raw bytes (a
    ``DefaultTable``, here the CFF table ``tx`` wrote) as it is, without importing
    the table's class for its dependencies (``TTFont._writeTable``; for the CFF
    table that is fontTools.cffLib): no table depends on the CFF table when the
    boxes are not recomputed.  Where fontTools has no such method the font saves
    as any other (importing the class)."""
    global _RAW_FONT
    if _RAW_FONT is None:
        from fontTools.ttLib import TTFont
        from fontTools.ttLib.tables.DefaultTable import DefaultTable

        class RawTablesFont(TTFont):
            written_cmap = None   # set by compile_static

            def _writeTable(self, tag, writer, done, *args, **kwargs):
                table = self.tables.get(tag)
                if type(table) is DefaultTable and tag not in done and not self.recalcBBoxes:
                    done.append(tag)
                    writer[tag] = table.data
                    return None
                return super()._writeTable(tag, writer, done, *args, **kwargs)

        _RAW_FONT = RawTablesFont
    return _RAW_FONT


_RAW_FONT = None


def _os2_script_metrics(os2, info):
    """OS/2's sub- and superscript sizes and offsets and strikeout, with ufo2ft's
    fallbacks (offsets slanted by the italic angle)."""
    upm = info_value(info, "unitsPerEm")
    angle = float(info_value(info, "italicAngle"))
    x_height = info_value(info, "xHeight")

    def shift(offset):
        return offset * math.tan(math.radians(-angle)) if angle else 0

    def value(attr, default):
        v = info_value(info, attr)
        return _ot_round(default() if v is None else v)

    os2.ySubscriptXSize = value("openTypeOS2SubscriptXSize", lambda: upm * 0.65)
    os2.ySubscriptYSize = value("openTypeOS2SubscriptYSize", lambda: upm * 0.6)
    os2.ySubscriptYOffset = value("openTypeOS2SubscriptYOffset", lambda: upm * 0.075)
    os2.ySubscriptXOffset = value("openTypeOS2SubscriptXOffset",
                                  lambda: shift(-os2.ySubscriptYOffset))
    os2.ySuperscriptXSize = value("openTypeOS2SuperscriptXSize",
                                  lambda: os2.ySubscriptXSize)
    os2.ySuperscriptYSize = value("openTypeOS2SuperscriptYSize",
                                  lambda: os2.ySubscriptYSize)
    os2.ySuperscriptYOffset = value("openTypeOS2SuperscriptYOffset", lambda: upm * 0.35)
    os2.ySuperscriptXOffset = value("openTypeOS2SuperscriptXOffset",
                                    lambda: shift(os2.ySuperscriptYOffset))
    os2.yStrikeoutSize = value("openTypeOS2StrikeoutSize",
                               lambda: info_value(info, "postscriptUnderlineThickness"))
    os2.yStrikeoutPosition = value("openTypeOS2StrikeoutPosition",
                                   lambda: x_height * 0.6 if x_height else upm * 0.22)


def _cff_top_fields(top, info):
    """A cffLib top dict's names, version and metrics from the font info, as ufo2ft
    sets them."""
    top.version = "%d.%d" % (info_value(info, "versionMajor"),
                             info_value(info, "versionMinor"))
    for attr, key in (("Notice", "trademark"), ("Copyright", "copyright")):
        text = info_value(info, key)
        if text:
            text = normalize_for_postscript(text.replace("\u00a9", "Copyright"))
        setattr(top, attr, "" if text is None else text)
    top.FullName = info_value(info, "postscriptFullName")
    top.FamilyName = info_value(info, "openTypeNamePreferredFamilyName")
    top.Weight = info_value(info, "postscriptWeightName")
    top.isFixedPitch = int(info_value(info, "postscriptIsFixedPitch"))
    top.ItalicAngle = float(info_value(info, "italicAngle"))
    top.UnderlinePosition = _ot_round(info_value(info, "postscriptUnderlinePosition"))
    top.UnderlineThickness = _ot_round(info_value(info, "postscriptUnderlineThickness"))
    upm = _ot_round(info_value(info, "unitsPerEm"))
    top.FontMatrix = [1.0 / upm, 0, 0, 1.0 / upm, 0, 0]


def _set_side_bearings(hhea, hmtx, order, widths):
    """hhea's minLeftSideBearing, minRightSideBearing and xMaxExtent over the glyphs
    of ``order`` with ink (``widths``: name -> ink width, None for an empty glyph)."""
    lefts, rights, extents = [], [], []
    for name in order:
        width = widths[name]
        if width is None:
            continue
        advance, left = hmtx[name]
        lefts.append(left)
        rights.append(advance - left - width)
        extents.append(left + width)
    hhea.minLeftSideBearing = min(lefts) if lefts else 0
    hhea.minRightSideBearing = min(rights) if rights else 0
    hhea.xMaxExtent = max(extents) if extents else 0


#: what ufo2ft strips from a production glyph name, and its longest one
_INVALID_NAME_CHARS = r"[^0-9a-zA-Z_.]"
_MAX_NAME = 63


def production_names(font, order, glyphs):
    """glyph name -> the name the font is saved with, as ufo2ft's post-processor
    renames the glyphs where the lib has ``public.postscriptNames`` (its
    ``_build_production_names``): the given name, or the glyph's own, without the
    characters PostScript names do not take, made unique with ".N" suffixes;
    ``.notdef`` made here kept.  Empty where the lib has no such names."""
    import re

    names = font.lib.get("public.postscriptNames")
    if not names:
        return {}
    seen, out = {}, {}
    for name in order:
        if name not in glyphs or isinstance(glyphs[name], _Notdef):
            continue
        prod = names.get(name) or name
        valid = re.sub(_INVALID_NAME_CHARS, "", prod)
        if name != prod and len(valid) > _MAX_NAME:
            valid = re.sub(_INVALID_NAME_CHARS, "", name)
        if valid in seen:
            n = seen[valid]
            while (valid + ".%d" % n) in seen:
                n += 1
            seen[valid] = n + 1
            valid += ".%d" % n
        seen[valid] = 1
        out[name] = valid
    return out


def compile_static(font, store, kind, features=None, jobs=1, **options):
    """The ``TTFont`` ufo2ft compiles from the light font of shells ``font``
    (:class:`morph.parse.light_ufo.LightFont`) with the stored outlines ``store``
    (glyph name -> :func:`morph.fonts.stream.compile_outline`'s ``(data, bounds)``:
    CFF charstrings without advance for ``.otf``, glyf bytes for ``.ttf``);
    ``features``: feaLib's tree of the feature file, parsed already (None: parsed
    here); ``jobs``: the subroutinizer's groups run at once
    (:func:`morph.fonts.subrs.font_subroutines`).  See the module docstring.  The
    font's boxes are final: it is to be saved as it is (``recalcBBoxes`` off; the
    CFF table is ``tx``'s bytes); its ``written_cmap`` is its character map as
    saved (code point -> glyph name, production names where the lib has them).

    A font this module does not compile (:func:`left_to_ufo2ft`) is compiled by
    ufo2ft (:func:`morph.fonts.stream.compile_stored`, given ``options``) from the
    ufoLib2 font of the same shells."""
    if features is None and font.features.text:
        features = parse_features(font)
    compiler = _Compiler(font, store, kind == ".otf", jobs)
    reason, writers = left_to_ufo2ft(font, kind, features, compiler.order, compiler.cmap)
    if reason is not None:
        from ..parse.light_ufo import as_ufolib2
        from .stream import compile_stored

        return compile_stored(as_ufolib2(font), store, kind, features=features, **options)
    otf = compiler.compile(features, writers)
    otf.recalcBBoxes = False
    otf.written_cmap = {u: compiler.names.get(n, n) for u, n in compiler.cmap.items()}
    return otf


def left_to_ufo2ft(font, kind, tree, order, cmap):
    """``(reason, writers)``: why the light font ``font`` is compiled by ufo2ft
    after all (None: it is not), and the writers of the features ufo2ft's writers
    would add to the feature file ``tree`` (in their order: the kern feature,
    :class:`morph.fonts.kern_static.KernWriter`; the mark and mkmk features,
    :class:`morph.fonts.mark_static.MarkWriter`; all on one tree).  ``order``: the
    exported glyphs in the font's order; ``cmap``: code point -> glyph name.
    Reasons: TrueType components :mod:`morph.fonts.glyf_static` does not write
    (:func:`~morph.fonts.glyf_static.composite_reason`), kerning or anchors these
    writers do not cover, feature writers that
    would add to the file (:func:`morph.fonts.writers_static.writers_add_nothing`)."""
    skip = set(font.lib.get("public.skipExportGlyphs", ()))
    glyphs = [g for g in font if g.name not in skip]
    if kind == ".ttf" and any(g.components for g in glyphs):
        from .glyf_static import composite_reason

        reason = composite_reason({g.name: g for g in glyphs})
        if reason is not None:
            return reason, []
    if not font.kerning and not any(g.anchors for g in glyphs):
        return None, []
    from fontTools.feaLib import ast

    from .writers_static import feature_tags, writers_add_nothing

    tags = feature_tags(tree)
    kern_todo = bool(font.kerning) and "kern" not in tags
    mark_todo = any(g.anchors for g in glyphs) and not {"mark", "mkmk"} <= tags
    codes = {u for g in glyphs for u in g.unicodes}
    reason = writers_add_nothing(font, tree, glyphs, codes, kern_written=kern_todo,
                                 mark_written=mark_todo)
    if reason is not None or not (kern_todo or mark_todo):
        return reason, []
    tree = tree if tree is not None else ast.FeatureFile()
    writers = []
    if kern_todo:
        from .kern_static import KernWriter

        writers.append(KernWriter(font, tree, order, cmap))
    if mark_todo:
        from .mark_static import MarkWriter

        writers.append(MarkWriter(tree, order, {g.name: g for g in glyphs}, codes))
    for w in writers:
        if w.reason is not None:
            return w.reason, []
    return None, writers


def parse_features(font):
    """feaLib's tree of the font's feature file as ufo2ft parses it (the font's
    glyph names, includes from the UFO's folder)."""
    from io import StringIO

    from .deferred import feature_parser

    buf = StringIO(font.features.text)
    include = None
    if font.path is not None:
        path = os.path.normpath(font.path)
        buf.name = os.path.join(path, "features.fea")
        include = os.path.normpath(os.path.dirname(path) or ".")
    return feature_parser().Parser(buf, set(font.keys()), includeDir=include).parse()


class _Compiler:
    def __init__(self, font, store, cff, jobs=1):
        self.ufo, self.info, self.store, self.cff = font, font.info, store, cff
        self.jobs = jobs
        skip = set(font.lib.get("public.skipExportGlyphs", ()))
        glyphs = {g.name: g for g in font if g.name not in skip}
        if ".notdef" not in glyphs:
            glyphs[".notdef"] = _Notdef(self.info, reverse=not cff)
        self.glyphs = glyphs
        order = [".notdef"]
        names = set(glyphs) - {".notdef"}
        for name in font.glyphOrder:
            if name in names:
                names.remove(name)
                order.append(name)
        self.order = order + sorted(names)
        self.cmap = {}
        for name in self.order:
            for u in glyphs[name].unicodes:
                if u in self.cmap:
                    raise ValueError("cannot map '%s' to U+%04X; already mapped to '%s'"
                                     % (name, u, self.cmap[u]))
                self.cmap[u] = name
        self.otf = _raw_font_class()(sfntVersion="OTTO" if cff else "\000\001\000\000")
        self.names = production_names(font, self.order, glyphs)

    def compile(self, features, writers=()):
        otf = self.otf
        otf.setGlyphOrder(self.order)
        if self.cff:
            self.programs = self._cff_programs()
            self.boxes = self._cff_boxes()
        else:
            self.compiled = self._glyf_glyphs()
            self.boxes = self._glyf_boxes()
        self.font_box = self._font_box()
        self._head()
        self._hmtx()
        self._hhea()
        self._name()
        self._maxp()
        self._cmap()
        self._os2()
        self._post()
        if not self.cff:
            self._glyf_table()
            self._gasp()
        self._features(features, writers)
        if self.cff:
            self._cff()
        else:
            from fontTools.ttLib.standardGlyphOrder import standardGlyphOrder

            post = otf["post"]      # ufo2ft's post-processor: format 2 names again,
            post.mapping = self.names   # production names where the font has them
            post.extraNames = [self.names.get(g, g) for g in otf.getGlyphOrder()
                               if self.names.get(g, g) not in standardGlyphOrder]
        return otf

    # ------------------------------------------------------------------ glyphs

    def _widths(self):
        if getattr(self, "_default_nominal", None) is None:
            info = self.info
            if info.postscriptDefaultWidthX is None and info.postscriptNominalWidthX is None:
                self._default_nominal = optimize_widths(
                    [_ot_round(g.width) for g in self.glyphs.values()])
            else:
                self._default_nominal = (
                    _ot_round(info_value(info, "postscriptDefaultWidthX")),
                    _ot_round(info_value(info, "postscriptNominalWidthX")))
        return self._default_nominal

    def _cff_programs(self):
        """The font's Type 2 programs, each with its advance (:class:`_Programs`,
        read from the store as they are written): the stored charstrings
        (unspecialized, :func:`morph.fonts.stream.compile_outlines`), a glyph with
        components decomposed (:class:`_Decomposer`), ``endchar`` for an empty
        glyph, the ``.notdef`` rectangles drawn as ``T2CharStringPen`` draws them
        (its segments, unspecialized: the subroutinizer rewrites every charstring
        from its path, so that the font is the one the specialized charstrings
        give); the bounds as a charstring's ``calcBounds``."""
        default, nominal = self._widths()
        out = _Programs(self.store, len(self.order))
        composite = [k for k, name in enumerate(self.order) if self.glyphs[name].components]
        prefixes = [width_prefix(self.glyphs[self.order[k]].width, default, nominal)
                    for k in composite]
        decomposed = _Decomposer({g.name: g for g in self.ufo}, self.store).many(
            [self.order[k] for k in composite], prefixes)
        for k, prefix, (program, bounds) in zip(composite, prefixes, decomposed):
            out.own(k, prefix, program, bounds)
        for k, name in enumerate(self.order):
            glyph = self.glyphs[name]
            prefix = width_prefix(glyph.width, default, nominal)
            if glyph.components:
                continue
            if name in self.store:
                out.stored(k, prefix, name)
            elif isinstance(glyph, _Notdef):
                out.own(k, prefix, *glyph.charstring(prefix))
            else:
                out.own(k, prefix, prefix + bytes([_ENDCHAR]), None)
        return out

    @property
    def bounds(self):
        """CFF: glyph name -> its charstring's bounds (None for none)."""
        if not self.cff or getattr(self, "programs", None) is None:
            return {}
        return dict(zip(self.order, self.programs.bounds_list()))

    def _cff_boxes(self):
        boxes = {}
        for name, box in zip(self.order, self.programs.bounds_list()):
            box = None if box is None else Box(*(_ot_round(v) for v in box))
            boxes[name] = None if box == (0, 0, 0, 0) else box
        return boxes

    def _glyf_glyphs(self):
        from fontTools.pens.ttGlyphPen import TTGlyphPointPen
        from fontTools.ttLib.tables._g_l_y_f import Glyph

        from .glyf_static import composite_glyph

        out, drawn = {}, {}
        for name in self.order:
            data = self.store.get(name, (b"",))[0]
            if getattr(self.glyphs[name], "components", None):
                out[name] = composite_glyph(name, self.glyphs, self.store, drawn)
                continue
            if data:
                out[name] = Glyph(data)
                continue
            pen = TTGlyphPointPen(self.glyphs)
            if isinstance(self.glyphs[name], _Notdef):
                self.glyphs[name].drawPoints(pen)
            out[name] = pen.glyph(dropImpliedOnCurves=False, round=_ot_round)
        return out

    def _glyf_boxes(self):
        return glyf_boxes(self.compiled, Box)

    def _font_box(self):
        from fontTools.misc.arrayTools import unionRect

        box = None
        for b in self.boxes.values():
            if b is not None:
                box = b if box is None else unionRect(box, b)
        return Box(0, 0, 0, 0) if box is None else box

    # ------------------------------------------------------------------ tables

    def _head(self):
        from fontTools.ttLib import newTable
        from fontTools.ttLib.tables._h_e_a_d import mac_epoch_diff

        info = self.info
        head = self.otf["head"] = newTable("head")
        head.checkSumAdjustment = 0
        head.tableVersion = 1.0
        head.magicNumber = 0x5F0F3CF5
        full = float("%d.%03d" % (info_value(info, "versionMajor"),
                                  info_value(info, "versionMinor")))
        head.fontRevision = round(full, 3)
        head.unitsPerEm = _ot_round(info_value(info, "unitsPerEm"))
        head.created = _time_value(info_value(info, "openTypeHeadCreated")) - mac_epoch_diff
        head.modified = _time_value(_date_now()) - mac_epoch_diff
        x0, y0, x1, y1 = self.font_box
        head.xMin, head.yMin, head.xMax, head.yMax = (_ot_round(x0), _ot_round(y0),
                                                      _ot_round(x1), _ot_round(y1))
        style = info_value(info, "styleMapStyleName")
        head.macStyle = _int_list_to_num({"bold": [0], "bold italic": [0, 1],
                                          "italic": [1]}.get(style, []), 0, 16)
        head.flags = _int_list_to_num(info_value(info, "openTypeHeadFlags"), 0, 16)
        head.lowestRecPPEM = _ot_round(info_value(info, "openTypeHeadLowestRecPPEM"))
        head.fontDirectionHint = 2
        head.indexToLocFormat = 0
        head.glyphDataFormat = 0

    def _hmtx(self):
        from fontTools.ttLib import newTable

        hmtx = self.otf["hmtx"] = newTable("hmtx")
        hmtx.metrics = {}
        for name, glyph in self.glyphs.items():
            width = _ot_round(glyph.width)
            if width < 0:
                raise ValueError("The width should not be negative: '%s'" % name)
            box = self.boxes[name]
            hmtx[name] = (width, box.xMin if box else 0)

    def _hhea(self):
        from fontTools.ttLib import newTable

        info = self.info
        hhea = self.otf["hhea"] = newTable("hhea")
        hhea.tableVersion = 0x00010000
        for attr, key in (("ascent", "Ascender"), ("descent", "Descender"),
                          ("lineGap", "LineGap"), ("caretSlopeRise", "CaretSlopeRise"),
                          ("caretSlopeRun", "CaretSlopeRun"),
                          ("caretOffset", "CaretOffset")):
            setattr(hhea, attr, _ot_round(info_value(info, "openTypeHhea" + key)))
        hmtx = self.otf["hmtx"]
        advances = [hmtx[name][0] for name in self.order]
        hhea.advanceWidthMax = max(advances) if advances else 0
        _set_side_bearings(hhea, hmtx, self.order, {
            name: None if box is None else box.xMax - box.xMin
            for name, box in self.boxes.items()})
        for i in range(4):
            setattr(hhea, "reserved%i" % i, 0)
        hhea.metricDataFormat = 0
        n = len(advances)
        if n > 1:
            last = advances[-1]
            while advances[n - 2] == last:
                n -= 1
                if n <= 1:
                    n = 1
                    break
        hhea.numberOfHMetrics = n

    def _name(self):
        """ufo2ft's name records (Windows, English, Unicode BMP or full) and the info's
        own records over them.  Where all are Windows Unicode ones the table is
        written here (fontTools' encoding: records sorted, equal strings stored
        once) and kept as bytes: fontTools' name table module loads its OpenType
        layout table classes (a tenth of a second); else fontTools builds it."""
        info = self.info
        values = {0: "copyright", 3: "openTypeNameUniqueID", 5: "openTypeNameVersion",
                  6: "postscriptFontName", 7: "trademark", 8: "openTypeNameManufacturer",
                  9: "openTypeNameDesigner", 10: "openTypeNameDescription",
                  11: "openTypeNameManufacturerURL", 12: "openTypeNameDesignerURL",
                  13: "openTypeNameLicense", 14: "openTypeNameLicenseURL",
                  18: "openTypeNameCompatibleFullName", 19: "openTypeNameSampleText",
                  21: "openTypeNameWWSFamilyName", 22: "openTypeNameWWSSubfamilyName"}
        values = {k: info_value(info, v) for k, v in values.items()}
        values.update({1: info_value(info, "styleMapFamilyName"),
                       2: info_value(info, "styleMapStyleName").title(),
                       4: full_name(info),
                       16: info_value(info, "openTypeNamePreferredFamilyName"),
                       17: info_value(info, "openTypeNamePreferredSubfamilyName")})
        if values[1] == values[16] and values[2] == values[17]:
            del values[16], values[17]
        if values[6]:
            values[6] = normalize_for_postscript(values[6])
        records = {}   # (platform, encoding, language, name ID) -> string, set in order
        for name_id in sorted(values):
            value = values[name_id]
            if value:
                enc = 10 if any(ord(c) > 0xFFFF for c in value) else 1
                records.setdefault((3, enc, 0x409, name_id), value)
        for r in info_value(info, "openTypeNameRecords"):
            records[(r["platformID"], r["encodingID"], r["languageID"], r["nameID"])] = \
                r["string"]
        if all(k[0] == 3 and k[1] in (1, 10) and isinstance(v, str)
               for k, v in records.items()):
            from fontTools.ttLib.tables.DefaultTable import DefaultTable

            from ..parse.names import name_bytes

            table = self.otf["name"] = DefaultTable("name")
            table.data = name_bytes(records)
            return
        from fontTools.ttLib import newTable

        name = self.otf["name"] = newTable("name")
        name.names = []
        for (platform, enc, lang, name_id), value in records.items():
            name.setName(value, name_id, platform, enc, lang)

    def _maxp(self):
        from fontTools.ttLib import newTable

        maxp = self.otf["maxp"] = newTable("maxp")
        maxp.numGlyphs = len(self.order)
        if self.cff:
            maxp.tableVersion = 0x00005000
            return
        maxp.tableVersion = 0x00010000
        maxp.maxZones = 1
        for attr in ("maxTwilightPoints", "maxStorage", "maxFunctionDefs",
                     "maxInstructionDefs", "maxStackElements", "maxSizeOfInstructions",
                     "maxComponentElements", "maxComponentDepth"):
            setattr(maxp, attr, 0)

    def _cmap(self):
        from fontTools.ttLib import newTable
        from fontTools.ttLib.tables._c_m_a_p import cmap_format_4, cmap_format_12

        cmap = self.otf["cmap"] = newTable("cmap")
        cmap.tableVersion = 0
        cmap.tables = []
        non_bmp = {k: v for k, v in self.cmap.items() if k > 65535}
        bmp = {k: v for k, v in self.cmap.items() if k <= 65535} if non_bmp \
            else dict(self.cmap)
        if bmp:
            for platform, enc in ((0, 3), (3, 1)):
                t = cmap_format_4(4)
                t.platformID, t.platEncID, t.language, t.cmap = platform, enc, 0, bmp
                cmap.tables.append(t)
        if non_bmp:
            non_bmp.update(bmp)
            for platform, enc in ((0, 4), (3, 10)):
                t = cmap_format_12(12)
                t.platformID, t.platEncID, t.language, t.cmap = platform, enc, 0, non_bmp
                cmap.tables.append(t)

    def _os2(self):
        from fontTools.ttLib import newTable

        info = self.info
        os2 = self.otf["OS/2"] = newTable("OS/2")
        os2.version = 0x0004
        os2.recalcAvgCharWidth(self.otf)
        os2.xAvgCharWidth = max(min(os2.xAvgCharWidth, 0x7FFF), -0x8000)
        os2.usWeightClass = info_value(info, "openTypeOS2WeightClass")
        os2.usWidthClass = info_value(info, "openTypeOS2WidthClass")
        os2.fsType = _int_list_to_num(info_value(info, "openTypeOS2Type"), 0, 16)
        _os2_script_metrics(os2, info)
        self._os2_classes(os2)
        os2.achVendID = info_value(info, "openTypeOS2VendorID").ljust(4)
        os2.sxHeight = _ot_round(info_value(info, "xHeight"))
        os2.sCapHeight = _ot_round(info_value(info, "capHeight"))
        os2.sTypoAscender = _ot_round(info_value(info, "openTypeOS2TypoAscender"))
        os2.sTypoDescender = _ot_round(info_value(info, "openTypeOS2TypoDescender"))
        os2.sTypoLineGap = _ot_round(info_value(info, "openTypeOS2TypoLineGap"))
        os2.usWinAscent = _ot_round(info_value(info, "openTypeOS2WinAscent"))
        os2.usWinDescent = _ot_round(info_value(info, "openTypeOS2WinDescent"))
        selection = list(info_value(info, "openTypeOS2Selection"))
        selection += {"regular": [6], "bold": [5], "italic": [0],
                      "bold italic": [0, 5]}.get(info_value(info, "styleMapStyleName"), [])
        os2.fsSelection = _int_list_to_num(selection, 0, 16)
        codes = list(self.cmap)
        first, last = (min(codes), max(codes)) if codes else (0xFFFF, 0xFFFF)
        os2.fsFirstCharIndex, os2.fsLastCharIndex = first, min(last, 0xFFFF)
        os2.usBreakChar = 32
        os2.usDefaultChar = 0
        os2.usMaxContext = 0

    def _os2_classes(self, os2):
        """OS/2's family class, PANOSE and Unicode / code page ranges: the font
        info's, or the ranges fontTools finds in the cmap."""
        from fontTools.ttLib.tables.O_S_2f_2 import Panose

        info = self.info
        cls, sub = info_value(info, "openTypeOS2FamilyClass")
        os2.sFamilyClass = (cls << 8) + sub
        data = info_value(info, "openTypeOS2Panose")
        panose = Panose()
        for attr, v in zip(("bFamilyType", "bSerifStyle", "bWeight", "bProportion",
                            "bContrast", "bStrokeVariation", "bArmStyle", "bLetterForm",
                            "bMidline", "bXHeight"), data):
            setattr(panose, attr, v)
        os2.panose = panose
        ranges = info_value(info, "openTypeOS2UnicodeRanges")
        if ranges is not None:
            for i in range(4):
                setattr(os2, "ulUnicodeRange%d" % (i + 1), _int_list_to_num(ranges, 32 * i, 32))
        else:
            os2.recalcUnicodeRanges(self.otf)
        pages = info_value(info, "openTypeOS2CodePageRanges")
        if pages is not None:
            os2.ulCodePageRange1 = _int_list_to_num(pages, 0, 32)
            os2.ulCodePageRange2 = _int_list_to_num(pages, 32, 32)
        else:
            os2.recalcCodePageRanges(self.otf)

    def _post(self):
        from fontTools.ttLib import newTable

        info = self.info
        post = self.otf["post"] = newTable("post")
        post.formatType = 3.0
        post.italicAngle = float(info_value(info, "italicAngle"))
        post.underlinePosition = _ot_round(info_value(info, "postscriptUnderlinePosition"))
        post.underlineThickness = _ot_round(info_value(info, "postscriptUnderlineThickness"))
        post.isFixedPitch = int(info_value(info, "postscriptIsFixedPitch"))
        post.minMemType42 = post.maxMemType42 = post.minMemType1 = post.maxMemType1 = 0
        if not self.cff:
            from fontTools.ttLib.standardGlyphOrder import standardGlyphOrder

            post.formatType = 2.0
            post.extraNames = [g for g in self.order if g not in standardGlyphOrder]
            post.mapping = {}
            post.glyphOrder = self.order

    def _cff(self):
        """The CFF table, subroutinized as ufo2ft does it (cffsubr's ``tx`` given the
        font without its layout tables).  Where cffsubr has its ``tx`` runner on bytes,
        the table ``tx`` reads is written here (:meth:`_cff_file`) and its output
        kept as ``tx`` wrote it: no fontTools.cffLib (and its OpenType table
        classes) is imported.  ``tx`` writes the same table from it (it re-encodes
        every dict, string and charstring); fontTools would re-encode its output
        on saving, so this table equals ufo2ft's as decompiled (ttx), not byte for
        byte.  The boxes the font save would recompute from the CFF table before
        ``tx`` (:meth:`_as_saved`) are set as it sets them.  Otherwise the table
        is built with fontTools.cffLib and
        :func:`morph.fonts.cff_encoding.subroutinize` d."""
        run_tx = _tx_runner()
        if run_tx is None:  # another cffsubr
            self._cff_table()
            subroutinize(self.otf, self.bounds)
            return
        from .subrs import font_subroutines

        box = self._as_saved()
        grouped = font_subroutines(self.programs, jobs=self.jobs)
        table = self._cff_file(box, grouped)
        self.programs = None   # the outlines are in the table's file now
        if grouped is not None:   # a large font: subroutinized in groups, not by one tx
            self.otf["CFF "] = table
            return
        rest = _raw_font_class()(sfntVersion="OTTO", recalcBBoxes=False)
        rest.setGlyphOrder(self.order)
        for tag in self.otf.keys():
            if tag != "GlyphOrder" and tag not in NOT_FOR_TX:
                rest[tag] = self.otf[tag]
        rest["CFF "] = table
        path = _font_file(rest)
        try:
            self.otf["CFF "] = run_tx(path)
        finally:
            os.remove(path)

    def _as_saved(self):
        """What fontTools' save of the font (``recalcBBoxes``) before ``tx`` sets
        from the CFF table: its FontBBox (the union of the charstrings' bounds,
        out to integers), head's box from it, hhea's extents from the bounds' widths
        (out to integers) and hmtx.  Returns the FontBBox."""
        every = self.bounds
        bounds = [b for b in every.values() if b is not None]
        if bounds:
            box = [math.floor(min(b[0] for b in bounds)), math.floor(min(b[1] for b in bounds)),
                   math.ceil(max(b[2] for b in bounds)), math.ceil(max(b[3] for b in bounds))]
        else:
            box = [0, 0, 0, 0]
        head = self.otf["head"]
        head.xMin, head.yMin, head.xMax, head.yMax = box
        hhea, hmtx = self.otf["hhea"], self.otf["hmtx"]
        hhea.advanceWidthMax = max(adv for adv, _ in hmtx.metrics.values())
        _set_side_bearings(hhea, hmtx, self.order, {
            name: None if b is None else int(math.ceil(b[2]) - math.floor(b[0]))
            for name, b in every.items()})
        return box

    def _cff_file(self, font_box, subrs=None):
        """A CFF 1 table of the font (name-keyed), written to a temporary file (a
        :func:`morph.fonts.stream.file_table`: the programs go from the store to the
        file, not into memory), with the top and private dict
        values ufo2ft gives fontTools (those equal to the CFF defaults left out, as
        fontTools leaves them), every string a custom one; ``subrs``: no subroutines
        (None) or (global subroutines, local ones, charstrings in glyph order)."""
        import tempfile

        from .stream import file_table

        info = self.info
        w = _CffDictWriter()
        sid, offset = w.sid, w.offset
        top = self._cff_top(w, font_box)
        private = self._private_dict(w.entry)
        gsubrs, lsubrs, programs = subrs or ([], [], self.programs)
        if lsubrs:      # the local subroutines right after the private dict
            private += offset([19], len(private) + 6)
        names = [sid(self.names.get(n, n)) for n in self.order[1:]]
        charset = b"\0" + struct.pack(">%dH" % len(names), *names)
        charstrings = _index_head(programs.sizes() if subrs else programs.sizes)
        size_charstrings = len(charstrings) + (len(programs.data) if subrs
                                               else int(programs.sizes.sum()))
        global_index = _index(gsubrs)
        name_index = _index([info_value(info, "postscriptFontName").encode("latin-1")])

        def top_index(at_charset, at_charstrings, at_private):
            return _index([b"".join(top) + offset([15], at_charset)
                           + offset([17], at_charstrings)
                           + offset([18], len(private), at_private)])

        size = len(top_index(0, 0, 0))
        string_index = _index([t.encode("latin-1") for t in w.strings])
        at_charset = 4 + len(name_index) + size + len(string_index) + len(global_index)
        at_charstrings = at_charset + len(charset)
        at_private = at_charstrings + size_charstrings
        end = at_private + len(private) + (len(_index(lsubrs)) if lsubrs else 0)
        out = tempfile.TemporaryFile(prefix="morph-cff-")
        for part in (bytes([1, 0, 4, 4]), name_index,
                     top_index(at_charset, at_charstrings, at_private), string_index,
                     global_index, charset, charstrings):
            out.write(part)
        if subrs:
            out.write(programs.data)
        else:
            buf = bytearray()
            for k in range(len(programs)):
                programs.write_to(k, buf)
                if len(buf) > 1 << 16:
                    out.write(buf)
                    del buf[:]
            out.write(buf)
        out.write(private)
        out.write(_index(lsubrs) if lsubrs else b"")
        assert out.tell() == end
        return file_table("CFF ", out)

    def _cff_top(self, w, font_box):
        """The top dict's entries but the offsets (``w``: a :class:`_CffDictWriter`)."""
        info, text, entry = self.info, w.text, w.entry
        top = [text([0], "%d.%d" % (info_value(info, "versionMajor"),
                                    info_value(info, "versionMinor")))]
        for op, key in (([1], "trademark"), ([12, 0], "copyright")):
            value = info_value(info, key)
            if value:
                value = normalize_for_postscript(value.replace("\u00a9", "Copyright"))
            top.append(text(op, "" if value is None else value))
        top.append(text([2], info_value(info, "postscriptFullName")))
        top.append(text([3], info_value(info, "openTypeNamePreferredFamilyName")))
        weight = info_value(info, "postscriptWeightName")
        if weight is not None:
            top.append(text([4], weight))
        upm = _ot_round(info_value(info, "unitsPerEm"))
        for op, value, default in (
                ([12, 1], int(info_value(info, "postscriptIsFixedPitch")), 0),
                ([12, 2], float(info_value(info, "italicAngle")), 0),
                ([12, 3], _ot_round(info_value(info, "postscriptUnderlinePosition")), -100),
                ([12, 4], _ot_round(info_value(info, "postscriptUnderlineThickness")), 50)):
            if value != default:
                top.append(entry(op, value))
        matrix = [1.0 / upm, 0, 0, 1.0 / upm, 0, 0]
        if matrix != [0.001, 0, 0, 0.001, 0, 0]:
            top.append(entry([12, 7], *matrix))
        if list(font_box) != [0, 0, 0, 0]:
            top.append(entry([5], *font_box))
        return top

    def _hints(self):
        """The info's blue zones (BlueValues, OtherBlues, FamilyBlues,
        FamilyOtherBlues: rounded lists or None) and its H and V stem snaps, rounded."""
        def rounded(key):
            v = info_value(self.info, key)
            return [_ot_round(i) for i in v] if isinstance(v, list) else v

        blues = {k: rounded("postscript" + k) for k in ("BlueValues", "OtherBlues",
                                                        "FamilyBlues", "FamilyOtherBlues")}
        return blues, rounded("postscriptStemSnapH"), rounded("postscriptStemSnapV")

    def _private_dict(self, entry):
        """The private dict's bytes: the advances' default and nominal widths, the
        hinting values where the info has blue zones (as ufo2ft writes them)."""
        info = self.info

        def delta(values):
            return [b - a for a, b in zip([0] + values[:-1], values)]

        out = []
        zones, stems_h, stems_v = self._hints()
        blues = list(zip(([6], [7], [8], [9]), zones.values()))
        if any(v for _, v in blues):
            out += [entry(op, *delta(v)) for op, v in blues if v]
            for op, value, default in (
                    ([12, 9], info_value(info, "postscriptBlueScale"), 0.039625),
                    ([12, 10], _ot_round(info_value(info, "postscriptBlueShift")), 7),
                    ([12, 11], _ot_round(info_value(info, "postscriptBlueFuzz")), 1),
                    ([12, 14], int(bool(info_value(info, "postscriptForceBold"))), 0)):
                if value != default:
                    out.append(entry(op, value))
        if stems_h and stems_v:
            out += [entry([10], stems_h[0]), entry([11], stems_v[0]),
                    entry([12, 12], *delta(sorted(stems_h))),
                    entry([12, 13], *delta(sorted(stems_v)))]
        default, nominal = self._widths()
        if default:
            out.append(entry([20], default))
        if nominal:
            out.append(entry([21], nominal))
        return b"".join(out)

    def _cff_table(self):
        from fontTools.cffLib import (CharStrings, GlobalSubrsIndex, IndexedStrings,
                                      PrivateDict, SubrsIndex, TopDict, TopDictIndex)
        from fontTools.ttLib import newTable

        info = self.info
        table = self.otf["CFF "] = newTable("CFF ")
        cff = table.cff
        cff.otFont = self.otf
        cff.major, cff.minor, cff.hdrSize, cff.offSize = 1, 0, 4, 4
        cff.fontNames = []
        strings = cff.strings = IndexedStrings()
        private = PrivateDict(strings=strings)
        private.rawDict.update(private.defaults)
        subrs = GlobalSubrsIndex(private=private)
        top = TopDict(GlobalSubrs=subrs, strings=strings)
        top.Private = private
        charstrings = top.CharStrings = CharStrings(
            file=None, charset=None, globalSubrs=subrs, private=private, fdSelect=None,
            fdArray=None)
        charstrings.charStringsAreIndexed = True
        top.charset = []
        charstrings.charStringsIndex = SubrsIndex(private=private, globalSubrs=subrs)
        cff.topDictIndex = TopDictIndex()
        cff.topDictIndex.append(top)
        cff.topDictIndex.strings = strings
        cff.GlobalSubrs = subrs
        cff.fontNames.append(info_value(info, "postscriptFontName"))
        _cff_top_fields(top, info)
        default, nominal = self._widths()
        if default:
            private.rawDict["defaultWidthX"] = default
        if nominal:
            private.rawDict["nominalWidthX"] = nominal
        blues, stems_h, stems_v = self._hints()
        if any(blues.values()):
            raw = private.rawDict
            raw["BlueFuzz"] = _ot_round(info_value(info, "postscriptBlueFuzz"))
            raw["BlueShift"] = _ot_round(info_value(info, "postscriptBlueShift"))
            raw["BlueScale"] = info_value(info, "postscriptBlueScale")
            raw["ForceBold"] = info_value(info, "postscriptForceBold")
            for k, v in blues.items():
                if v:
                    raw[k] = v
        if stems_h and stems_v:
            private.rawDict["StemSnapH"] = sorted(stems_h)
            private.rawDict["StdHW"] = stems_h[0]
            private.rawDict["StemSnapV"] = sorted(stems_v)
            private.rawDict["StdVW"] = stems_v[0]
        self._fill_charstrings(top, private, subrs)
        top.FontBBox = self.font_box

    def _fill_charstrings(self, top, private, subrs):
        """The glyph programs into ``top``'s CharStrings, in glyph order."""
        charstrings = top.CharStrings
        index = charstrings.charStringsIndex
        for k, (name, bounds) in enumerate(zip(self.order, self.programs.bounds_list())):
            cs = BoundedCharString(bytecode=self.programs[k], private=private,
                                   globalSubrs=subrs)
            cs.bounds = bounds
            if name in charstrings:
                index.items[charstrings.charStrings[name]] = cs
            else:
                index.append(cs)
                charstrings.charStrings[name] = len(top.charset)
                top.charset.append(name)

    def _glyf_table(self):
        from fontTools.ttLib import newTable

        self.otf["loca"] = newTable("loca")
        glyf = self.otf["glyf"] = newTable("glyf")
        glyf.glyphs = {}
        glyf.glyphOrder = self.order
        for name in self.order:
            glyf.glyphs[name] = self.compiled[name]
        composites = [n for n in self.order if getattr(self.glyphs[n], "components", None)
                      and self.compiled[n].isComposite()]
        if composites:
            from .glyf_static import set_component_flags

            for name in composites:
                set_component_flags(name, self.compiled[name], self.glyphs[name],
                                    self.otf["hmtx"])
        maxp = self.otf["maxp"]
        maxp.recalc(HeaderFont(self.otf, Expanded(glyf.glyphs)))
        maxp.maxSizeOfInstructions = max(
            (len(g.program.getBytecode()) for g in glyf.glyphs.values()
             if hasattr(g, "program")), default=0)

    def _gasp(self):
        records = self.info.openTypeGaspRangeRecords
        if not records:
            return
        from fontTools.ttLib import newTable

        gasp = self.otf["gasp"] = newTable("gasp")
        gasp.gaspRange = {r["rangeMaxPPEM"]: _int_list_to_num(r["rangeGaspBehavior"], 0, 4)
                          for r in records}

    def _features(self, tree, writers=()):
        """The feature file as ufo2ft compiles it: parsed (:func:`parse_features`),
        the features ufo2ft's writers would add written in (``writers``, of
        :func:`left_to_ufo2ft`, in their order, on one tree), built by feaLib.

        ufo2ft writes the tree out and feaLib parses that text again with the
        font's glyph order as the glyph names; the tree is built as it is where
        that parse gives the same tree (:meth:`_same_parse`), else written out and
        parsed as ufo2ft does.  A 62-glyph font's kern feature is some 500 lines:
        its parse costs more than building the tables from it."""
        written = [w.write() for w in writers]   # each, in ufo2ft's order
        if not (self.ufo.features.text or "") and not any(written):
            return
        if any(written):
            tree = writers[0].tree
        if tree is None:
            tree = parse_features(self.ufo)
        from .deferred import feature_builder
        from .pair_classes import packed_class_pairs

        builder = feature_builder()
        with packed_class_pairs():   # the class kerning's records held as their bytes
            if self._same_parse():
                if tree.statements:   # the text ufo2ft writes of it is not empty
                    builder.addOpenTypeFeatures(self.otf, tree)
                return
            fea = tree.asFea()
            if fea:
                builder.addOpenTypeFeaturesFromString(self.otf, fea, filename=None)

    def _same_parse(self):
        """Whether feaLib's parse of the feature file with the font's glyph order as
        its glyph names gives the tree of its parse with the UFO's glyph names
        (:func:`parse_features`).  The names decide a parse in two ways only: a
        name the parse does not know is an error, and a hyphenated name that is no
        glyph's is split into a range at the hyphen that leaves glyph names on
        either side.  Both parses are the same where no name of one but not the
        other (the glyphs not exported, the ``.notdef`` this module adds) is in the
        text, not even within another name (the UFO's text: a file with includes
        is parsed again; the writers' features name exported glyphs only)."""
        text = self.ufo.features.text or ""
        extra = set(self.order) ^ set(self.ufo.keys())
        return "include" not in text and not any(name in text for name in extra)
