"""The kern feature ufo2ft's ``KernFeatureWriter`` writes from a static font's
kerning and groups, for the fonts whose kerning is all left to right: written into
feaLib's tree of the feature file as that writer writes it (the same class
definitions, lookups, feature block and their places), so that feaLib builds the
same GPOS table.  A port of ufo2ft 3's writer (``kernFeatureWriter.py``, MIT
licence) restricted to what :meth:`KernWriter.reason` vouches for:

- no GDEF table block in the feature file (ufo2ft would read mark classes from it
  and split the kerning of marks apart);
- no glyph of a right-to-left script or of a script of the 'dist' feature among
  the scripts the writer gives the glyphs (the code points' script extensions cut
  to the scripts it knows the font by, carried to the glyphs the GSUB table
  substitutes for them), and no code point of right-to-left bidi type;
- no 'dist' feature in the file, no insertion marker (checked by
  :mod:`morph.fonts.writers_static`).

Anything else leaves the font to ufo2ft (:func:`morph.fonts.tables_static.
left_to_ufo2ft`).  tests/fonts/test_kern_static.py compares the written feature
text with ufo2ft's writer's on fonts of several scripts, with class and glyph
kerning, exceptions, glyphs reached through GSUB, glyphs not exported.
"""

import itertools

__all__ = ["KernWriter"]

COMMON_SCRIPT = "Zyyy"
DFLT_SCRIPTS = frozenset(("Zyyy", "Zinh"))
_ALIASES = {"Hira": "Hrkt", "Kana": "Hrkt"}   # ufo2ft's UNICODE_SCRIPT_ALIASES
SIDE1_PREFIX, SIDE2_PREFIX = "public.kern1.", "public.kern2."


def _extensions(code):
    from fontTools import unicodedata

    return {_ALIASES.get(s, s) for s in unicodedata.script_extension(chr(code))}


def _direction(script):
    from fontTools.unicodedata import script_horizontal_direction

    return "Auto" if script == COMMON_SCRIPT else script_horizontal_direction(script, "LTR")


class _Pair:
    """ufo2ft's ``KerningPair``: sides a glyph name or a tuple of names (a class)."""

    __slots__ = ("side1", "side2", "value")

    def __init__(self, side1, side2, value):
        self.side1, self.side2, self.value = side1, side2, value

    def key(self):   # glyph pairs first, then glyph-class, class-glyph, class-class
        return (isinstance(self.side1, tuple), isinstance(self.side2, tuple),
                self.side1, self.side2)

    def glyphs(self, side):
        s = self.side1 if side == 1 else self.side2
        return s if isinstance(s, tuple) else (s,)


