"""XML property lists in the plain markup UFO tools write, read without an XML parser.

:mod:`plistlib` reads a plist with expat and one Python call per element event (a
UFO's groups, kerning and glyph contents are thousands of elements).  For a plist
in plain markup (the usual XML declaration and doctype, ``<plist version="1.0">``,
then tags without attributes of the types ``dict``, ``array``, ``key``,
``string``, ``integer``, ``real``, ``true/``, ``false/``; no text between elements
but white space; numbers in JSON's syntax; no reference but XML's five entities)
:func:`plain_plist` rewrites the markup as JSON with a fixed number of string
replacements and reads it with :mod:`json`'s scanner (all in C): the same objects as
plistlib's, the same texts given to the same conversions (an integer's digits to
``int``, a real's to ``float``), the same dict and list nesting.  Anything else (a
comment, a ``data`` or ``date`` element, a hexadecimal integer, a key without a
value ...) gives None, and the caller reads the file with :mod:`plistlib`, which
reads or refuses it as always.
"""

import re

__all__ = ["plain_plist", "plain_markup", "plain_value", "load_plist"]

#: the start of a plain plist up to its root element's start tag
_HEAD = re.compile(
    rb"<\?xml version=([\"'])1\.0\1 encoding=([\"'])(?i:utf-8)\2\?>[ \t\n]*"
    rb"(?:<!DOCTYPE plist PUBLIC \"-//Apple//DTD PLIST 1\.0//EN\" "
    rb"\"http://www\.apple\.com/DTDs/PropertyList-1\.0\.dtd\">[ \t\n]*)?"
    rb"<plist version=\"1\.0\">")
#: the end of a plain plist: the root element's end tag, white space
_TAIL = re.compile(rb"</plist>[ \t\n]*\Z")
#: bytes a plain plist holds none of: controls but tab and line feed (expat turns a
#: carriage return into a line feed)
_CONTROLS = bytes([*range(9), *range(11, 32)])
#: byte strings a plain plist holds none of: the end of a CDATA section, the
#: characters U+FFFE and U+FFFF (XML refuses them)
_NOT_PLAIN = (b"]]>", b"\xef\xbf\xbe", b"\xef\xbf\xbf")
#: a number element whose text is not in JSON's syntax of its value (an integer, a
#: real without exponent)
_ODD_NUMBER = re.compile(r"<integer>(?!-?(?:0|[1-9][0-9]*)</integer>)"
                         r"|<real>(?!-?(?:0|[1-9][0-9]*)(?:\.[0-9]+)?</real>)")
#: a key or string element not closed by its own end tag right after its text (each
#: leaf's end tag is its own: the counts of each leaf's start and end tags agree too)
_UNCLOSED = re.compile(r"<(?:key>(?![^<]*</key>)|string>(?![^<]*</string>))")
#: XML's five predefined entities, the only references a plain plist holds
_ENTITY = re.compile(r"&(?:amp|lt|gt|quot|apos);")
#: the markup of a plain plist as JSON: first the characters of the texts that JSON
#: reads as syntax escaped (so that text between elements, which plistlib ignores,
#: can only be read by JSON as a number or a constant, see :func:`plain_value`), then
#: each tag: a number's text after a space (text before it cannot join it), a
#: real's with an exponent (JSON reads a float of it: float("5e0") is float("5")),
#: each value followed by a comma; the five entities last
_TEXT_ESCAPES = (("\\", "\\\\"), ('"', '\\"'), ("{", "\\u007b"), ("}", "\\u007d"),
                 ("[", "\\u005b"), ("]", "\\u005d"), (",", "\\u002c"), (":", "\\u003a"))
_TAGS = (("<key>", '"'), ("</key>", '":'), ("<key/>", '"":'),
         ("<string>", '"'), ("</string>", '",'), ("<string/>", '"",'),
         ("<integer>", " "), ("</integer>", ","), ("<real>", " "), ("</real>", "e0,"),
         ("<true/>", "true,"), ("<false/>", "false,"),
         ("<dict>", "{"), ("</dict>", "},"), ("<dict/>", "{},"),
         ("<array>", "["), ("</array>", "],"), ("<array/>", "[],"))
