"""A UFO read without ufoLib2, for the fonts :mod:`morph.fonts.tables_static`
compiles without ufo2ft.

ufoLib2 and ufo2ft are a fifth of a second of imports in every process; a small
stroke font (a hundred Hershey glyphs) spends more on them than on its strokes.
For a font whose tables :mod:`morph.fonts.tables_static` builds (nothing in the
libs that ufo2ft reads but the production names and the glyphs not exported, no
feature file with includes) this module reads the UFO without them: the plists
(font info, lib, groups, kerning) as :mod:`plistlib` reads them (:mod:`.plain_plist`),
each ``.glif``'s shell (advance, unicodes, anchors, components, guidelines, note,
lib; the outline's contours only counted, their points read later by
:mod:`morph.parse.glif`) with fontTools' XML parser (lxml where installed).  The
objects have the attributes of ufoLib2's that the stroke pipeline uses (duck-typed:
:class:`LightFont`, :class:`LightGlyph`, :class:`LightInfo`, :class:`LightComponent`,
:class:`LightAnchor`); :func:`as_ufolib2` makes the ufoLib2 font of the same data,
for a font the static compiler leaves to ufo2ft after all.

Whatever this reader does not take (another UFO version, a GLIF 1 glyph, an image,
another lib key ufo2ft reads, groups or kerning ufoLib2's validation refuses, a
``data`` folder, a feature file with ``include``, a glyph the plain XML read
refuses) raises :class:`NotLight`: the caller reads the font with ufoLib2 and
compiles it with ufo2ft, which judge it as before.
"""

import os
import re

from .glif_xml import glif_number as _number
from .glif_xml import (PlainElement, lib_markup, plain_components, plain_lib, plain_libs,
                       plain_tree, xml_module)
from .plain_plist import load_plist

__all__ = ["NotLight", "LightFont", "LightGlyph", "LightInfo", "LightFeatures",
           "LightAnchor", "LightComponent", "read_contents", "read_light_font",
           "glif_shell", "as_ufolib2"]


class NotLight(Exception):
    """The UFO holds something only ufoLib2 and ufo2ft handle (the message says
    what)."""


#: font lib keys ufo2ft does not read: the glyph order; anything else under these
#: prefixes may change what ufo2ft compiles
_UFO2FT_LIB_PREFIXES = ("public.", "com.github.googlei18n.ufo2ft", "com.github.fonttools",
                        "com.nagwa.", "com.schriftgestaltung.Don't use Production Names")
_FONT_LIB_OK = frozenset(("public.glyphOrder", "public.postscriptNames",
                          "public.skipExportGlyphs"))
#: (the object libs ufo2ft reads hold the contexts of contextual anchors, which
#: morph.fonts.mark_static leaves to ufo2ft, and TrueType component flags, which
#: morph.fonts.glyf_static sets as ufo2ft does)
_GLYPH_LIB_OK = frozenset(("public.markColor", "public.objectLibs"))

#: the three vertical metrics with which ufo2ft writes vhea / vmtx (not done here)
_VERTICAL = ("openTypeVheaVertTypoAscender", "openTypeVheaVertTypoDescender",
             "openTypeVheaVertTypoLineGap")


class LightInfo:
    """The font info: the fontinfo.plist's values as attributes, None for one the
    plist lacks (as ufoLib2's ``Info``)."""

    def __init__(self, values=None):
        self.__dict__.update(values or {})

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return None


class LightFeatures:
    """The feature file's text (``features.text``, "" for none)."""

    def __init__(self, text=""):
        self.text = text


class LightGuideline:
    def __init__(self, x=None, y=None, angle=None, name=None, color=None, identifier=None):
        self.x, self.y, self.angle = x, y, angle
        self.name, self.color, self.identifier = name, color, identifier


class LightAnchor:
    def __init__(self, x=0, y=0, name=None, color=None, identifier=None):
        self.x, self.y, self.name = x, y, name
        self.color, self.identifier = color, identifier


