"""Class kerning (GPOS pair adjustment, format 2) built by feaLib with its class
matrix held as bytes.

A format 2 ``PairPos`` subtable stores one value record for every pair of a
first class and a second class: Relief SingleLine's kern feature has two such
subtables of 43 x 62 and 37 x 50 classes, 4,516 records.  fontTools' otlLib
builds each as two ``otTables`` objects (a ``Class2Record`` and its
``ValueRecord``) and its table compiler compiles each as a table of its own (a
dozen attribute tests and a dictionary copy a record): three quarters of the
compilation of Relief's GPOS table and a third of its feaLib build.

:func:`packed_class_pairs` has feaLib build those subtables with each first
class's row of records held as the bytes the compiler writes for it
(:func:`packed_record`), for value records of the four plain fields
(placement and advance, 16-bit integers each; no device tables): the same
subtable, the same bytes in the font.  Any other subtable (device tables or
variations in its records, a value that is no integer in range, more than 65,536
glyphs) is built by otlLib as usual.  A row read as records (``Class2Record``:
ttx, an overflow split of the lookup) is decoded into them, and then compiled
as they are.
"""

import contextlib
import functools

__all__ = ["packed_class_pairs", "packed_record"]

#: the value record fields written as signed 16-bit integers, by format bit, in
#: the order of the record (fontTools' ``valueRecordFormat``)
_PLAIN_FIELDS = ((0x0001, "XPlacement"), (0x0002, "YPlacement"), (0x0004, "XAdvance"),
                 (0x0008, "YAdvance"))


@contextlib.contextmanager
def packed_class_pairs():
    """Within the block, otlLib's ``buildPairPosClassesSubtable`` (which feaLib's
    pair positioning builder calls for each class subtable) builds its subtable
    with packed rows where it can (:func:`_packed_subtable`) and where the packing
    agrees with the installed fontTools (:func:`_agrees`); restored after."""
    from fontTools.otlLib import builder as otl

    original = otl.buildPairPosClassesSubtable

    # noqa reason: the argument names are otlLib's, which otlLib's callers pass by keyword
    def build(pairs, glyphMap, valueFormat1=None, valueFormat2=None):  # noqa: N803 - see above
        st = (_packed_subtable(pairs, glyphMap, valueFormat1, valueFormat2)
              if _agrees(original) else None)
        return original(pairs, glyphMap, valueFormat1, valueFormat2) if st is None else st

    otl.buildPairPosClassesSubtable = build
    try:
        yield
    finally:
        otl.buildPairPosClassesSubtable = original


@functools.lru_cache(maxsize=None)
def _agrees(original):
    """Whether packed rows compile to the bytes of ``original`` (otlLib's own
    ``buildPairPosClassesSubtable``) with the installed fontTools: a small subtable
    (two value formats, a value record of one side only, a class of one glyph)
    built both ways and compiled in a lookup, once per process, when the first class
    subtable is due.  False where they differ or the packing raises (a fontTools
    whose classes or table compiler this module does not follow): then otlLib
    builds every subtable."""
    from fontTools.otlLib import builder as otl
    from fontTools.ttLib import TTFont
    from fontTools.ttLib.tables.otBase import OTTableWriter, ValueRecord

    font = TTFont()
    font.setGlyphOrder([".notdef", "a", "b", "c", "d"])
    glyph_map = {g: k for k, g in enumerate(font.getGlyphOrder())}

    def value(**fields):
        record = ValueRecord()
        record.__dict__.update(fields)
        return record

    pairs = {(("a", "b"), ("c",)): (value(XAdvance=-40), None),
             (("a", "b"), ("d",)): (value(XPlacement=3, XAdvance=5), value(YAdvance=-7)),
             (("c",), ("c",)): (value(XAdvance=12), None)}

    def compiled(subtable):
        writer = OTTableWriter(tableTag="GPOS")
        otl.buildLookup([subtable]).compile(writer, font)
        return writer.getAllData()

    try:
        return compiled(_packed_subtable(pairs, glyph_map, None, None)) == compiled(
            original(pairs, glyph_map))
    except Exception:  # noqa: BLE001 - any failure of the packing means: do not pack
        return False


def _value_format(forced, values, side):
    """otlLib's value format of one side: ``forced``, else the union of the
    formats of that side's value records."""
    if forced is not None:
        return forced
    mask = 0
    for value in values:
        if value is not None and value[side] is not None:
            mask |= value[side].getFormat()
    return mask