class KernWriter:
    """The kern feature of the light font ``font`` (exported glyph names in
    ``order``, the cmap ``cmap``: code point -> glyph name) for feaLib's tree
    ``tree`` of its feature file (None: none).  :attr:`reason` says why ufo2ft
    must write it (None: :meth:`write` writes it as ufo2ft does)."""

    def __init__(self, font, tree, order, cmap):
        from fontTools.feaLib import ast

        self.font, self.order, self.cmap = font, order, cmap
        self.glyph_set = set(order)
        self.tree = tree if tree is not None else ast.FeatureFile()
        self.reason = None
        if any(isinstance(s, ast.TableBlock) and s.name == "GDEF"
               for s in self.tree.statements):
            self.reason = "a GDEF table in the feature file (kerning of marks)"
            return
        self.pairs, self.membership = self._pairs()
        if not self.pairs:
            return
        self.glyph_scripts = self._glyph_scripts()
        from .writers_static import DIST_OR_ABVM_SCRIPTS

        scripts = set().union(*self.glyph_scripts.values()) if self.glyph_scripts else set()
        if any(_direction(s) == "RTL" for s in scripts) or scripts & DIST_OR_ABVM_SCRIPTS \
                or self._rtl_codes():
            self.reason = "kerning of right-to-left or dist scripts"

    # ------------------------------------------------------------ inputs

    def _rtl_codes(self):
        from fontTools import unicodedata

        return any(unicodedata.bidirectional(chr(c)) in ("R", "AL") for c in self.cmap)

    def _languages(self):
        """ufo2ft's ``getScriptLanguageSystems``: ISO script -> [(OT tag,
        languages)], in the file's order (DFLT too where ``dflt``)."""
        from fontTools import unicodedata
        from fontTools.feaLib import ast

        by_tag = {}
        for s in self.tree.statements:
            if isinstance(s, ast.LanguageSystemStatement):
                by_tag.setdefault(s.script, []).append(s.language)
        out = {}
        for tag, languages in by_tag.items():
            out.setdefault(unicodedata.ot_tag_to_script(tag), []).append((tag, languages))
        return out

    def _glyph_scripts(self):
        """glyph name -> the scripts ufo2ft's writer gives it (``classifyGlyphs``
        of the code points' scripts, closed over the GSUB table)."""
        from fontTools import unicodedata
        from fontTools.feaLib import ast

        # ufo2ft's guessFontScripts: the file's languagesystem scripts but DFLT, and
        # the scripts of the glyphs' code points of a single script
        known = {unicodedata.ot_tag_to_script(s.script) for s in self.tree.statements
                 if isinstance(s, ast.LanguageSystemStatement) and s.script != "DFLT"}
        for name in self.order:
            g = self.font[name] if name in self.font else None
            for code in (g.unicodes if g is not None else ()):
                ext = _extensions(code)
                if len(ext) == 1:
                    known |= ext
        sets, neutral = {}, set()
        for code, name in self.cmap.items():
            keys = ({COMMON_SCRIPT} if not known
                    else _extensions(code) & (known | DFLT_SCRIPTS) or None)
            if keys is None:
                neutral.add(name)
            for k in keys or ():
                sets.setdefault(k, set()).add(name)
        gsub = self._gsub()
        if gsub is not None:
            if neutral:
                _close(gsub, neutral)
            for glyphs in sets.values():
                s = glyphs | neutral
                _close(gsub, s)
                glyphs.update(s - neutral)
        out = {}
        for script, glyphs in sets.items():
            for g in glyphs:
                out.setdefault(g, set()).add(script)
        return out

    def _gsub(self):
        from fontTools.ttLib import TTFont

        from .deferred import feature_builder

        tt = TTFont()
        tt.setGlyphOrder(self.order)
        feature_builder().addOpenTypeFeatures(tt, self.tree, tables={"GSUB"})
        return tt.get("GSUB")

    def _groups(self):
        """ufo2ft's ``collectKerningGroups`` of one font: each side's groups (members
        in the font, sorted) and glyph -> group name without its prefix."""
        groups = ({}, {})
        membership = ({}, {})
        for name, members in self.font.groups.items():
            members = {g for g in members if g in self.glyph_set}
            if not members:
                continue
            for side, prefix in enumerate((SIDE1_PREFIX, SIDE2_PREFIX)):
                if name.startswith(prefix):
                    if members & membership[side].keys():   # ufoLib2 refuses such groups
                        continue
                    if name not in groups[side]:
                        groups[side][name] = tuple(sorted(members))
                        for m in members:
                            membership[side][m] = name[len(prefix):]
        return groups, membership

    def _pairs(self):
        """ufo2ft's ``getKerningPairs``: pairs of known glyphs and groups, zero
        class-to-class pairs dropped, values rounded to integers."""
        from fontTools.misc.roundTools import otRound

        (side1, side2), membership = self._groups()
        out = []
        for (a, b), value in self.font.kerning.items():
            first, second = a in side1, b in side2
            if (not first and a not in self.glyph_set) or (not second and b not in self.glyph_set):
                continue
            if first and second and value == 0:
                continue
            out.append(_Pair(side1[a] if first else a, side2[b] if second else b,
                             otRound(value)))
        return out, membership

    # ------------------------------------------------------------ writing

    def write(self):
        """The kern feature, its lookups and class definitions inserted into the
        tree as ufo2ft inserts them; False where there is nothing to write."""
        from fontTools.feaLib import ast

        if not getattr(self, "pairs", None):
            return False
        per_script = _split(self.pairs, self.glyph_scripts)
        class_defs, names = self._class_definitions(per_script)
        lookups = {}
        for scripts, pairs in per_script.items():
            name = ("kern_%s" % "_".join(scripts)).replace(COMMON_SCRIPT, "Default")
            lookup = ast.LookupBlock(name)
            lookup.statements.append(ast.LookupFlagStatement(8))   # IgnoreMarks
            for pair in pairs:
                lookup.statements.append(_rule(pair, names))
            for script in scripts:
                lookups.setdefault(script, {})[name] = lookup
        for script in list(lookups):
            for name, lookup in list(lookups[script].items()):
                if len(lookup.statements) <= 1:
                    del lookups[script][name]
            if not lookups[script]:
                del lookups[script]
        if not lookups:
            return False
        feature = ast.FeatureBlock("kern")
        self._register(feature, lookups)
        if not feature.statements:
            return False
        used = {s.lookup for s in feature.statements
                if isinstance(s, ast.LookupReferenceStatement)}
        blocks = []
        for _, group in sorted(lookups.items()):
            blocks.extend(lk for lk in group.values() if lk in used and lk not in blocks)
        self._insert([c for _, c in sorted(class_defs.items())], blocks, feature)
        return True

    def _insert(self, class_defs, lookups, feature):
        """ufo2ft's ``_insert`` without insertion markers: the feature last, its
        lookups before it, the class definitions first (then an empty comment)."""
        from fontTools.feaLib import ast

        st = self.tree.statements
        at = len(st)
        st = st[:at] + lookups + [feature]
        others = list(class_defs) + [ast.Comment("")] if class_defs else []
        self.tree.statements = others + st

    def _class_definitions(self, per_script):
        """ufo2ft's ``makeAllGlyphClassDefinitions``: a class for each group side
        used (the common script's first), named "kern1.<scripts>.<group>"."""
        from fontTools.feaLib import ast

        taken = {c.name for c in _class_definitions(self.tree)}
        defs, names = {}, ({}, {})

        def add(side, group, script):
            if group in names[side - 1]:
                return
            name = _fea_class_name("kern%d.%s.%s" % (
                side, script, self.membership[side - 1][group[0]]), taken)
            taken.add(name)
            cdef = ast.GlyphClassDefinition(name, ast.GlyphClass(list(group)))
            names[side - 1][group] = defs[name] = cdef

        common = [(s, p) for s, p in per_script.items() if set(s) == {COMMON_SCRIPT}]
        rest = [(s, p) for s, p in sorted(per_script.items()) if set(s) != {COMMON_SCRIPT}]
        for scripts, pairs in common + rest:
            script = "_".join(scripts).replace(COMMON_SCRIPT, "Default")
            for pair in pairs:
                if isinstance(pair.side1, tuple):
                    add(1, pair.side1, script)
                if isinstance(pair.side2, tuple):
                    add(2, pair.side2, script)
        return defs, names

    def _register(self, feature, lookups):
        """ufo2ft's ``_registerLookups`` for the kern feature of left-to-right
        scripts: the common lookups and every script's under DFLT, then each
        script's tags with the common lookups first, for every language the file
        names for the tag."""
        from fontTools import unicodedata

        languages = {tag: langs for pairs in self._languages().values()
                     for tag, langs in pairs}
        dflt = []
        if COMMON_SCRIPT in lookups:
            dflt.extend(lk for lk in lookups[COMMON_SCRIPT].values() if lk not in dflt)
        ltr = []
        for script, group in sorted(lookups.items()):
            if _direction(script) == "LTR":
                ltr.extend(group.values())
        dflt.extend(lk for lk in ltr if lk not in dflt)
        if dflt:
            _add_references(feature, dflt, "DFLT", languages.get("DFLT", ["dflt"]))
        for script in sorted(set(lookups) - DFLT_SCRIPTS):
            for tag in unicodedata.ot_tags_from_script(script):
                if feature.statements:
                    from fontTools.feaLib import ast

                    feature.statements.append(ast.Comment(""))
                these = {}
                for d in DFLT_SCRIPTS:
                    these.update(lookups.get(d, {}))
                these.update(lookups[script])
                _add_references(feature, list(these.values()), tag,
                                languages.get(tag, ["dflt"]))