class LightComponent:
    """A component: ``baseGlyph``, ``transformation`` (the six numbers, a tuple),
    ``identifier``."""

    def __init__(self, baseGlyph, transformation=(1, 0, 0, 1, 0, 0),  # noqa: N803 - ufoLib2's name
                 identifier=None):
        self.baseGlyph = baseGlyph
        self.transformation = tuple(transformation)
        self.identifier = identifier


class LightGlyph:
    """A glyph's shell: ``name``, ``width``, ``height``, ``unicodes`` (``unicode``
    the first), ``anchors``, ``components``, ``guidelines``, ``lib``, ``note``; no
    contours (their number is the reader's ``contour_counts``)."""

    def __init__(self, name, width=0, height=0, unicodes=None, guidelines=None, lib=None,
                 note=None, anchors=None, components=None):
        self.name, self.width, self.height = name, width, height
        self.unicodes = list(unicodes or [])
        self.guidelines = list(guidelines or [])
        self.lib = dict(lib or {})
        self.note = note
        self.anchors = list(anchors or [])
        self.components = list(components or [])
        self.contours = []

    @property
    def unicode(self):
        return self.unicodes[0] if self.unicodes else None

    def clearContours(self):
        self.contours = []

    def clearComponents(self):
        self.components = []

    def __len__(self):
        return len(self.contours)


class LightFont:
    """The font of shells (:func:`read_light_font`): ``info``, ``lib``, ``groups``
    (name -> list of glyph names), ``kerning`` ((first, second) -> value, as
    ufoLib2's), ``features``, ``path``; its glyphs by name in the order of the
    default layer's contents.plist (ufoLib2's), ``glyphOrder`` from the lib.
    ``light`` tells the writers to build the tables without ufo2ft."""

    light = True

    def __init__(self, path, info, lib, features, glyphs, groups=None, kerning=None):
        self.path, self.info, self.lib, self.features = path, info, lib, features
        self.groups, self.kerning = dict(groups or {}), dict(kerning or {})
        self._glyphs = glyphs

    @property
    def glyphOrder(self):
        return list(self.lib.get("public.glyphOrder", []))

    def keys(self):
        return list(self._glyphs)

    def __iter__(self):
        return iter(self._glyphs.values())

    def __len__(self):
        return len(self._glyphs)

    def __contains__(self, name):
        return name in self._glyphs

    def __getitem__(self, name):
        return self._glyphs[name]


# the UFO 3 font info attributes by value type (fontTools.ufoLib's
# fontInfoAttributesVersion3ValueData): a value of another type, or one of the checks
# of _info_checked failing, leaves the font to ufoLib2, whose validation names it
_STR = ("familyName styleName styleMapFamilyName styleMapStyleName copyright trademark "
        "note openTypeHeadCreated openTypeNameDesigner openTypeNameDesignerURL "
        "openTypeNameManufacturer openTypeNameManufacturerURL openTypeNameLicense "
        "openTypeNameLicenseURL openTypeNameVersion openTypeNameUniqueID "
        "openTypeNameDescription openTypeNamePreferredFamilyName "
        "openTypeNamePreferredSubfamilyName openTypeNameCompatibleFullName "
        "openTypeNameSampleText openTypeNameWWSFamilyName openTypeNameWWSSubfamilyName "
        "openTypeOS2VendorID postscriptFontName postscriptFullName postscriptWeightName "
        "postscriptDefaultCharacter macintoshFONDName").split()
