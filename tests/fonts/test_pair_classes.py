"""Class kerning built with its rows packed (morph.fonts.pair_classes) against
fontTools' own build of the same feature file: the same GSUB/GPOS/GDEF bytes, the
same records when the packed rows are read, otlLib's build where a row cannot be
packed (device tables, a value out of range)."""

import io

import pytest
from fontTools.feaLib.builder import addOpenTypeFeaturesFromString
from fontTools.misc.xmlWriter import XMLWriter
from fontTools.otlLib import builder as otl
from fontTools.ttLib import TTFont

from morph.fonts.pair_classes import packed_class_pairs

GLYPHS = [".notdef"] + ["g%02d" % k for k in range(40)]

#: class pairs in two subtables (an explicit break, then classes that overlap the
#: first ones, a break again), a glyph pair, value records of one and of two sides
#: (of all four fields, of the advance, of the y placement only), zero pairs (one
#: subtable of zero pairs only: no value record)
FEATURES = """
languagesystem DFLT dflt;
@L1 = [g00 g01 g02];
@L2 = [g03 g04];
@L3 = [g05];
@R1 = [g10 g11];
@R2 = [g12 g13 g14];
@R3 = [g15];
@L4 = [g00 g06];
@R4 = [g10 g16 g17];
feature kern {
    lookup kern_a {
        pos g20 g21 -7;
        pos @L1 @R1 -40;
        pos @L1 @R2 25;
        pos @L2 @R3 <3 -4 -50 6>;
        pos @L3 @R1 0;
        pos @L2 <1 2 3 4> @R2 <-5 -6 -7 -8>;
        subtable;
        pos @L4 @R4 -12;
        pos @L3 @R4 32767;
        pos @L4 @R1 -32768;
        subtable;
        pos @L1 @R3 <0 7 0 0>;
        pos @L2 @R3 <0 -9 0 0>;
        subtable;
        pos @L1 @R1 0;
    } kern_a;
} kern;
"""


def _font(text, packed):
    font = TTFont()
    font.setGlyphOrder(GLYPHS)
    if packed:
        with packed_class_pairs():
            addOpenTypeFeaturesFromString(font, text)
    else:
        addOpenTypeFeaturesFromString(font, text)
    return font


def _compiled(font):
    return {tag: font[tag].compile(font) for tag in ("GDEF", "GSUB", "GPOS") if tag in font}


def _class_subtables(font):
    return [st for lookup in font["GPOS"].table.LookupList.Lookup for st in lookup.SubTable
            if st.Format == 2]


def _xml(font):
    out = io.BytesIO()
    writer = XMLWriter(out)
    font["GPOS"].toXML(writer, font)
    writer.close()
    return out.getvalue()


def test_packed_rows_compile_to_fonttools_bytes():
    packed, plain = _font(FEATURES, True), _font(FEATURES, False)
    subtables = _class_subtables(packed)
    assert len(subtables) == 5   # the explicit breaks, the classes that overlap
    assert all(type(r).__name__ == "PackedClass1Record"
               for st in subtables for r in st.Class1Record)
    assert _compiled(packed) == _compiled(plain)


def test_packed_rows_read_as_fonttools_records():
    packed, plain = _font(FEATURES, True), _font(FEATURES, False)
    assert _xml(packed) == _xml(plain)   # every record, read from the packed rows
    assert _compiled(packed) == _compiled(plain)   # and the decoded rows compiled
    # a decoded record changed is compiled as it is
    st = _class_subtables(packed)[0]
    st.Class1Record[1].Class2Record[1].Value1.XAdvance += 1
    assert _compiled(packed)["GPOS"] != _compiled(plain)["GPOS"]


@pytest.mark.parametrize("rule", ["pos @L1 <0 0 -40 0 <device 11 -1> <device NULL> "
                                  "<device NULL> <device NULL>> @R1;",
                                  "pos @L1 @R1 40000;"])
def test_rows_left_to_otllib(rule):
    """A device table or a value out of 16 bits: otlLib builds the subtable (and
    fails where it fails)."""
    text = FEATURES.replace("pos @L1 @R1 -40;", rule)
    packed, plain = _font(text, True), _font(text, False)
    assert not any(type(r).__name__ == "PackedClass1Record"
                   for st in _class_subtables(packed)[:1] for r in st.Class1Record)
    try:
        expected = _compiled(plain)
    except Exception as exc:  # noqa: BLE001 - otlLib's error, whatever it is
        with pytest.raises(type(exc)):
            _compiled(packed)
    else:
        assert _compiled(packed) == expected


def test_builder_restored():
    original = otl.buildPairPosClassesSubtable
    with pytest.raises(ZeroDivisionError):
        with packed_class_pairs():
            assert otl.buildPairPosClassesSubtable is not original
            raise ZeroDivisionError
    assert otl.buildPairPosClassesSubtable is original


def test_packing_checked_against_the_installed_fonttools(monkeypatch):
    """The packing is used only where its self-check agrees with fontTools' own
    build (true of the installed fontTools); a packing that writes other bytes
    fails the check, and otlLib then builds every subtable: the same font."""
    from morph.fonts import pair_classes

    assert pair_classes._agrees(otl.buildPairPosClassesSubtable)
    real = pair_classes._packed_subtable

    def wrong(*args):   # the second side's value format dropped
        st = real(*args)
        st.ValueFormat2 = 0
        return st

    monkeypatch.setattr(pair_classes, "_packed_subtable", wrong)
    pair_classes._agrees.cache_clear()
    try:
        packed, plain = _font(FEATURES, True), _font(FEATURES, False)
        assert not any(type(r).__name__ == "PackedClass1Record"
                       for st in _class_subtables(packed) for r in st.Class1Record)
        assert _compiled(packed) == _compiled(plain)
    finally:
        pair_classes._agrees.cache_clear()