def _close(gsub, glyphs):
    """ufo2ft's ``closeGlyphsOverGSUB``: ``glyphs`` grown by every glyph the GSUB
    table substitutes for them (fontTools' subsetter closure).

    A table whose lookups the scripts' features reach are all single, multiple,
    alternate or ligature substitutions (:func:`_substitutions`) is closed here: the
    subsetter's closure of those is the least set holding ``glyphs`` that has every
    glyph a substitution makes of its glyphs (a ligature's when all its components
    are in), which it reaches applying every lookup until no glyph comes in, as this
    does.  Contextual lookups (whose closure depends on their contexts) are left to
    fontTools.subset, which loads some sixty modules more."""
    rules = _substitutions(gsub.table)
    if rules is None:
        from fontTools import subset

        subsetter = subset.Subsetter()
        subsetter.glyphs = glyphs
        gsub.closure_glyphs(subsetter)
        return
    maps, ligatures = rules
    count = None
    while count != len(glyphs):
        count = len(glyphs)
        for glyph, made in maps:
            if glyph in glyphs:
                glyphs.update(made)
        glyphs.update(lig for components, lig in ligatures if glyphs.issuperset(components))


def _substitutions(table):
    """``(maps, ligatures)`` of the GSUB table ``table`` (fontTools' ``otTables``): the
    lookups the features of its scripts reference (the subsetter's
    ``collect_features`` / ``collect_lookups``), as ``(glyph, glyphs made of it)``
    pairs and ``(components, ligature)`` pairs; None where one of them is not a
    single, multiple, alternate or ligature substitution, or the table has feature
    variations."""
    if getattr(table, "FeatureVariations", None):
        return None
    if not table.LookupList:
        return [], []
    features = set()
    for record in (table.ScriptList.ScriptRecord if table.ScriptList else ()):
        script = record.Script
        for lang in [script.DefaultLangSys] + [r.LangSys for r in script.LangSysRecord]:
            if lang is not None:
                features.update(lang.FeatureIndex)
                if lang.ReqFeatureIndex != 0xFFFF:
                    features.add(lang.ReqFeatureIndex)
    records = table.FeatureList.FeatureRecord if table.FeatureList else []
    indices = {i for f in features if f < len(records)
               for i in records[f].Feature.LookupListIndex}
    lookups = table.LookupList.Lookup
    maps, ligatures = [], []
    for i in sorted(indices):
        if i >= len(lookups) or not lookups[i]:
            continue
        for st in lookups[i].SubTable:
            st = st.ExtSubTable if lookups[i].LookupType == 7 else st
            kind = getattr(st, "LookupType", None)
            if kind == 1:
                maps.extend((g, (v,)) for g, v in st.mapping.items())
            elif kind in (2, 3):
                maps.extend((st.mapping if kind == 2 else st.alternates).items())
            elif kind == 4:
                ligatures.extend(((g, *lig.Component), lig.LigGlyph)
                                 for g, ligs in st.ligatures.items() for lig in ligs)
            else:
                return None
    return maps, ligatures


