"""Whether ufo2ft's default feature writers would add anything to a font's feature
file: where they add nothing, :mod:`morph.fonts.tables_static` builds the layout
tables from the feature file alone (feaLib), without importing ufo2ft.

ufo2ft 3's writers (``CursFeatureWriter``, ``KernFeatureWriter``,
``MarkFeatureWriter``, ``GdefFeatureWriter``; MIT licence) run in "skip" mode: a
feature the file already has is left as it is, and each writes only from its
inputs.  :func:`writers_add_nothing` answers from the same inputs, conservatively
(a font it cannot vouch for goes to ufo2ft):

- kerning (kern, dist): no kerning, or a ``kern`` feature in the file and no
  script the 'dist' feature serves (Indic, USE, Khmer, Myanmar) among the scripts
  the kern writer knows the font by (its code points of a single script and the
  file's ``languagesystem`` scripts); a font with kerning and no kern feature has
  it written by :mod:`morph.fonts.kern_static` where that covers it;
- mark attachment (mark, mkmk, abvm, blwm): no anchors, or ``mark`` and ``mkmk``
  features in the file (or written by :mod:`morph.fonts.mark_static`) and no
  above/below-base mark script (Indic, USE, Khmer) that the writer would serve:
  of the file's ``languagesystem`` scripts where it has some, else among the
  font's code points' script extensions;
- cursive attachment (curs): no anchor named ``entry``/``exit`` (or ``entry.*``,
  ``exit.*``), or a ``curs`` feature in the file;
- GDEF (glyph classes, ligature carets): no ``caret_`` / ``vcaret_`` anchor (the
  glyph classes come from a lib key the light reader does not take);
- no insertion marker (a comment "# Automatic Code") anywhere in the file.
"""

import re

__all__ = ["writers_add_nothing", "feature_tags", "DIST_OR_ABVM_SCRIPTS"]

#: ufo2ft.constants' INDIC_SCRIPTS and USE_SCRIPTS, with Khmer and Myanmar: the
#: scripts of the 'dist' feature (kern writer) and of 'abvm' / 'blwm' (mark writer)
DIST_OR_ABVM_SCRIPTS = frozenset(
    "Beng Deva Gujr Guru Knda Mlym Orya Sinh Taml Telu "
    "Adlm Ahom Bali Batk Bhks Brah Bugi Buhd Cakm Cham Chrs Cpmn Diak Dogr Dupl Egyp "
    "Elym Gong Gonm Gran Hano Hmng Hmnp Java Kali Kawi Khar Khoj Kits Kthi Lana Lepc "
    "Limb Mahj Maka Mand Mani Marc Medf Modi Mong Mtei Mult Nagm Nand Newa Nkoo Ougr "
    "Phag Phlp Plrd Rjng Rohg Saur Shrd Sidd Sind Sogd Sogo Soyo Sund Sylo Tagb Takr "
    "Tale Tavt Tfng Tglg Tibt Tirh Tnsa Toto Vith Wcho Yezi Zanb Khmr Mymr".split()
    + ["Nko "])

_MARKER = re.compile(r"automatic\s+code", re.IGNORECASE)


def feature_tags(tree):
    """The tags of the feature blocks of feaLib's tree ``tree`` (None: none)."""
    return _fea_statements(tree)[0] if tree is not None else set()


def _fea_statements(tree):
    from fontTools.feaLib import ast

    tags = {s.name for s in tree.statements if isinstance(s, ast.FeatureBlock)}
    scripts = {s.script for s in tree.statements
               if isinstance(s, ast.LanguageSystemStatement) and s.script != "DFLT"}
    return tags, scripts


def _iso_scripts(ot_tags):
    from fontTools import unicodedata

    return {unicodedata.ot_tag_to_script(t) for t in ot_tags}


def _anchor_names(glyphs):
    return {a.name for g in glyphs for a in g.anchors if a.name}


def writers_add_nothing(font, tree, glyphs, codes, kern_written=False, mark_written=False):
    """None where ufo2ft's feature writers would add nothing to the feature file
    ``tree`` (feaLib's parse of ``font``'s, None for no file) of the font whose
    exported glyphs are ``glyphs`` and whose cmap has the code points ``codes``;
    else the reason (see the module docstring).  ``kern_written``: the kern
    feature ufo2ft would write is written already (:mod:`morph.fonts.kern_static`),
    so that kerning without a kern feature in the file is no reason;
    ``mark_written``: the same for the mark and mkmk features
    (:mod:`morph.fonts.mark_static`) and anchors."""
    text = font.features.text or ""
    if _MARKER.search(text):
        return "an insertion marker in the feature file"
    tags, fea_scripts = _fea_statements(tree) if tree is not None else (set(), set())
    names = _anchor_names(glyphs)
    if any(n.startswith(("caret_", "vcaret_")) for n in names):
        return "ligature caret anchors (GDEF)"
    if "curs" not in tags and any(n.startswith(("entry", "exit")) for n in names):
        return "cursive anchors without a curs feature"
    if font.kerning and "kern" not in tags and not kern_written:
        return "kerning without a kern feature"
    if names and not {"mark", "mkmk"} <= tags and not mark_written:
        return "anchors without mark and mkmk features"
    if not font.kerning and not names:
        return None
    fea_iso = _iso_scripts(fea_scripts)
    if font.kerning and "kern" in tags and "dist" not in tags and (
            _known_scripts(codes, fea_iso) & DIST_OR_ABVM_SCRIPTS):
        return "kerning in a script of the dist feature"
    if names and not {"abvm", "blwm"} <= tags and _abvm_scripts(codes, fea_iso):
        return "anchors in a script of the abvm / blwm features"
    return None


def _extensions(code):
    from fontTools import unicodedata

    aliases = {"Hira": "Hrkt", "Kana": "Hrkt"}   # ufo2ft's UNICODE_SCRIPT_ALIASES
    return {aliases.get(s, s) for s in unicodedata.script_extension(chr(code))}


def _known_scripts(codes, fea_iso):
    """The kern writer's ``guessFontScripts``: the scripts of the code points of a
    single script, and the feature file's."""
    out = set(fea_iso)
    for code in codes:
        ext = _extensions(code)
        if len(ext) == 1:
            out |= ext
    return out


def _abvm_scripts(codes, fea_iso):
    """Whether the mark writer's ``_getAbvmGlyphs`` may find glyphs: its scripts
    (cut to the feature file's where it names some) among the code points' script
    extensions."""
    scripts = DIST_OR_ABVM_SCRIPTS
    if fea_iso:
        scripts = scripts & fea_iso
    return bool(scripts) and any(_extensions(c) & scripts for c in codes)
