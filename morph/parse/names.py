"""A font's name records read and written from the ``name`` table's stored bytes.

fontTools' name table module imports its OpenType layout table classes
(``fontTools.ttLib.tables.otTables``, some 300 classes built as it loads, and through
``otBase`` the HarfBuzz bindings: about 0.19 G instructions) for the name IDs other
tables refer to.  A font whose records are all in encodings read here (Windows
Unicode, Macintosh Roman English; :data:`ENCODINGS`) has its names read
(:func:`name_table`) and a renamed font its table written (:class:`NameTable`)
without it, to the bytes fontTools would write; any other font's names go through
fontTools as usual.
"""

import struct

from fontTools.ttLib.tables.DefaultTable import DefaultTable

__all__ = ["ENCODINGS", "NameTable", "name_records", "name_table", "name_keys", "records_of",
           "set_names", "name_bytes"]

#: (platform, encoding, language or None for any) -> the Python codec of its strings,
#: as ``fontTools.misc.encodingTools.getEncoding`` tells them
ENCODINGS = {(3, 0, None): "utf_16_be", (3, 1, None): "utf_16_be",
             (3, 10, None): "utf_16_be", (1, 0, 0): "mac_roman"}


def codec(platform, encoding, language):
    """The codec of the records at (platform, encoding, language), None if not read here."""
    return ENCODINGS.get((platform, encoding, None)) or ENCODINGS.get(
        (platform, encoding, language))


def name_records(data):
    """``{(platform, encoding, language, name ID): bytes}`` of a stored ``name`` table,
    in its order, where fontTools would read every record as stored (format 0,
    strings inside the table, no key twice) and each is in an encoding of
    :data:`ENCODINGS`; else None."""
    try:
        fmt, count, strings = struct.unpack_from(">3H", data)
        if fmt != 0 or strings != 6 + 12 * count:
            return None
        records = {}
        for k in range(count):
            *key, length, at = struct.unpack_from(">6H", data, 6 + 12 * k)
            key = tuple(key)
            if key in records or at + length > len(data) - strings or codec(*key[:3]) is None:
                return None
            records[key] = data[strings + at:strings + at + length]
    except struct.error:
        return None
    return records


def _debug_name(records, name_id):
    """fontTools' ``getDebugName``: the first English record's text (Windows
    0x409 or Macintosh 0), else the last record's that decodes, else None."""
    some = None
    for (platform, encoding, language, nid), raw in records.items():
        if nid != name_id:
            continue
        try:
            text = raw.decode(codec(platform, encoding, language))
        except UnicodeDecodeError:
            continue
        if (platform, language) in ((1, 0), (3, 0x409)):
            return text or None
        some = text
    return some or None


class NameTable(DefaultTable):
    """A ``name`` table held as its records (``records``: :func:`name_records`),
    compiled to the bytes fontTools writes for them (records sorted, equal strings
    stored once); ``getDebugName``, :func:`name_keys` and :func:`set_names` work on
    the records.  Any other attribute of fontTools' name table (``names``, ``setName``,
    ``toXML`` ...) makes fontTools' table of the records, which the font then
    compiles: code using the fontTools API gets it."""

    def __init__(self, records):
        super().__init__("name")
        self.records = records

    def getDebugName(self, name_id):  # noqa: N802 - the method fontTools calls on a table
        real = self.__dict__.get("_table")
        return real.getDebugName(name_id) if real else _debug_name(self.records, name_id)

    def compile(self, font):
        real = self.__dict__.get("_table")
        return real.compile(font) if real else name_bytes(self.records)

    def toXML(self, writer, font):  # noqa: N802 - the method fontTools calls on a table
        self.fonttools().toXML(writer, font)

    def fonttools(self):
        """fontTools' table of these records (made once; then what is compiled)."""
        real = self.__dict__.get("_table")
        if real is None:
            from fontTools.ttLib import newTable

            real = newTable("name")
            real.decompile(self.compile(None), None)
            self.__dict__["_table"] = real
        return real

    def __getattr__(self, attr):
        if attr.startswith("__") or attr in ("_table", "records"):
            raise AttributeError(attr)
        return getattr(self.fonttools(), attr)


def name_table(font, install=False):
    """``font["name"]``, a :class:`NameTable` where the table is not decompiled yet
    and its stored records are all read here (:func:`name_records`); with
    ``install``, it becomes the font's table.  None when the font has no name table.
    """
    if "name" not in font:
        return None
    if font.isLoaded("name") or font.reader is None:
        return font["name"]
    records = name_records(font.reader["name"])
    if records is None:
        return font["name"]
    table = NameTable(records)
    if install:
        font["name"] = table
    return table


def records_of(table):
    """The records of a :class:`NameTable` not handed to fontTools yet, else None."""
    fields = vars(table)
    return fields["records"] if "records" in fields and "_table" not in fields else None


def name_keys(table):
    """``(platform, encoding, language, name ID)`` of each record of a name table
    (a :class:`NameTable` or fontTools'), in its order."""
    records = records_of(table)
    if records is not None:
        return list(records)
    return [(r.platformID, r.platEncID, r.langID, r.nameID) for r in table.names]


def set_names(table, texts, where, drop=()):
    """Remove the records of the name IDs ``drop``, then give each name ID of
    ``texts`` ({name ID: text}) that text at each (platform, encoding, language) of
    ``where`` (in sorted order) and nowhere else, as fontTools' ``removeNames`` and
    ``setName`` do."""
    records = records_of(table)
    for nid in list(drop) + list(texts):
        if records is None:
            table.removeNames(nameID=nid)
        else:
            for key in [k for k in records if k[3] == nid]:
                del records[key]
    for nid, text in texts.items():
        for plat, enc, lang in sorted(where):
            if records is None:
                table.setName(text, nid, plat, enc, lang)
            else:
                records[(plat, enc, lang, nid)] = text.encode(codec(plat, enc, lang))


def name_bytes(records):
    """A format 0 name table of Windows Unicode ``records`` ((platform, encoding,
    language, name ID) -> string, or its encoded bytes) as fontTools compiles one:
    records sorted by those four numbers, UTF-16BE strings, each distinct string
    stored once."""
    keys = sorted(records)
    data = [struct.pack(">HHH", 0, len(keys), 6 + 12 * len(keys))]
    strings, at = [], {}
    size = 0
    for key in keys:
        text = records[key]
        text = text if isinstance(text, bytes) else text.encode("utf_16_be")
        if text not in at:
            at[text] = size
            strings.append(text)
            size += len(text)
        data.append(struct.pack(">HHHHHH", *key, len(text), at[text]))
    return b"".join(data + strings)