_INT = ("versionMajor versionMinor year openTypeHeadLowestRecPPEM openTypeHheaAscender "
        "openTypeHheaDescender openTypeHheaLineGap openTypeHheaCaretSlopeRise "
        "openTypeHheaCaretSlopeRun openTypeHheaCaretOffset openTypeOS2WidthClass "
        "openTypeOS2WeightClass openTypeOS2TypoAscender openTypeOS2TypoDescender "
        "openTypeOS2TypoLineGap openTypeOS2WinAscent openTypeOS2WinDescent "
        "openTypeOS2SubscriptXSize openTypeOS2SubscriptYSize openTypeOS2SubscriptXOffset "
        "openTypeOS2SubscriptYOffset openTypeOS2SuperscriptXSize "
        "openTypeOS2SuperscriptYSize openTypeOS2SuperscriptXOffset "
        "openTypeOS2SuperscriptYOffset openTypeOS2StrikeoutSize "
        "openTypeOS2StrikeoutPosition openTypeVheaVertTypoAscender "
        "openTypeVheaVertTypoDescender openTypeVheaVertTypoLineGap "
        "openTypeVheaCaretSlopeRise openTypeVheaCaretSlopeRun openTypeVheaCaretOffset "
        "postscriptUniqueID postscriptWindowsCharacterSet macintoshFONDFamilyID").split()
_NUMBER = ("unitsPerEm descender xHeight capHeight ascender italicAngle "
           "postscriptSlantAngle postscriptUnderlineThickness postscriptUnderlinePosition "
           "postscriptBlueFuzz postscriptBlueShift postscriptBlueScale "
           "postscriptDefaultWidthX postscriptNominalWidthX").split()
_BOOL = ("postscriptIsFixedPitch", "postscriptForceBold")
_INT_LISTS = {"openTypeHeadFlags": range(15), "openTypeOS2Selection": (1, 2, 3, 4, 7, 8, 9),
              "openTypeOS2Panose": None, "openTypeOS2FamilyClass": None,
              "openTypeOS2UnicodeRanges": range(128), "openTypeOS2CodePageRanges": range(64),
              "openTypeOS2Type": (0, 1, 2, 3, 8, 9)}
_NUMBER_LISTS = ("postscriptBlueValues postscriptOtherBlues postscriptFamilyBlues "
                 "postscriptFamilyOtherBlues postscriptStemSnapH postscriptStemSnapV").split()
_NON_NEGATIVE = ("versionMinor", "unitsPerEm", "openTypeHeadLowestRecPPEM",
                 "openTypeOS2WeightClass", "openTypeOS2WinAscent", "openTypeOS2WinDescent")
_CREATED = re.compile(r"\d{4}/\d{2}/\d{2} \d{2}:\d{2}:\d{2}$")


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _info_checked(info):
    """``info`` (the fontinfo.plist's dict) where every value is of its attribute's
    type and passes the checks here; else NotLight."""
    for key, v in info.items():
        if key in _STR:
            ok = isinstance(v, str)
        elif key in _INT:
            ok = isinstance(v, int) and not isinstance(v, bool)
        elif key in _NUMBER:
            ok = _is_number(v)
        elif key in _BOOL:
            ok = isinstance(v, bool)
        elif key in _INT_LISTS:
            allowed = _INT_LISTS[key]
            ok = isinstance(v, list) and all(
                isinstance(i, int) and not isinstance(i, bool)
                and (allowed is None or i in allowed) for i in v)
        elif key in _NUMBER_LISTS:
            ok = isinstance(v, list) and all(_is_number(i) for i in v)
        elif key == "openTypeNameRecords":
            ok = isinstance(v, list) and all(
                isinstance(r, dict) and set(r) == {"nameID", "platformID", "encodingID",
                                                   "languageID", "string"}
                and isinstance(r["string"], str)
                and all(isinstance(r[k], int) and r[k] >= 0 for k in r if k != "string")
                for r in v)
        elif key == "openTypeGaspRangeRecords":
            ok = isinstance(v, list) and all(
                isinstance(r, dict) and set(r) == {"rangeMaxPPEM", "rangeGaspBehavior"}
                and isinstance(r["rangeMaxPPEM"], int)
                and isinstance(r["rangeGaspBehavior"], list)
                and all(b in (0, 1, 2, 3) for b in r["rangeGaspBehavior"]) for r in v)
        elif key == "guidelines":
            ok = isinstance(v, list) and all(
                isinstance(g, dict) and all(_is_number(g[k]) for k in ("x", "y", "angle")
                                            if k in g) for g in v)
        else:   # WOFF metadata, unknown keys: ufoLib2's to read and judge
            ok = False
        if ok and key in _NON_NEGATIVE:
            ok = v >= 0
        if not ok:
            raise NotLight("font info %s" % key)
    checks = ((info.get("styleMapStyleName"), ("regular", "italic", "bold", "bold italic")),
              (info.get("openTypeOS2WidthClass"), range(1, 10)))
    if any(v is not None and v not in allowed for v, allowed in checks) \
            or len(info.get("openTypeOS2Panose", [0] * 10)) != 10 \
            or len(info.get("openTypeOS2FamilyClass", [0, 0])) != 2 \
            or not _CREATED.match(info.get("openTypeHeadCreated", "2000/01/01 00:00:00")):
        raise NotLight("font info values")
    return info


