"""The composite glyphs of a TrueType font compiled without ufo2ft
(:mod:`morph.fonts.tables_static`), as ufo2ft's outline compiler of the stored
outlines writes them (:class:`morph.fonts.stored.StoredGlyf`, ufo2ft 3's
``OutlineTTFCompiler`` and ``InstructionCompiler``; MIT licence):

- a glyph of components only stays a composite: fontTools' ``TTGlyphPointPen``
  makes its components (offsets rounded, the 2x2 matrix quantized to F2Dot14 and
  values just under +2 clamped, the ROUND_XY_TO_GRID flag set);
- a glyph with stored contours and components is decomposed: its own contours,
  then each component's base (its contours, then its components, recursively)
  through the component's transformation, drawn into the same pen;
- component flags from the glyph's object libs as ufo2ft sets them
  (``public.truetype.roundOffsetToGrid`` false clears ROUND_XY_TO_GRID,
  ``public.truetype.useMyMetrics`` sets USE_MY_METRICS on the first such
  component); where no component's lib has the latter, USE_MY_METRICS goes on the
  first component of the composite's advance width that is not scaled and not
  moved horizontally.

:func:`composite_reason` leaves to ufo2ft the composites this does not cover: a
component whose base is not exported or missing (ufo2ft decomposes or drops it)
and a matrix beyond F2Dot14's range (ufo2ft decomposes the glyph).  The overlap
flags ufo2ft sets come from glyph lib keys the light reader does not take.
"""

__all__ = ["composite_reason", "composite_glyph", "set_component_flags"]

_ROUND_KEY = "public.truetype.roundOffsetToGrid"
_METRICS_KEY = "public.truetype.useMyMetrics"
_OBJECT_LIBS = "public.objectLibs"


def composite_reason(glyphs):
    """None where the composites among the exported glyphs ``glyphs`` (name ->
    shell) are written here as ufo2ft writes them, else why not."""
    for g in glyphs.values():
        for c in g.components:
            if c.baseGlyph not in glyphs:
                return "a component of a glyph not exported or missing (%s in %s)" \
                    % (c.baseGlyph, g.name)
            if any(v > 2 or v < -2 for v in c.transformation[:4]):
                return "a component matrix beyond F2Dot14 (in %s)" % g.name
    return None


def composite_glyph(name, glyphs, store, drawn):
    """The glyf glyph of the glyph ``name`` with components: a composite, or where
    ``store`` holds contours of its own, those and its components' decomposed
    (``drawn``: glyph name -> its stored contours recorded, shared by the calls)."""
    from fontTools.misc.roundTools import otRound
    from fontTools.pens.ttGlyphPen import TTGlyphPointPen

    pen = TTGlyphPointPen(glyphs)
    if store.get(name, (b"",))[0]:
        _decomposed(name, pen, glyphs, store, drawn)
    else:
        for c in glyphs[name].components:
            pen.addComponent(c.baseGlyph, tuple(c.transformation), identifier=c.identifier)
    return pen.glyph(dropImpliedOnCurves=False, round=otRound)


def _own(name, pen, store, drawn):
    rec = drawn.get(name)
    if rec is None:
        from fontTools.pens.recordingPen import RecordingPointPen
        from fontTools.ttLib.tables._g_l_y_f import Glyph

        rec = drawn[name] = RecordingPointPen()
        data = store.get(name, (b"",))[0]
        if data:
            g = Glyph(data)
            g.expand(None)
            g.drawPoints(rec, None)
    rec.replay(pen)


def _decomposed(name, pen, glyphs, store, drawn):
    from fontTools.pens.transformPen import TransformPointPen

    _own(name, pen, store, drawn)
    for c in glyphs[name].components:
        if c.baseGlyph in glyphs:
            _decomposed(c.baseGlyph, TransformPointPen(pen, tuple(c.transformation)),
                        glyphs, store, drawn)


def set_component_flags(name, ttglyph, glyph, hmtx):
    """ufo2ft's ``_set_composite_flags`` on the composite ``ttglyph`` of the shell
    ``glyph`` (``hmtx``: the font's hmtx table)."""
    from fontTools.ttLib.tables._g_l_y_f import ROUND_XY_TO_GRID, USE_MY_METRICS

    if len(ttglyph.components) != len(glyph.components):
        _auto_use_my_metrics(name, ttglyph, hmtx)
        return
    libs = glyph.lib.get(_OBJECT_LIBS, {})
    chosen, has_metrics_key = None, False
    for c, source in zip(ttglyph.components, glyph.components):
        ident = source.identifier
        lib = libs.get(ident) if ident is not None and ident in libs else None
        if lib is None or not (_ROUND_KEY in lib or _METRICS_KEY in lib):
            continue
        if not lib.get(_ROUND_KEY, True):
            c.flags &= ~ROUND_XY_TO_GRID
        if lib.get(_METRICS_KEY, False) and chosen is None:
            c.flags |= USE_MY_METRICS
            chosen = ident
        else:
            c.flags &= ~USE_MY_METRICS
        has_metrics_key |= _METRICS_KEY in lib
    if not has_metrics_key:
        _auto_use_my_metrics(name, ttglyph, hmtx)


def _auto_use_my_metrics(name, ttglyph, hmtx):
    """ufo2ft's ``autoUseMyMetrics``: USE_MY_METRICS on the first component of
    the composite's advance, with no matrix and no horizontal offset."""
    from fontTools.ttLib.tables._g_l_y_f import USE_MY_METRICS

    width = hmtx[name][0]
    for component in ttglyph.components:
        base, transform = component.getComponentInfo()
        if base in hmtx.metrics and hmtx[base][0] == width \
                and transform[:-1] == (1, 0, 0, 1, 0):
            component.flags |= USE_MY_METRICS
            break
