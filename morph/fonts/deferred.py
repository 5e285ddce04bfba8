"""Modules a command imports but rarely runs, registered to run at their first use.

fontTools' CFF table without its OpenType layout classes, unless a table needs them:

``fontTools.cffLib`` imports fontTools' OpenType layout table classes
(``fontTools.ttLib.tables.otTables``, which builds some 300 classes from its data
tables as it loads) and, through ``otBase``, the HarfBuzz bindings (``uharfbuzz``,
fontTools' GSUB/GPOS packer), both for CFF2's variation store only: a CFF 1 font
without layout tables never uses them, yet every process reading one paid about a
twelfth of a second of CPU for them (a tenth of a 62-glyph ``morph brush``).

:func:`cff_table` reads a font's ``CFF `` table with those two modules deferred
(:func:`deferred_imports`): each is registered under its name and executed at its
first attribute access, as the standard library's ``importlib.util.LazyLoader``
does, so whatever
uses them (a GPOS table decompiled to move anchors, GSUB compiled with HarfBuzz's
packer, a CFF2 variation store) gets the whole module as a plain import would, and a
font that never needs them does not load them.

fontTools' Adobe Glyph List read from morph's copy of the part fontTools names glyphs
by: a font without glyph names (a TrueType font with a format 3 ``post`` table, such
as the bundled Noto Sans) has them made from its character map
(``TTFont._makeGlyphName``: the AGL for New Fonts name, else ``uniXXXX``), which
imports ``fontTools.agl``; that module parses both of Adobe's lists as it loads
(about 57 M instructions, a fifth of a second of a 62-glyph ``morph brush``) while
the names need only the short one (586 names).  :func:`glyph_list` registers
``fontTools.agl`` deferred with its ``UV2AGL`` read from
``morph/fonts/data/aglfn.txt`` (the list fontTools carries, with Adobe's notice);
any other attribute runs the module.

Pillow without its EXIF and TIFF tag tables: ``PIL.Image`` imports ``PIL.ExifTags``
(some hundreds of ``IntEnum`` members, built as it loads: about 30 M instructions,
half of Pillow's import) and ``PIL.TiffTags`` for the metadata of the photographs it
reads; the images morph draws and saves (a font's sample, a shape's PNG) have none.
``Image.tobytes`` (the pixels a sample's PNG is written from) imports
``PIL.ImageFile``, the base of Pillow's file formats, for one number, the size of
the chunks its raw encoder writes: the bytes do not depend on it.  :func:`pillow`
imports Pillow's modules with those deferred, ``PIL.ImageFile``'s ``MAXBLOCK`` set
(:data:`PILLOW_PRESET`).

fontTools.feaLib without fontTools.varLib's package: feaLib's parser and builder import
five small modules of ``fontTools.varLib`` (``models``, ``errors``, ``varStore``,
``builder``, ``featureVars``: variable scalars and feature variations), and importing a
package's module runs the package's ``__init__`` first, here the variable-font builder
(its merger, colorLib's builder, the designspace splitter ...: about 49 M instructions,
more than parsing a 500-line feature file twice).  :func:`feature_parser` and
:func:`feature_builder` import feaLib's modules with the package registered deferred,
its ``__path__`` set (:func:`preset`) so that its modules import without running it;
whatever reads anything else of the package (ufo2ft's variable compilers,
``fontTools.subset``) runs it then and gets it whole.
"""

import sys
import types

__all__ = ["cff_table", "deferred_imports", "feature_builder", "feature_parser", "glyph_list",
           "pillow", "preset", "LAYOUT_MODULES",
           "PILLOW_METADATA", "PILLOW_PRESET"]

#: what fontTools.cffLib imports for CFF2 only: the OpenType layout classes and the
#: HarfBuzz bindings that otBase imports for its packer
LAYOUT_MODULES = ("fontTools.ttLib.tables.otTables", "uharfbuzz")

#: what ``PIL.Image`` imports for the EXIF and TIFF metadata of images it reads
PILLOW_METADATA = ("PIL.ExifTags", "PIL.TiffTags")

#: what ``Image.tobytes`` reads of ``PIL.ImageFile``: its encoder's chunk size (Pillow's
#: value; the bytes are the same for any)
PILLOW_PRESET = {"PIL.ImageFile": {"MAXBLOCK": 65536}}