def _plist(path, default):
    """The plist at ``path`` (``default`` where there is none), read as plistlib
    reads it (:func:`.plain_plist.load_plist`)."""
    if not os.path.exists(path):
        return default
    return load_plist(path)


def read_contents(path):
    """``(glyphs folder, contents)`` of a UFO's default layer: the folder's path and
    its contents.plist (glyph name -> file name, in the file's order).

    Raises:
        NotLight: not a UFO 3 this reader takes (the caller reads it with ufoLib2).
    """
    try:
        meta = _plist(os.path.join(path, "metainfo.plist"), None)
        if not isinstance(meta, dict) or meta.get("formatVersion") != 3:
            raise NotLight("not a UFO 3")
        layers = _plist(os.path.join(path, "layercontents.plist"), [["public.default",
                                                                    "glyphs"]])
        if "glyphs" not in [d for _, d in layers]:   # the default layer's, by the spec
            raise NotLight("no default layer folder 'glyphs'")
        folder = os.path.join(path, "glyphs")
        contents = _plist(os.path.join(folder, "contents.plist"), None)
    except (OSError, ValueError, TypeError) as exc:   # plistlib's InvalidFileException too
        raise NotLight("plists: %s" % exc) from exc
    if not isinstance(contents, dict):
        raise NotLight("no contents.plist")
    return folder, contents


def read_light_font(path, glif, contour_counts, contents=None, plain=None):
    """The :class:`LightFont` of the UFO at ``path``, every glyph's shell read from
    its ``.glif`` bytes (``glif(name)``); ``contour_counts`` (a dict) gets each
    glyph's number of contours, ``plain`` (a dict, or None) the glyphs whose markup
    but the outline is a plain GLIF 2 glyph (:func:`glif_shell`).  ``contents``: the
    default layer's contents (:func:`read_contents`) where the caller has read them,
    else read here.

    Raises:
        NotLight: the font needs ufoLib2 / ufo2ft (see the module docstring).
    """
    if contents is None:
        _folder, contents = read_contents(path)
    if os.path.isdir(os.path.join(path, "data")) and any(
            files for _, _, files in os.walk(os.path.join(path, "data"))):
        raise NotLight("data folder")
    try:
        info = _plist(os.path.join(path, "fontinfo.plist"), {})
        lib = _plist(os.path.join(path, "lib.plist"), {})
        groups = _plist(os.path.join(path, "groups.plist"), {})
        kerning = _plist(os.path.join(path, "kerning.plist"), {})
        fea = os.path.join(path, "features.fea")
        text = ""
        if os.path.exists(fea):
            with open(fea, "rb") as f:
                text = f.read().decode("utf-8")
    except (OSError, ValueError, TypeError) as exc:   # plistlib's InvalidFileException too
        raise NotLight("plists: %s" % exc) from exc
    order = lib.get("public.glyphOrder", []) if isinstance(lib, dict) else None
    if not isinstance(info, dict) or not isinstance(lib, dict) \
            or not all(isinstance(k, str) for k in lib) \
            or not isinstance(order, list) or not all(isinstance(n, str) for n in order):
        raise NotLight("fontinfo or lib not a dict")
    _info_checked(info)
    upm = info.get("unitsPerEm")
    if upm is not None and not 0 < upm < float("inf"):
        raise NotLight("unitsPerEm %r" % (upm,))
    groups, kerning = _groups_checked(groups), _kerning_checked(kerning)
    for key in lib:
        if key not in _FONT_LIB_OK and key.startswith(_UFO2FT_LIB_PREFIXES):
            raise NotLight("font lib key %s" % key)
    _lib_values_checked(lib)
    if all(info.get(k) is not None for k in _VERTICAL):
        raise NotLight("vertical metrics")
    if re.search(r"\binclude\s*\(", text):
        raise NotLight("feature file includes")
    glyphs, libs = {}, []
    for name in contents:
        try:
            data = glif(name)
        except OSError as exc:   # a missing or unreadable .glif: ufoLib2's to name
            raise NotLight("glyph %r: %s" % (name, exc)) from exc
        glyph, count = glif_shell(name, data, libs, plain)
        glyphs[name] = glyph
        contour_counts[name] = count
    _read_libs(libs, plain)
    return LightFont(path, LightInfo(info), lib, LightFeatures(text), glyphs, groups, kerning)


