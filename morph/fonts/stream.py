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

- CFF: ``T2CharStringPen``, specialized (ufo2ft's ``optimizeCFF``); the advance is
  prepended when the font's nominal and default widths are known
  (:func:`width_prefix`, what the pen does);
- TrueType: ``TTGlyphPen`` behind a contour reversal, as ufo2ft's
  cubic-to-quadratic filter reverses them (the contours are quadratic already).

Composites: a TrueType glyph of components only stays a composite (ufo2ft draws its
shell); a glyph with components and contours, and every CFF glyph with components,
is decomposed here as ufo2ft's ``DecomposeComponentsFilter`` does it (the glyph's
own contours, then each component's base drawn the same way, transformed), from
the stored outlines.

The source is read the same way (:class:`SkeletonSource`): one pass over the glyphs
for their shells, then each glyph's contours read again when its chunk is prepared,
and dropped (by the worker that strokes the chunk, :func:`worker_source`, when the
source is a UFO on disk and there are workers).  A UFO output is written glyph by glyph (:class:`UfoGlyphWriter`): the
shells are saved first by ufoLib2 (info, kerning, groups, features, lib, layers,
data), then each stroked glyph's ``.glif`` is rewritten as it arrives.
"""

import copy
from pathlib import Path
from types import SimpleNamespace

from .tables import draw_contours

__all__ = ["compile_outline", "width_prefix", "SkeletonSource", "compile_stored",
           "UfoGlyphWriter", "shell_glyph", "sample_font", "worker_source"]


# =========================================================================== worker side

#: the private dict a charstring without an advance is drawn with
_NO_WIDTHS = SimpleNamespace(defaultWidthX=0, nominalWidthX=0)


def compile_outline(contours, flavor):
    """``(data, bounds)`` of integer contours (:func:`morph.fonts.tables.contours_from_loops`)
    compiled as ufo2ft compiles them from a UFO glyph holding those contours.

    ``flavor``: ``"cff"`` (cubic contours; ``data`` the Type 2 charstring's bytes
    without the advance, see :func:`width_prefix`) or ``"glyf"`` (quadratic splines
    in the UFO's direction; ``data`` the compiled ``glyf`` glyph, reversed).
    ``bounds``: (xMin, yMin, xMax, yMax), None when empty: for CFF the outline's
    tight box (``BoundsPen``, what the charstring's ``calcBounds`` computes), for
    glyf the glyph's (integers).  The contours are drawn straight into the
    segment pens: the same bytes as ufo2ft's drawing of a ufoLib2 glyph's points
    (tests/fonts/test_stream.py compares them).
    """
    from fontTools.misc.roundTools import otRound
    from fontTools.pens.recordingPen import RecordingPen

    outline = RecordingPen()
    draw_contours(outline, contours, flavor == "glyf")
    if flavor == "cff":
        from fontTools.pens.boundsPen import BoundsPen
        from fontTools.pens.t2CharStringPen import T2CharStringPen

        pen = T2CharStringPen(None, None, roundTolerance=0.5)
        outline.replay(pen)
        cs = pen.getCharString(_NO_WIDTHS, optimize=True)
        cs.compile()
        box = BoundsPen(None)
        outline.replay(box)
        return bytes(cs.bytecode), (None if box.bounds is None
                                    else tuple(float(v) for v in box.bounds))
    from fontTools.pens.reverseContourPen import ReverseContourPen
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    pen = TTGlyphPen(None)
    outline.replay(ReverseContourPen(pen))
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
        self._glyph_set = self._glyph_dir = None
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

    def glif_data(self, name):
        """The ``.glif`` bytes of glyph ``name`` of a UFO on disk (None for an open
        font, or a glyph the glyph set cannot give: the reader then reads it the
        ufoLib2 way, which names the defect)."""
        if self._glyph_set is None:
            return None
        try:
            return self._glif(name)
        except Exception:  # noqa: BLE001 - read again (and judged) by _read
            return None

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
        """The font to write (see the class docstring); read once, glyph by glyph, on
        the first call (later calls return the same font)."""
        if getattr(self, "_shells", None) is None:
            self._shells = self._shell_font()
        return self._shells

    def _shell_font(self):
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
            shell, contours = self._read_shell(name)
            default.insertGlyph(shell, overwrite=True, copy=False)
            self.contour_counts[name] = contours
        return font

    def _glif(self, name):
        """The .glif bytes of glyph ``name``: from the UFO folder's ``glyphs``
        directory (the default layer's, by the UFO specification) with a plain
        read, a sixth of the time of glifLib's file system layer; from that layer
        where there is no such folder (a zipped UFO)."""
        if self._glyph_dir is None:
            folder = Path(self.path) / "glyphs"
            self._glyph_dir = folder if folder.is_dir() else False
        if self._glyph_dir is False:
            return self._glyph_set.getGLIF(name)
        return (self._glyph_dir / self._glyph_set.contents[name]).read_bytes()

    def _read_shell(self, name):
        """(shell, number of contours) of glyph ``name``, its points not read: the
        .glif's data but its outline by glifLib, the outline's contours counted
        and its components read from the XML tree (in GLIF 2, a component is
        one element, a contour one element of points: reading every point was
        60 % of the shells' time).  A GLIF 1 glyph (whose anchors are contours
        of one point) is read whole."""
        from fontTools.misc import etree
        from fontTools.ufoLib.glifLib import readGlyphFromString
        from ufoLib2.objects import Glyph

        glyph = Glyph(name)
        try:
            text = self._glif(name)
            root = etree.fromstring(text)
            if root.get("format", "2").split(".")[0] == "1":
                shell, pen = self._read(name, _ShellPen)
                return shell, pen.contours
            readGlyphFromString(text, glyph, None, validate=False)
            pen, contours = glyph.getPointPen(), 0
            for element in root.iterfind("outline/*"):
                if element.tag == "contour":
                    contours += 1
                elif element.tag == "component":
                    pen.addComponent(element.get("base"), tuple(
                        _number(element.get(key, default)) for key, default in _TRANSFORM),
                        identifier=element.get("identifier"))
        except Exception:  # noqa: BLE001 - a .glif the plain read cannot take is glifLib's to judge
            shell, pen = self._read(name, _ShellPen)  # its error names the defect
            return shell, pen.contours
        return glyph, contours


_WORKER_SOURCE = {}  # (path, token) -> SkeletonSource: the one this process reads


def worker_source(path, token):
    """The :class:`SkeletonSource` of the UFO at ``path`` for the run ``token``,
    opened once in this process (a worker reads its chunks' skeletons itself); a
    new token (a new run: the UFO may have changed) opens it again."""
    source = _WORKER_SOURCE.get((path, token))
    if source is None:
        _WORKER_SOURCE.clear()
        source = _WORKER_SOURCE[path, token] = SkeletonSource(path)
    return source


#: a GLIF component's transformation attributes and their defaults, in order
_TRANSFORM = (("xScale", "1"), ("xyScale", "0"), ("yxScale", "0"), ("yScale", "1"),
              ("xOffset", "0"), ("yOffset", "0"))


def _number(text):
    """A GLIF number: an int where it is one, else a float (as glifLib reads it)."""
    try:
        return int(text)
    except ValueError:
        return float(text)


# =========================================================================== compiled font

def compile_stored(font, store, kind, **options):
    """The ``TTFont`` ufo2ft compiles from ``font`` (shells, see the module docstring)
    with the stored outlines ``store`` (glyph name -> :func:`compile_outline`'s
    ``(data, bounds)``, of the flavor of ``kind``: ``.otf`` CFF, ``.ttf`` glyf);
    ``options`` go to ufo2ft's ``compileOTF`` / ``compileTTF``."""
    import ufo2ft

    from .stored import StoredCFF, StoredGlyf

    base = StoredCFF if kind == ".otf" else StoredGlyf
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


def sample_font(path, text, length=15):
    """A small ufoLib2 font of the UFO at ``path`` for its sample image
    (:func:`morph.fonts.specimen.sample_text` and ``write_sample_image`` take it as
    they took the whole font, and pick the same text): the glyphs of ``text``'s
    characters and of the font's first ``length`` characters with ink (in code
    point order, as ``sample_text`` picks them), with their components' bases and
    the font info; only those glyphs are read."""
    import unicodedata

    import ufoLib2
    from fontTools.ufoLib import UFOReader

    src = ufoLib2.Font.open(str(path), lazy=True)
    codes = UFOReader(str(path), validate=False).getGlyphSet(validateRead=False).getUnicodes()
    cmap = {}
    for name in src.keys():
        for u in codes.get(name, ()):
            cmap.setdefault(u, name)
    wanted = [cmap[ord(ch)] for ch in text if ord(ch) in cmap]
    own = 0
    for code in sorted(cmap):
        if own == length:
            break
        if unicodedata.category(chr(code))[0] not in ("C", "Z") \
                and src[cmap[code]].getBounds(src) is not None:
            wanted.append(cmap[code])
            own += 1
    out = ufoLib2.Font(info=copy.deepcopy(src.info))
    while wanted:
        name = wanted.pop()
        if name in out or name not in src:
            continue
        out.layers.defaultLayer.insertGlyph(src[name], copy=True)
        wanted.extend(c.baseGlyph for c in src[name].components)
    return out