def _class_definitions(block):
    from fontTools.feaLib import ast

    for s in block.statements:
        if isinstance(s, ast.GlyphClassDefinition):
            yield s
        elif isinstance(s, ast.Block):
            yield from _class_definitions(s)


def _fea_class_name(name, taken):
    """ufo2ft's ``makeFeaClassName``."""
    import re

    name = re.sub(r"[^A-Za-z0-9._]", r"", name)
    base, i = name, 1
    while name in taken:
        name = "%s_%d" % (base, i)
        i += 1
    return name


def _rule(pair, names):
    """ufo2ft's ``_makePairPosRule`` of a left-to-right pair."""
    from fontTools.feaLib import ast

    first, second = isinstance(pair.side1, tuple), isinstance(pair.side2, tuple)
    g1 = ast.GlyphClassName(names[0][pair.side1]) if first else ast.GlyphName(pair.side1)
    g2 = ast.GlyphClassName(names[1][pair.side2]) if second else ast.GlyphName(pair.side2)
    return ast.PairPosStatement(glyphs1=g1, valuerecord1=ast.ValueRecord(xAdvance=pair.value),
                                glyphs2=g2, valuerecord2=None, enumerated=first ^ second)


def _add_references(feature, lookups, script, languages):
    """ufo2ft's ``addLookupReferences`` for a script and its languages."""
    from fontTools.feaLib import ast

    feature.statements.append(ast.ScriptStatement(script))
    feature.statements.append(ast.LanguageStatement("dflt", include_default=True))
    for lookup in lookups:
        feature.statements.append(ast.LookupReferenceStatement(lookup))
    for language in languages or ():
        if language != "dflt":
            feature.statements.append(ast.LanguageStatement(language, include_default=True))