def _groups_checked(groups):
    """The groups plist as ufoLib2 holds it, where fontTools' ``groupsValidator``
    would pass it (names and members strings, no glyph in two kerning groups of a
    side); else NotLight."""
    if not isinstance(groups, dict):
        raise NotLight("groups")
    sides = ({}, {})
    for name, members in groups.items():
        if not name or not isinstance(members, list) \
                or not all(isinstance(m, str) for m in members):
            raise NotLight("group %r" % (name,))
        for i, prefix in enumerate(("public.kern1.", "public.kern2.")):
            if name.startswith(prefix):
                if name == prefix or any(m in sides[i] for m in members):
                    raise NotLight("kerning group %r" % name)
                sides[i].update(dict.fromkeys(members, name))
    return {name: list(members) for name, members in groups.items()}


def _kerning_checked(kerning):
    """((first, second) -> value) of the kerning plist, where fontTools'
    ``kerningValidator`` would pass it; else NotLight."""
    if not isinstance(kerning, dict):
        raise NotLight("kerning")
    out = {}
    for first, seconds in kerning.items():
        if not isinstance(seconds, dict):
            raise NotLight("kerning of %r" % (first,))
        for second, value in seconds.items():
            if not _is_number(value):
                raise NotLight("kerning of %r, %r" % (first, second))
            out[first, second] = value
    return out


def _lib_values_checked(lib):
    """The lib keys ufo2ft reads that this reader takes, of the types ufo2ft
    reads: production names (glyph name -> name), glyphs not exported (names)."""
    names = lib.get("public.postscriptNames", {})
    skip = lib.get("public.skipExportGlyphs", [])
    if not isinstance(names, dict) or not all(isinstance(k, str) and isinstance(v, str)
                                              for k, v in names.items()) \
            or not isinstance(skip, list) or not all(isinstance(n, str) for n in skip):
        raise NotLight("production names or glyphs not exported")


_CONTOUR = re.compile(rb"<contour[\s/>]")