_ENTITIES = (("&lt;", "<"), ("&gt;", ">"), ("&quot;", '\\"'), ("&apos;", "'"), ("&amp;", "&"))
#: the last value's comma before its container's end (a text's ``}`` and ``]`` are
#: escaped: a comma in a text is followed by its string's closing quote), and an
#: empty array
_LAST_COMMA = (re.compile(r",[ \t\n]*}"), re.compile(r",[ \t\n]*]"))
_EMPTY_ARRAY = re.compile(r"\[[ \t\n]*]")


def load_plist(path):
    """The object of the plist file at ``path``: :func:`plain_plist` of its bytes,
    or :mod:`plistlib`'s reading where that gives None."""
    with open(path, "rb") as f:
        data = f.read()
    value = plain_plist(data)
    if value is not None:
        return value
    import io
    import plistlib

    return plistlib.load(io.BytesIO(data))


def plain_plist(data):
    """The object :mod:`plistlib` reads from the plist ``data`` (bytes) in plain
    markup (see the module docstring); None for anything else."""
    head = _HEAD.match(data)
    tail = _TAIL.search(data, head.end()) if head is not None else None
    return None if tail is None else plain_markup(data[head.end():tail.start()])


def plain_markup(markup):
    """The one value of a plain plist's root element from its ``markup`` (the bytes
    between its tags, UTF-8), as :mod:`plistlib` reads it; None for anything else
    (see :func:`plain_value`)."""
    if len(markup.translate(None, _CONTROLS)) != len(markup) \
            or any(b in markup for b in _NOT_PLAIN):
        return None
    try:
        return plain_value(markup.decode("utf-8"))
    except UnicodeDecodeError:
        return None


def plain_value(markup):
    """:func:`plain_markup` of the markup as text (no control character but tab and
    line feed, no ``]]>``), read as JSON (see the module docstring).

    The leaves' tags pair up (checked), the containers' as JSON's brackets
    do.  Text between elements, which plistlib ignores, is refused: JSON cannot read
    it (its syntax characters escaped, a number after a space) but where it is a
    number or a constant last in an array (``[1, 2, 3]``), which the count of the
    arrays' ends finds: each of ours follows a value's comma or its start."""
    markup = markup.strip(" \t\n")
    count = markup.count
    if not markup.startswith("<") or _ODD_NUMBER.search(markup) or _UNCLOSED.search(markup) \
            or count("<key>") != count("</key>") or count("<string>") != count("</string>") \
            or count("<integer>") != count("</integer>") or count("<real>") != count("</real>"):
        return None
    amp = "&" in markup
    if amp and "&" in _ENTITY.sub("", markup):
        return None
    for old, new in _TEXT_ESCAPES + _TAGS:
        markup = markup.replace(old, new)
    if "<" in markup or not markup.endswith(","):   # another element: plistlib's
        return None
    if amp:
        for old, new in _ENTITIES:
            markup = markup.replace(old, new)
    markup = _LAST_COMMA[0].sub("}", markup[:-1])
    markup, ends = _LAST_COMMA[1].subn("]", markup)
    if ends + len(_EMPTY_ARRAY.findall(markup)) != markup.count("]"):
        return None
    try:
        value, end = _scanner()(markup, 0)
    except (ValueError, StopIteration):
        return None
    return value if end == len(markup) else None


def _no_constant(name):
    raise ValueError(name)


class _JSON:
    """The settings of the JSON scanner: strings may hold tabs and line feeds, no
    hooks, numbers by ``int`` and ``float``, no NaN or Infinity."""

    strict = False
    object_hook = object_pairs_hook = None
    parse_float, parse_int, parse_constant = float, int, staticmethod(_no_constant)
    memo = {}


_SCAN = []


def _scanner():
    """The JSON scanner ``scan(text, index) -> (value, end)`` of :class:`_JSON`:
    json's C scanner (``_json``, without importing the json package, a few M
    instructions), else its Python one."""
    if not _SCAN:
        try:
            from _json import make_scanner
        except ImportError:   # an interpreter without json's C speedups
            from json.scanner import py_make_scanner as make_scanner
        _SCAN.append(make_scanner(_JSON()))
    return _SCAN[0]
