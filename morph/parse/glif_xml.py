"""The markup of GLIF files read as trees: ufoLib's plain markup by splitting its
bytes (:func:`plain_tree`, no XML parser imported), anything else by the XML parser
fontTools' GLIF reader uses (:func:`xml_module`).  The GLIF readers (:mod:`.glif`, its
byte scan :mod:`._glif_scan`, the glyph shells of :mod:`.light_ufo`) share it.
"""

import re

__all__ = ["PlainElement", "glif_number", "lib_markup", "parse_glif", "plain_components",
           "plain_lib", "plain_libs", "plain_tree", "xml_module"]

_PARSER = None


def glif_number(text):
    """A GLIF number: an int where the text is one, else a float (as glifLib reads
    it).  A text with a point is no int: it goes to ``float`` at once (without the
    ValueError ``int`` would raise, formatted and caught)."""
    if "." not in text:
        try:
            return int(text)
        except ValueError:
            pass
    return float(text)


def xml_module():
    """The XML module fontTools' GLIF reader parses with: ``fontTools.misc.etree``
    where lxml is installed (lxml's parser), else ``xml.etree.ElementTree``, whose
    ``fromstring`` ``fontTools.misc.etree`` then exports: the same trees, without
    importing fontTools' serializer (its classes and regular expressions, about a
    ms of every process reading a UFO)."""
    global _XML
    if _XML is None:
        try:
            import lxml.etree  # noqa: F401 - only whether lxml is installed
        except ImportError:
            import xml.etree.ElementTree as _XML
        else:
            from fontTools.misc import etree as _XML
    return _XML


_XML = None


#: the XML declarations of a plain GLIF file (:func:`plain_tree`)
_DECLARATIONS = (b"<?xml version='1.0' encoding='UTF-8'?>",
                 b'<?xml version="1.0" encoding="UTF-8"?>')
_WS = b" \t\r\n"
#: bytes a plain GLIF file holds none of: controls other than XML's white space,
#: references, bytes outside ASCII (read in the file's encoding)
_NOT_PLAIN = bytes([*range(9), 11, 12, *range(14, 32), ord("&"), *range(127, 256)])


class PlainElement:
    """An element of :func:`plain_tree`: what the GLIF readers ask of an ElementTree
    element (``tag``, ``attrib``, ``get``, ``text``, its children by iteration and
    ``len``)."""

    __slots__ = ("tag", "attrib", "text", "children")

    def __init__(self, tag, attrib, text=None, children=()):
        self.tag, self.attrib, self.text, self.children = tag, attrib, text, list(children)

    def get(self, key, default=None):
        return self.attrib.get(key, default)

    def __iter__(self):
        return iter(self.children)

    def __len__(self):
        return len(self.children)


#: an element's markup between ``<`` and ``>`` (or ``/>``): its name, then attributes
#: ``name="value"`` each after white space (a value without the characters XML
#: normalizes or refuses there), then white space
_ELEMENT = re.compile(rb'([A-Za-z]+)((?:[ \t\r\n]+[A-Za-z]+="[^"<>\t\r\n]*")*)[ \t\r\n]*')
_ATTRIBUTE = re.compile(rb'([A-Za-z]+)="([^"]*)"')


def _plain_element(markup):
    """(tag, attributes) of an element's markup between ``<`` and ``>`` (or ``/>``):
    a name, then attributes ``name="value"`` each after white space; None for
    anything else (another quote, white space in a value or before ``=``, a name
    of other characters, a repeated attribute)."""
    m = _ELEMENT.fullmatch(markup)
    if m is None:
        return None
    pairs = _ATTRIBUTE.findall(m[2])
    attrib = {k.decode(): v.decode() for k, v in pairs}
    return (m[1].decode(), attrib) if len(attrib) == len(pairs) else None


def plain_tree(data):
    """The tree of GLIF ``data`` (bytes) in the plain form ufoLib writes, the glyph's
    element of empty children (advance, unicodes, anchors, an empty outline ...)
    with double-quoted attributes, as :class:`PlainElement` s: read by splitting
    the bytes, without an XML parser (whose import is a few ms of every process);
    None for anything else (comments, references, processing instructions,
    single quotes, bytes outside ASCII, text, nested elements), which the XML
    parser reads.  The tags, attributes and texts are those ElementTree gives."""
    for declaration in _DECLARATIONS:
        if data.startswith(declaration):
            data = data[len(declaration):]
            break
    if data.translate(None, _NOT_PLAIN) != data:
        return None
    front, *parts = data.split(b"<")
    if len(parts) < 2 or front.strip(_WS) or parts[-1].rstrip(_WS) != b"/glyph>":
        return None
    elements = []
    for part in parts[:-1]:
        markup, close, text = part.partition(b">")
        empty = markup[-1:] == b"/"
        element = _plain_element(markup[:-1] if empty else markup) if close else None
        if element is None or text.strip(_WS) or empty != bool(elements):
            return None
        elements.append((element, text))
    ((tag, attrib), text), *children = elements
    if tag != "glyph":
        return None
    return PlainElement(tag, attrib, text.decode() or None,
                        [PlainElement(t, a) for (t, a), _ in children])