def _split(pairs, glyph_scripts):
    """ufo2ft's ``splitKerning``: the pairs by the scripts of their glyphs (a class
    split where its glyphs' directions differ), buckets sharing a script merged,
    each bucket's pairs sorted."""
    per, sides = {}, {}
    for pair in pairs:
        for scripts, part in _by_script(pair, glyph_scripts, sides):
            per.setdefault(tuple(sorted(scripts)), []).append(part)
    per = _merge(per)
    for bucket in per.values():
        bucket.sort(key=_Pair.key)
    return per


def _by_script(pair, glyph_scripts, sides):
    """ufo2ft's ``partitionByScript`` (directions: left to right or neutral).
    ``sides``: each side's :func:`_side_parts`, by side, filled as they come (a
    group is a side of many pairs)."""
    parts = []
    for side in (pair.side1, pair.side2):
        if side not in sides:
            sides[side] = _side_parts(side, glyph_scripts)
        parts.append(sides[side])
    for (d1, (local1, scripts1)), (d2, (local2, scripts2)) in itertools.product(
            parts[0].items(), parts[1].items()):
        if d1 != d2 and "Auto" not in (d1, d2):
            continue
        scripts = scripts1 | scripts2
        if not (COMMON_SCRIPT in scripts1 and COMMON_SCRIPT in scripts2):
            scripts -= {COMMON_SCRIPT}
        yield scripts, _Pair(local1, local2, pair.value)


def _side_parts(side, glyph_scripts):
    """One side of a pair (a glyph name, or a tuple of names for a class) by the
    directions of its glyphs' scripts (those of the common script, or none, as the
    common script): direction -> (its glyphs of that direction, the glyph or a
    sorted tuple for a class; the union of their scripts)."""
    dirs, resolved = {}, {}
    for glyph in side if isinstance(side, tuple) else (side,):
        scripts = glyph_scripts.get(glyph, DFLT_SCRIPTS)
        if scripts & DFLT_SCRIPTS:
            scripts = {COMMON_SCRIPT}
        resolved[glyph] = scripts
        for d in (_direction(s) for s in sorted(scripts)):
            dirs.setdefault(d, set()).add(glyph)
    out = {}
    for d, members in dirs.items():
        if isinstance(side, tuple):
            local = tuple(sorted(members))
        else:
            (local,) = members
        out[d] = (local, set().union(*(resolved[g] for g in
                                       (local if isinstance(local, tuple) else (local,)))))
    return out


def _merge(per):
    """ufo2ft's ``mergeScripts``: buckets that share a script made one."""
    sets = [set(s) for s in per if s]
    merged = True
    while merged:
        merged = False
        result = []
        while sets:
            common, rest = sets[0], sets[1:]
            sets = []
            for s in rest:
                if s.isdisjoint(common):
                    sets.append(s)
                else:
                    merged = True
                    common |= s
            result.append(common)
        sets = result
    out = {tuple(sorted(s)): [] for s in sets}
    for scripts, pairs in per.items():
        for s in sets:
            if s & set(scripts):
                out[tuple(sorted(s))].extend(pairs)
                break
        else:
            raise AssertionError("a bucket of no script")
    return out
