"""Build the test subset of Relief SingleLine (SIL OFL 1.1, see OFL.txt / AUTHORS.txt).

    python tests/data/relief/make_subset.py SOURCE.ufo
    MORPH_RELIEF_UFO=SOURCE.ufo python tests/data/relief/make_subset.py

Source: Relief-SingleLine.ufo (https://github.com/isdat-type/Relief-SingleLine), 584
skeleton glyphs, every contour an open cubic path.  Kept: A-Z, a-z, 0-9, space,
period, comma, hyphen, the composites eacute, i, j and ordfeminine (a scaled 'a':
decomposed when stroked), g.ss01, and every base glyph they use; kerning and groups
restricted to those glyphs.  The features are rebuilt from the source's lines for the
kept glyphs: the ss01 substitution and the mark feature with its explicit anchors
(kerning comes from kerning.plist, which ufo2ft turns into a kern feature).
"""

import os
import re
import sys
from pathlib import Path

import ufoLib2

HERE = Path(__file__).resolve().parent
#: the full font: the first argument, else the environment variable MORPH_RELIEF_UFO
DEFAULT_SOURCE = os.environ.get("MORPH_RELIEF_UFO")
NAMES = ([chr(c) for c in range(ord("A"), ord("Z") + 1)]
         + [chr(c) for c in range(ord("a"), ord("z") + 1)]
         + "zero one two three four five six seven eight nine space period comma hyphen "
           "eacute i j ordfeminine g.ss01".split())


def closure(font, names):
    out, todo = [], list(names)
    while todo:
        n = todo.pop(0)
        if n in out:
            continue
        out.append(n)
        todo.extend(c.baseGlyph for c in font[n].components)
    return out


def main(source=DEFAULT_SOURCE):
    if not source:
        sys.exit("make_subset.py: give the full Relief-SingleLine.ufo as the argument "
                 "or in MORPH_RELIEF_UFO")
    src = ufoLib2.Font.open(source)
    keep = closure(src, NAMES)
    keep_set = set(keep)
    font = ufoLib2.Font(info=src.info)
    for n in [g for g in src.keys() if g in keep_set]:
        font.layers.defaultLayer.insertGlyph(src[n], name=n, overwrite=False, copy=True)
    groups = {}
    for gname, members in src.groups.items():
        kept = [m for m in members if m in keep_set]
        if kept:
            groups[gname] = kept
    font.groups.update(groups)

    def ok(side):
        return side in keep_set or side in groups

    font.kerning.update({pair: v for pair, v in src.kerning.items()
                         if ok(pair[0]) and ok(pair[1])})
    lib = dict(src.lib)
    lib["public.glyphOrder"] = [n for n in src.lib.get("public.glyphOrder", []) if n in keep_set]
    lib["public.skipExportGlyphs"] = [n for n in src.lib.get("public.skipExportGlyphs", [])
                                      if n in keep_set]
    lib["public.postscriptNames"] = {k: v for k, v in src.lib.get("public.postscriptNames",
                                                                  {}).items() if k in keep_set}
    font.lib.update(lib)

    text = src.features.text
    marks = [ln.strip() for ln in text.splitlines()
             if ln.strip().startswith("markClass")
             and re.search(r"\[(\S+)\]", ln).group(1) in keep_set]
    classes = {re.search(r"@(\w+);", m).group(1) for m in marks}
    bases = []
    for ln in text.splitlines():
        words = ln.split()
        if len(words) > 2 and words[:2] == ["pos", "base"] and words[2] in keep_set:
            parts = [a for a, c in re.findall(r"(<anchor [-\d]+ [-\d]+> mark @(\w+))", ln)
                     if c in classes]
            if parts:
                bases.append("pos base %s %s;" % (words[2], " ".join(parts)))
    fea = ["# Subset of the Relief SingleLine features (see make_subset.py).",
           "languagesystem DFLT dflt;", "languagesystem latn dflt;", ""]
    fea += marks + ["", "feature ss01 {", "\tsub g by g.ss01;", "} ss01;", "",
                    "feature mark {", "\tlookup mark_latn {"]
    fea += ["\t\t" + b for b in bases] + ["\t} mark_latn;", "} mark;", ""]
    font.features.text = "\n".join(fea)
    out = HERE / "Relief-SingleLine-subset.ufo"
    font.save(out, overwrite=True)
    print("wrote %s: %d glyphs, %d kerning pairs, %d groups"
          % (out, len(font), len(font.kerning), len(font.groups)))


if __name__ == "__main__":
    main(*sys.argv[1:])