def _packed_subtable(pairs, glyph_map, format1, format2):
    """otlLib's ``buildPairPosClassesSubtable`` (the same classes, coverage and
    value formats) with its rows packed; None where a row cannot be packed (the
    module docstring): otlLib builds that subtable."""
    import numpy as np
    from fontTools.otlLib.builder import ClassDefBuilder, buildCoverage
    from fontTools.ttLib.tables import otTables as ot

    if len(glyph_map) > 0x10000:   # format 4 (24-bit glyph ids)
        return None
    format1 = _value_format(format1, pairs.values(), 0)
    format2 = _value_format(format2, pairs.values(), 1)
    if (format1 | format2) & ~0xF:
        return None
    fields = [[name for bit, name in _PLAIN_FIELDS if f & bit] for f in (format1, format2)]
    coverage = set()
    class_def1, class_def2 = ClassDefBuilder(useClass0=True), ClassDefBuilder(useClass0=False)
    for gc1, gc2 in sorted(pairs):
        coverage.update(gc1)
        class_def1.add(gc1)
        class_def2.add(gc2)
    classes1, classes2 = class_def1.classes(), class_def2.classes()
    row1 = {c: k for k, c in enumerate(classes1)}
    row2 = {c: k for k, c in enumerate(classes2)}
    width = len(fields[0]) + len(fields[1])
    cells = np.zeros((len(classes1), len(classes2), width), np.int64)
    for (gc1, gc2), values in pairs.items():
        cell = []
        for value, names in zip(values, fields):
            got = value.__dict__ if value is not None else {}
            cell.extend(got.get(name, 0) for name in names)
        if any(type(v) is not int or not -0x8000 <= v <= 0x7FFF for v in cell):
            return None   # otlLib writes it, or names the bad value
        cells[row1[gc1], row2[gc2]] = cell
    st = ot.PairPos()
    st.Format = 2
    st.ValueFormat1, st.ValueFormat2 = format1, format2
    st.Coverage = buildCoverage(coverage, glyph_map)
    st.ClassDef1, st.ClassDef2 = class_def1.build(), class_def2.build()
    packed = cells.astype(">i2")
    st.Class1Record = [packed_record(row.tobytes(), len(classes2), format1, format2)
                       for row in packed]
    st.Class1Count, st.Class2Count = len(classes1), len(classes2)
    return st


def packed_record(data, count, format1, format2):
    """A ``Class1Record`` of a format 2 ``PairPos`` (see the module docstring): its
    ``Class2Record`` row held as the bytes fontTools' compiler writes for it
    (``count`` records of the value formats ``format1`` and ``format2``, plain
    fields only), compiled as those bytes; reading its ``Class2Record`` decodes
    them into fontTools' records (kept, and compiled as fontTools compiles them)."""
    record = _packed_class()()
    record.__dict__["_packed"] = (data, count, format1, format2)
    return record


def _packed_class():
    """The class of :func:`packed_record`'s records, a subclass of fontTools'
    ``otTables.Class1Record`` (which its module builds as it loads), made once."""
    global _PACKED
    if _PACKED is not None:
        return _PACKED
    from fontTools.ttLib.tables import otTables as ot

    class PackedClass1Record(ot.Class1Record):
        def compile(self, writer, font):
            if "Class2Record" in self.__dict__:   # decoded: compiled as fontTools does
                return super().compile(writer, font)
            data, count = self._packed[:2]
            writer["Class2Count"].setValue(count)
            writer.writeData(data)
            return None

        def __getattr__(self, attr):
            if attr != "Class2Record" or "_packed" not in self.__dict__:
                return super().__getattr__(attr)
            self.__dict__["Class2Record"] = records = _decoded(*self._packed)
            return records

    _PACKED = PackedClass1Record
    return _PACKED


_PACKED = None


def _decoded(data, count, format1, format2):
    """The ``Class2Record`` objects of a packed row, as otlLib builds them."""
    import numpy as np
    from fontTools.ttLib.tables import otTables as ot
    from fontTools.ttLib.tables.otBase import ValueRecord

    fields = [[name for bit, name in _PLAIN_FIELDS if f & bit] for f in (format1, format2)]
    values = np.frombuffer(data, ">i2").reshape(count, len(fields[0]) + len(fields[1])).tolist()
    out = []
    for row in values:
        rec = ot.Class2Record()
        at = 0
        for attr, fmt, names in (("Value1", format1, fields[0]), ("Value2", format2, fields[1])):
            if not fmt:
                setattr(rec, attr, None)
                continue
            value = ValueRecord(valueFormat=fmt)
            for name in names:
                setattr(value, name, row[at])
                at += 1
            setattr(rec, attr, value)
        out.append(rec)
    return out