def plain_components(outline):
    """The attributes of the components of an outline element's bytes (``<outline>``
    up to its end tag, not included) in ufoLib's plain markup (contours of empty
    point elements and empty components, attributes as :func:`plain_tree` reads
    them, nothing else), in order; None for anything else, which the XML parser
    reads."""
    if outline.translate(None, _NOT_PLAIN) != outline:
        return None
    front, *parts = outline.split(b"<")
    if front or not parts:
        return None
    out, depth = [], -1          # -1: before the outline's start tag
    for part in parts:
        markup, close, text = part.partition(b">")
        if not close or text.strip(_WS):
            return None
        if markup[:1] == b"/":   # only a contour ends inside the outline
            if depth != 1 or markup[1:].rstrip(_WS) != b"contour":
                return None
            depth = 0
            continue
        empty = markup[-1:] == b"/"
        element = _plain_element(markup[:-1] if empty else markup)
        if element is None:
            return None
        tag = element[0]
        if depth == -1 and tag == "outline" and not empty:
            depth = 0
        elif depth == 0 and tag == "contour":
            depth = 0 if empty else 1
        elif depth == 0 and tag == "component" and empty:
            out.append(element[1])
        elif not (depth == 1 and tag == "point" and empty):
            return None
    return out if depth == 0 else None


#: a tag without attributes (a plain lib's markup, :func:`plain_lib`)
_BARE_TAG = re.compile(rb"</?[A-Za-z]+/?>")


def plain_lib(data):
    """``(rest, lib)``: GLIF ``data`` without its ``<lib>`` element and the lib's dict
    (:func:`plain_libs` of :func:`lib_markup`'s markup), else None, for the XML
    parser."""
    split = lib_markup(data)
    lib = plain_libs([split[1]])[0] if split is not None else None
    return None if lib is None else (split[0], lib)


def lib_markup(data):
    """``(rest, markup)``: GLIF ``data`` without its ``<lib>`` element, and the
    element's content, where the file has one lib element (no attributes) holding
    one ``dict`` in plain markup (tags without attributes: no comment, CDATA
    section, processing instruction or namespace; no character reference, which
    the tree's serialization can turn into another character, a carriage return
    into a line end); else None."""
    a = data.find(b"<lib>")
    if a < 0 or data.count(b"<lib") != 1 or data.count(b"</lib>") != 1:
        return None
    b = data.find(b"</lib>", a)
    inner = data[a + 5:b].strip(_WS)
    # one dict child: the first and the last element are dicts, and plistlib finds one
    if not inner.startswith(b"<dict>") or not inner.endswith(b"</dict>") or b"&#" in inner \
            or inner.count(b"<") != len(_BARE_TAG.findall(inner)):
        return None
    return data[:a] + data[b + 6:], inner


def plain_libs(markups):
    """Per lib markup of :func:`lib_markup` its dict as :mod:`plistlib` reads it
    (expat: the XML parser's own checks of well-formedness); None where plistlib
    refuses it or finds other than one dict (the XML parser's to judge).  The dict
    is what plistlib reads of the element as the XML parser's tree serializes it
    (the same characters: entities resolved, line ends normalized, by expat).  A
    lib in plain markup is read without plistlib
    (:func:`.plain_plist.plain_markup`), the others all in one parse."""
    from .plain_plist import plain_markup

    values = [plain_markup(m) for m in markups]
    values = [v if isinstance(v, dict) else None for v in values]
    rest = [k for k, v in enumerate(values) if v is None]
    for k, v in zip(rest, _plistlib_libs([markups[k] for k in rest]) if rest else ()):
        values[k] = v
    return values


def _plistlib_libs(markups):
    """:func:`plain_libs` of ``markups`` by :mod:`plistlib`, all in one parse."""
    import plistlib

    try:   # each inside a lib element, as in its file: its markup closes nothing around it
        values = plistlib.loads(b'<plist version="1.0"><array>' + b"".join(
            b"<array><lib>" + m + b"</lib></array>" for m in markups) + b"</array></plist>")
    except Exception:  # noqa: BLE001 - expat's and plistlib's errors: each read alone
        if len(markups) == 1:
            return [None]
        return [lib for m in markups for lib in _plistlib_libs([m])]
    return [v[0] if len(v) == 1 and isinstance(v[0], dict) else None for v in values]


def parse_glif(data):
    """The tree of GLIF ``data`` (bytes): :func:`plain_tree` where the file is in
    ufoLib's plain markup, else the XML parser's (:func:`xml_module`; lxml's
    parser drops comments, as glifLib's does)."""
    global _PARSER
    plain = plain_tree(data)
    if plain is not None:
        return plain
    etree = xml_module()

    if getattr(etree, "_have_lxml", False):
        if _PARSER is None:
            _PARSER = etree.XMLParser(remove_comments=True)
        return etree.fromstring(data, parser=_PARSER)
    return etree.fromstring(data)
