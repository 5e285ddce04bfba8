"""The markup of GLIF files read as trees: ufoLib's plain markup by splitting its
bytes (:func:`plain_tree`, no XML parser imported), anything else by the XML parser
fontTools' GLIF reader uses (:func:`xml_module`).  The GLIF readers (:mod:`.glif`, its
byte scan :mod:`._glif_scan`, the glyph shells of :mod:`.light_ufo`) share it.
"""

__all__ = ["PlainElement", "parse_glif", "plain_tree", "xml_module"]

_PARSER = None


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


def _plain_element(markup):
    """(tag, attributes) of an element's markup between ``<`` and ``>`` (or ``/>``):
    a name, then attributes ``name="value"`` each after white space; None for
    anything else (another quote, white space in a value or before ``=``, a name
    of other characters, a repeated attribute)."""
    pieces = markup.split(b'"')
    head, tail = pieces[0], pieces[-1]
    if len(pieces) == 1:
        tag, head, tail = markup.rstrip(_WS), b"", b""
    else:
        tag = head.split(None, 1)[0]
        head = head[len(tag):]
    if not tag.isalpha() or tail.strip(_WS) or not tag.isascii():
        return None
    attrib = {}
    for key, value in zip([head] + pieces[2:-1:2], pieces[1::2]):
        name = key[:-1].lstrip(_WS)
        if key[-1:] != b"=" or len(name) == len(key) - 1 or not name.isalpha() \
                or name.decode() in attrib or value.translate(None, b"\t\r\n<>") != value:
            return None
        attrib[name.decode()] = value.decode()
    return tag.decode(), attrib


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