def glif_shell(name, data, libs=None, plain=None):
    """``(LightGlyph, number of contours)`` of a GLIF 2 glyph's bytes, read as glifLib
    reads them (advance, unicodes without repeats, anchors, components, guidelines,
    note, lib).  ``libs``: a list that takes ``(glyph, markup, data)`` of a glyph with
    a plain lib (:func:`.glif_xml.lib_markup`), read with the others' by
    :func:`_read_libs`; None: read here.  ``plain`` (a dict, or None) takes ``name``
    -> ``hash(data)`` where the markup but the outline is in ufoLib's plain form
    (:func:`.glif_xml.plain_tree`, a plain lib apart) of format "2": what the outline
    scan checks by parsing it (:func:`morph.parse._glif_scan.scan_outlines`).

    Raises:
        NotLight: anything else (an image, GLIF 1, bad XML).
    """
    a, whole = data.find(b"<outline"), data
    contours, components = 0, []
    if a >= 0:
        if data.count(b"<outline") != 1 or b"<!--" in data or b"<![CDATA[" in data:
            raise NotLight("glyph %r: outline not plain" % name)
        b = data.find(b"</outline>", a)
        inner = data[a:b] if b >= 0 else data[a:]
        if b"<component" in inner:
            components = _components(name, inner)
        contours = len(_CONTOUR.findall(inner))
        if b >= 0:
            data = data[:a] + data[b + 10:]
    root, lib = _shell_tree(name, data, libs is not None)
    if root.tag != "glyph" or root.get("format", "2").split(".")[0] != "2" \
            or root.get("name") != name or (root.text or "").strip():
        raise NotLight("glyph %r: not a GLIF 2 glyph of that name" % name)
    glyph = LightGlyph(name, components=components)
    _read_children(name, root, glyph)
    if plain is not None and isinstance(root, PlainElement) and root.get("format") == "2":
        plain[name] = hash(whole)   # the outline scan's check of the rest, done here
    if isinstance(lib, bytes):    # its markup, read with the others' (_read_libs)
        libs.append((glyph, lib, whole))
        return glyph, contours
    if lib is not None:
        glyph.lib = lib
    _lib_keys_checked(name, glyph.lib)
    return glyph, contours


def _read_children(name, root, glyph):
    """The glyph element ``root``'s children (its outline cut) read into ``glyph``, as
    glifLib reads them (:func:`glif_shell`); NotLight for anything else."""
    try:
        for el in root:
            tag = el.tag
            if tag == "advance":
                glyph.width = _number(el.get("width", "0"))
                glyph.height = _number(el.get("height", "0"))
            elif tag == "unicode":
                u = int(el.get("hex"), 16)
                if u not in glyph.unicodes:
                    glyph.unicodes.append(u)
            elif tag == "guideline":
                glyph.guidelines.append(LightGuideline(
                    **{k: (_number(v) if k in ("x", "y", "angle") else v)
                       for k, v in el.attrib.items()}))
            elif tag == "anchor":
                glyph.anchors.append(_anchor(el.attrib))
            elif tag == "note":
                glyph.note = el.text
            elif tag == "lib":
                glyph.lib = _lib(el)
            elif tag == "outline" and not len(el):
                pass
            else:  # image, anything unknown
                raise NotLight("glyph %r: <%s>" % (name, tag))
    except (TypeError, ValueError) as exc:
        raise NotLight("glyph %r: %s" % (name, exc)) from exc


def _shell_tree(name, data, defer):
    """``(root, lib)`` of :func:`glif_shell`'s data (its outline cut): ufoLib's plain
    markup without an XML parser, a plain lib (nested markup) cut out and read by
    plistlib (``lib`` its dict, or with ``defer`` its markup, read later); else the
    XML parser's tree (lxml where installed, as glifLib and .glif read) and None."""
    split = None
    if b"<lib" not in data:
        root = plain_tree(data)
    else:
        split = lib_markup(data) if defer else plain_lib(data)
        root = plain_tree(split[0]) if split is not None else None
    if root is not None:
        return root, split[1] if split is not None else None
    try:
        return xml_module().fromstring(data), None
    except Exception as exc:  # noqa: BLE001 - lxml and ElementTree raise their own types
        raise NotLight("glyph %r: %s" % (name, exc)) from exc


def _lib_keys_checked(name, lib):
    """NotLight for a glyph lib key ufo2ft reads that this reader does not take."""
    for key in lib:
        if key not in _GLYPH_LIB_OK and key.startswith(_UFO2FT_LIB_PREFIXES):
            raise NotLight("glyph %r: lib key %s" % (name, key))


def _read_libs(pending, plain=None):
    """The libs of the glyphs ``pending`` (``(glyph, markup, data)`` of
    :func:`glif_shell`) read in one parse (:func:`.glif_xml.plain_libs`) and their
    keys checked; a glyph whose lib plistlib does not read so is read again whole
    (its lib from the XML parser's tree, not plain: its mark left ``plain``), which
    raises NotLight where the reader does not take the file."""
    for (glyph, _, data), lib in zip(pending, plain_libs([m for _, m, _ in pending])
                                     if pending else ()):
        if lib is None and plain is not None:
            plain.pop(glyph.name, None)
        glyph.lib = lib if lib is not None else glif_shell(glyph.name, data)[0].lib
        _lib_keys_checked(glyph.name, glyph.lib)


