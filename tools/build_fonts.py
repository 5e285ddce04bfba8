"""Rebuild the fonts shipped in morph/fonts/data/ (run by hand, not at install time).

Source: Noto Sans (SIL OFL 1.1, no reserved font name) from the PyPI package
``fontpkg-noto-sans``.  The variable font is instanced at wght=400, wdth=100 with
overlaps removed (skia-pathops), subset to Basic Latin + Latin-1, and written as:

- NotoSans-Regular.ttf  (TrueType, quadratic outlines: the default font)
- NotoSans-Regular.otf  (CFF, cubic outlines made with fontTools.qu2cu: the cubic test font)

Usage: pip install fontpkg-noto-sans skia-pathops && python tools/build_fonts.py
"""

from pathlib import Path

from fontTools import subset
from fontTools.fontBuilder import FontBuilder
from fontTools.pens.qu2cuPen import Qu2CuPen
from fontTools.pens.t2CharStringPen import T2CharStringPen
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib import TTFont
from fontTools.varLib import instancer

OUT = Path(__file__).resolve().parent.parent / "morph" / "fonts" / "data"
UNICODES = list(range(0x20, 0x7F)) + list(range(0xA0, 0x100))


def source_path():
    import fontpkg_noto_sans
    return Path(fontpkg_noto_sans.__file__).parent / "files" / "NotoSans[wdth,wght].ttf"


def build_ttf():
    font = TTFont(source_path())
    font = instancer.instantiateVariableFont(
        font, {"wght": 400, "wdth": 100}, overlap=instancer.OverlapMode.REMOVE)
    options = subset.Options()
    options.layout_features = ["kern"]
    options.hinting = False
    options.name_IDs = ["*"]
    sub = subset.Subsetter(options)
    sub.populate(unicodes=UNICODES)
    sub.subset(font)
    font.save(OUT / "NotoSans-Regular.ttf")
    return OUT / "NotoSans-Regular.ttf"


def build_otf(ttf_path):
    src = TTFont(ttf_path)
    gs = src.getGlyphSet()
    order = src.getGlyphOrder()
    charstrings = {}
    for name in order:
        pen = T2CharStringPen(src["hmtx"][name][0], gs)
        gs[name].draw(Qu2CuPen(pen, max_err=0.5, all_cubic=True))
        charstrings[name] = pen.getCharString()
    fb = FontBuilder(src["head"].unitsPerEm, isTTF=False)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap(src.getBestCmap())
    names = {n.nameID: n.toUnicode() for n in src["name"].names if n.platformID == 3}
    fb.setupCFF(names.get(6, "NotoSans-Regular"), {"FullName": names.get(4, "Noto Sans")},
                charstrings, {})
    fb.setupHorizontalMetrics({n: src["hmtx"][n] for n in order})
    hhea = src["hhea"]
    fb.setupHorizontalHeader(ascent=hhea.ascent, descent=hhea.descent)
    fb.setupNameTable({"familyName": "Noto Sans CFF", "styleName": "Regular",
                       "copyright": names.get(0, ""), "licenseDescription": names.get(13, "")})
    os2 = src["OS/2"]
    fb.setupOS2(sTypoAscender=os2.sTypoAscender, sTypoDescender=os2.sTypoDescender,
                usWinAscent=os2.usWinAscent, usWinDescent=os2.usWinDescent)
    fb.setupPost()
    fb.save(OUT / "NotoSans-Regular.otf")


if __name__ == "__main__":
    OUT.mkdir(parents=True, exist_ok=True)
    build_otf(build_ttf())
    print("wrote", sorted(p.name for p in OUT.iterdir()))