class _Deferred(types.ModuleType):
    """A module registered in ``sys.modules`` and executed at its first attribute
    access other than ``__spec__`` and ``__name__`` (which the import system reads
    when the module is imported again by name: ``import uharfbuzz as hb`` in
    fontTools' otBase binds the deferred module without running it) and those
    set before it runs (named in its ``_morph_preset``, see :func:`glyph_list`)."""

    def __getattribute__(self, attr):
        fields = types.ModuleType.__getattribute__(self, "__dict__")
        if attr in ("__spec__", "__name__") or attr in fields.get("_morph_preset", ()):
            return fields[attr]
        spec = fields["__spec__"]
        self.__class__ = types.ModuleType
        try:
            spec.loader.exec_module(self)
        except BaseException:
            sys.modules.pop(spec.name, None)  # as a failed plain import leaves it
            raise
        return getattr(self, attr)


def deferred_imports(names):
    """Register each module of ``names`` not yet imported as a :class:`_Deferred`
    module, bound in its parent package as an import binds it; a name that cannot be
    found is left to a plain import (which then raises as usual).  Returns the
    names deferred."""
    import importlib.util

    done = []
    for name in names:
        if name in sys.modules:
            continue
        try:
            spec = importlib.util.find_spec(name)
        except (ImportError, ValueError):
            continue
        if spec is None or not hasattr(spec.loader, "exec_module"):
            continue
        module = importlib.util.module_from_spec(spec)
        module.__class__ = _Deferred
        sys.modules[name] = module
        parent, _, child = name.rpartition(".")
        if parent:
            setattr(sys.modules[parent], child, module)
        done.append(name)
    return done


def _without_variation_package(module):
    """The module ``module`` of fontTools.feaLib, imported with ``fontTools.varLib``'s
    package registered deferred when it is not imported yet (the module docstring)."""
    import importlib

    if module not in sys.modules and deferred_imports(["fontTools.varLib"]):
        package = sys.modules["fontTools.varLib"]
        preset("fontTools.varLib",
               __path__=types.ModuleType.__getattribute__(package, "__dict__")["__path__"])
    return importlib.import_module(module)


def feature_parser():
    """``fontTools.feaLib.parser``, without running ``fontTools.varLib``'s package."""
    return _without_variation_package("fontTools.feaLib.parser")


def feature_builder():
    """``fontTools.feaLib.builder``, without running ``fontTools.varLib``'s package."""
    return _without_variation_package("fontTools.feaLib.builder")


def cff_table(font):
    """``font["CFF "]``, fontTools.cffLib imported with :data:`LAYOUT_MODULES`
    deferred (:func:`deferred_imports`) when it is not imported yet."""
    if "fontTools.cffLib" not in sys.modules:
        deferred_imports(LAYOUT_MODULES)
    return font["CFF "]


def glyph_list():
    """Register ``fontTools.agl`` deferred, its ``UV2AGL`` (code point -> AGL for New
    Fonts name) read from ``data/aglfn.txt``, when it is not imported yet (see the
    module docstring)."""
    from pathlib import Path

    if not deferred_imports(["fontTools.agl"]):
        return
    names = {}
    text = (Path(__file__).parent / "data" / "aglfn.txt").read_text(encoding="ascii")
    for line in text.splitlines():
        if line and line[0] != "#":
            code, name, _ = line.split(";", 2)
            names[int(code, 16)] = name
    preset("fontTools.agl", UV2AGL=names)


def preset(name, **values):
    """Set ``values`` on the deferred module ``name``: they are read without running
    it (:class:`_Deferred`), and replaced by the module's own when it runs."""
    fields = types.ModuleType.__getattribute__(sys.modules[name], "__dict__")
    fields.update(values, _morph_preset=tuple(values))


def pillow(*names):
    """Pillow's modules ``names`` (``"Image"``, ``"ImageDraw"``, ...), in order, imported
    with :data:`PILLOW_METADATA` deferred (:func:`deferred_imports`) when
    ``PIL.Image`` is not imported yet."""
    import importlib

    if "PIL.Image" not in sys.modules:
        deferred_imports(PILLOW_METADATA)
        for name in deferred_imports(PILLOW_PRESET):
            preset(name, **PILLOW_PRESET[name])
    return tuple(importlib.import_module("PIL." + name) for name in names)