def _anchor(attrib):
    """A GLIF anchor (x and y required, as glifLib requires them)."""
    if "x" not in attrib or "y" not in attrib \
            or not set(attrib) <= {"x", "y", "name", "color", "identifier"}:
        raise ValueError("anchor %r" % dict(attrib))
    return LightAnchor(_number(attrib["x"]), _number(attrib["y"]), attrib.get("name"),
                       attrib.get("color"), attrib.get("identifier"))


#: a GLIF component's transformation attributes and their defaults, in order
_TRANSFORM = (("xScale", "1"), ("xyScale", "0"), ("yxScale", "0"), ("yScale", "1"),
              ("xOffset", "0"), ("yOffset", "0"))
_COMPONENT_KEYS = frozenset(k for k, _ in _TRANSFORM) | {"base", "identifier"}


def _components(name, outline):
    """The components of a glyph's outline element's bytes (``<outline>`` up to its
    end tag), in order; NotLight for one without a base or with another attribute.
    Plain markup is read without the XML parser (:func:`.glif_xml.plain_components`)."""
    try:
        plain = plain_components(outline)
        if plain is None:   # (attributes, number of children) of each component
            root = xml_module().fromstring(outline + b"</outline>")
            plain = [(el.attrib, len(el)) for el in root.iterfind("component")]
        else:
            plain = [(attrib, 0) for attrib in plain]
        out = []
        for attrib, children in plain:
            if not attrib.get("base") or not set(attrib) <= _COMPONENT_KEYS or children:
                raise ValueError("component %r" % dict(attrib))
            out.append(LightComponent(attrib["base"], tuple(
                _number(attrib.get(k, d)) for k, d in _TRANSFORM), attrib.get("identifier")))
    except Exception as exc:  # noqa: BLE001 - lxml and ElementTree raise their own types
        raise NotLight("glyph %r: %s" % (name, exc)) from exc
    return out


def _lib(element):
    import plistlib

    from fontTools.misc import etree

    if len(element) != 1 or element[0].tag != "dict":
        raise ValueError("lib is not one dict")
    text = b'<plist version="1.0">' + etree.tostring(element[0]) + b"</plist>"
    return plistlib.loads(text)


def as_ufolib2(font):
    """The ufoLib2 font of a :class:`LightFont`'s data as it is now (shells: no
    contours): font info, lib, groups, kerning, feature text and every glyph's
    advance, unicodes, anchors, components, guidelines, note and lib, in the same
    order; for ufo2ft, where :mod:`morph.fonts.tables_static` does not compile a
    font itself."""
    import copy

    import ufoLib2
    from ufoLib2.objects import Anchor, Component, Glyph, Guideline

    out = ufoLib2.Font(lib=copy.deepcopy(font.lib), groups=copy.deepcopy(font.groups),
                       kerning=dict(font.kerning))
    out.features.text = font.features.text or ""
    for key, value in vars(font.info).items():
        setattr(out.info, key, copy.deepcopy(value))
    layer = out.layers.defaultLayer
    for g in font:
        layer.insertGlyph(Glyph(
            g.name, width=g.width, height=g.height, unicodes=list(g.unicodes),
            lib=copy.deepcopy(g.lib), note=g.note,
            anchors=[Anchor(a.x, a.y, a.name, a.color, a.identifier) for a in g.anchors],
            components=[Component(c.baseGlyph, tuple(c.transformation), c.identifier)
                        for c in g.components],
            guidelines=[Guideline(x=gl.x, y=gl.y, angle=gl.angle, name=gl.name,
                                  color=gl.color, identifier=gl.identifier)
                        for gl in g.guidelines]), copy=False)
    return out
