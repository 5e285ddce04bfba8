"""The mark and mkmk features ufo2ft's ``MarkFeatureWriter`` writes from a static
font's anchors: written into feaLib's tree of the feature file as that writer
writes them (the same mark class definitions and names, lookups, their order and
places), so that feaLib builds the same GPOS and GDEF tables.  A port of ufo2ft 3's
writer (``markFeatureWriter.py``, MIT licence) in its default mode ("skip": a
feature the file has already is not written; one lookup per mark class, sorted by
the class's anchor name), for what :attr:`MarkWriter.reason` vouches for:

- anchors as ufo2ft derives them: "_top" makes a mark glyph of class
  ``@mark_top``, "top" a base (mark to base), "top_1", "top_2"... a ligature's
  components (mark to ligature; "_2" alone: a component without anchor), "top"
  in a mark glyph a mark to mark attachment with its mark filtering set; names
  not starting with a letter ignored, unpaired anchors pruned, coordinates
  rounded as ufo2ft rounds them; mark classes the feature file defines already
  extended or renamed as ufo2ft does;
- no GDEF table block in the feature file (ufo2ft would take its glyph classes);
- no contextual anchor (a name starting with "*");
- no glyph of the scripts of the abvm / blwm features (Indic, USE, Khmer), which
  ufo2ft splits off into those features;
- no anchor name ufo2ft refuses (a numbered mark anchor, "_" alone): ufo2ft
  raises its error.

The writer has no direction of its own (ufo2ft's writes the same lookups for
right-to-left scripts).  Anything else leaves the font to ufo2ft
(:func:`morph.fonts.tables_static.left_to_ufo2ft`).  tests/fonts/test_mark_static.py
compares the written feature text with ufo2ft's writer's, character for
character, and the compiled GPOS and GDEF tables byte for byte.
"""

import re

from .kern_static import _class_definitions, _fea_class_name

__all__ = ["MarkWriter", "FEATURES"]

#: the features of ufo2ft's mark writer
FEATURES = frozenset(("mark", "mkmk", "abvm", "blwm"))
_LIGA_NUM = re.compile(r".*?(\d+)$")


def _round(v):
    from fontTools.misc.roundTools import otRound

    return otRound(v)


class _Anchor:
    """ufo2ft's ``NamedAnchor``: an anchor's name parsed (mark or not, its key,
    its ligature component number)."""

    __slots__ = ("name", "x", "y", "is_mark", "key", "number", "mark_class")

    def __init__(self, name, x, y):
        self.name, self.x, self.y, self.mark_class = name, x, y, None
        number = None
        m = _LIGA_NUM.match(name)
        key = name
        if m:
            digits = m.group(1)
            key = name.rstrip(digits)
            if key.endswith("_"):
                key, number = key[:-1], int(digits)
            else:
                key = name
        self.is_mark = bool(name.startswith("_") and key)
        if self.is_mark:
            if number is not None:
                raise ValueError("mark anchor cannot be numbered: %r" % name)
            key = key[1:]
            if not key:
                raise ValueError("mark anchor key is nil: %r" % name)
        if number is not None and number < 1:
            raise ValueError("ligature component indexes must start from 1")
        self.key, self.number = key, number

    @property
    def ignorable(self):
        return bool(self.key) and not self.key[0].isalpha()

    @property
    def mark_name(self):
        return "_" + self.key

    def ast_anchor(self):
        from fontTools.feaLib import ast

        return ast.Anchor(x=_round(self.x), y=_round(self.y))


def _marks(anchors):
    return [(a.ast_anchor(), a.mark_class) for a in sorted(anchors, key=lambda a: a.name)]


class _Pos:
    """ufo2ft's ``MarkToBasePos`` / ``MarkToMarkPos`` (``kind`` "base" / "mark":
    ``marks`` a list of anchors) and ``MarkToLigaPos`` ("liga": ``marks`` a list
    of each component's anchors) of the glyph ``name``."""

    def __init__(self, kind, name, marks):
        self.kind, self.name, self.marks = kind, name, marks

    def filtered(self, classes):
        if self.kind == "liga":
            marks = [[a for a in comp if a.mark_class.name in classes] for comp in self.marks]
        else:
            marks = [a for a in self.marks if a.mark_class.name in classes]
        return _Pos(self.kind, self.name, marks) if any(marks) else None

    def statement(self):
        from fontTools.feaLib import ast

        glyph = ast.GlyphName(self.name)
        if self.kind == "liga":
            return ast.MarkLigPosStatement(glyph, [_marks(c) for c in self.marks])
        if self.kind == "mark":
            return ast.MarkMarkPosStatement(glyph, _marks(self.marks))
        return ast.MarkBasePosStatement(glyph, _marks(self.marks))


class MarkWriter:
    """The mark and mkmk features ufo2ft would add to feaLib's tree ``tree`` of
    the feature file (None: none) of the light font whose exported glyphs, in the
    font's order, are ``order`` (name -> glyph in ``glyphs``) and whose cmap has
    the code points ``codes``.  :attr:`reason` says why ufo2ft must write them
    (None: :meth:`write` writes them as ufo2ft does)."""

    def __init__(self, tree, order, glyphs, codes):
        from fontTools.feaLib import ast

        self.tree = tree if tree is not None else ast.FeatureFile()
        self.reason = None
        self.todo = FEATURES - {s.name for s in self.tree.statements
                                if isinstance(s, ast.FeatureBlock)}
        if any(isinstance(s, ast.TableBlock) and s.name == "GDEF"
               for s in self.tree.statements):
            self.reason = "a GDEF table in the feature file (mark glyph classes)"
            return
        try:
            self.lists = self._anchor_lists(order, glyphs)
        except ValueError as exc:   # ufo2ft raises the same
            self.reason = "an anchor ufo2ft refuses: %s" % exc
            return
        if self.reason is None and self._abvm(codes):
            self.reason = "anchors in a script of the abvm / blwm features"

    def _anchor_lists(self, order, glyphs):
        """ufo2ft's ``_getAnchorLists``: glyph name -> its named anchors (the last
        of a repeated name, at the first's place), those not starting with a
        letter left out; sets :attr:`reason` for a contextual anchor."""
        out = {}
        for name in order:
            found = {}
            for a in getattr(glyphs.get(name), "anchors", ()):
                if not a.name:
                    continue
                if a.name.startswith("*"):
                    self.reason = "contextual anchors"
                anchor = _Anchor(a.name, _round(a.x), _round(a.y))
                if not anchor.ignorable:
                    found[a.name] = anchor
            if found:
                out[name] = list(found.values())
        return out

    def _abvm(self, codes):
        """Whether ufo2ft's ``_getAbvmGlyphs`` finds glyphs (cut to the feature
        file's scripts where it names some)."""
        from fontTools.feaLib import ast

        from .writers_static import _abvm_scripts, _iso_scripts

        fea = {s.script for s in self.tree.statements
               if isinstance(s, ast.LanguageSystemStatement) and s.script != "DFLT"}
        return _abvm_scripts(codes, _iso_scripts(fea))

    # ------------------------------------------------------------ writing

    def write(self):
        """The missing mark and mkmk features, their mark class definitions
        inserted into the tree as ufo2ft inserts them; False where there is
        nothing to write."""
        if self.reason is not None:
            raise ValueError(self.reason)
        pairs = self._pairs()
        if not pairs or not self.todo:
            return False
        self._prune(pairs)
        new_defs = self._mark_classes(set(pairs.values()))
        for anchors in self.lists.values():
            for a in anchors:
                if not a.is_mark and a.key and a.key in self.classes:
                    a.mark_class = self.classes[a.key]
        features = {}
        if "mark" in self.todo:
            features["mark"] = self._mark_feature()
        if "mkmk" in self.todo:
            features["mkmk"] = self._mkmk_feature()
        features = [f for _, f in sorted(features.items()) if f is not None]
        if not features:
            return False
        from fontTools.feaLib import ast

        others = list(new_defs) + [ast.Comment("")] if new_defs else []
        self.tree.statements = others + self.tree.statements + features
        return True

    def _pairs(self):
        """ufo2ft's ``_getAnchorPairs``: base anchor name -> the mark anchor name
        it pairs with."""
        marks = {a.name for anchors in self.lists.values() for a in anchors if a.is_mark}
        return {a.name: a.mark_name for anchors in self.lists.values() for a in anchors
                if not a.is_mark and a.mark_name in marks}

    def _prune(self, pairs):
        keep = set(pairs) | set(pairs.values())
        for name, anchors in list(self.lists.items()):
            anchors[:] = [a for a in anchors if a.name in keep or not a.key]
            if not anchors:
                del self.lists[name]

    def _mark_classes(self, mark_names):
        """ufo2ft's ``_makeMarkClassDefinitions``: the new mark class definitions
        (a class per mark anchor name, "mark" + the name, sorted; a glyph the
        file's class holds already at another anchor makes a class "..._1");
        sets the mark glyphs and :attr:`classes` (anchor key -> class)."""
        groups, self.mark_glyphs = {}, set()
        for name, anchors in self.lists.items():
            marks = [a for a in anchors if a.name in mark_names]
            for a in marks:
                groups.setdefault(a.name, {})[name] = a
            if marks:
                self.mark_glyphs.add(name)
        current = self.tree.markClasses
        self.classes, new_defs = {}, []
        for mark_name, members in sorted(groups.items()):
            class_name = _fea_class_name("mark" + mark_name, ())
            for glyph, anchor in members.items():
                mcd = _define(glyph, anchor, class_name, current)
                if mcd is not None:
                    new_defs.append(mcd)
                    class_name = mcd.markClass.name
                self.classes[anchor.key] = current[class_name]
        return new_defs

    # the features

    def _base_attachments(self):
        """ufo2ft's ``_makeMarkToBaseAttachments`` (glyphs not marks, their
        anchors of a mark class and no number)."""
        out = []
        for name, anchors in self.lists.items():
            if name in self.mark_glyphs:
                continue
            marks = [a for a in anchors if a.mark_class is not None and a.number is None]
            if marks:
                out.append(_Pos("base", name, marks))
        return out

    def _liga_attachments(self):
        """ufo2ft's ``_makeMarkToLigaAttachments``: each component's anchors
        (numbered from 1; a missing number or a bare "_N" anchor: none)."""
        out = []
        for name, anchors in self.lists.items():
            if name in self.mark_glyphs:
                continue
            comps = {}
            for a in anchors:
                if (a.mark_class is None and a.key) or a.number is None:
                    continue
                if not a.key:
                    comps[a.number] = []
                else:
                    comps.setdefault(a.number, []).append(a)
            if comps:
                out.append(_Pos("liga", name, [comps.get(n, [])
                                               for n in range(1, max(comps) + 1)]))
        return out

    def _grouped(self, attachments):
        """ufo2ft's ``_groupAttachments`` without ``groupMarkClasses``: a group
        per mark class, in the order of their anchor keys."""
        groups = []
        for _, mark_class in sorted(self.classes.items(), key=lambda kv: kv[0]):
            kept = (p.filtered({mark_class.name}) for p in attachments)
            groups.append([p for p in kept if p is not None])
        return groups

    def _lookups(self, prefix, attachments):
        from fontTools.feaLib import ast

        out = []
        for group in self._grouped(attachments):
            if group:
                i = len(out)
                lookup = ast.LookupBlock(prefix + ("_%d" % i if i > 0 else ""))
                lookup.statements.extend(p.statement() for p in group)
                out.append(lookup)
        return out

    def _mark_feature(self):
        """ufo2ft's ``_makeMarkFeature`` without contextual anchors: the mark to
        base lookups, then the mark to ligature ones, inside the feature."""
        from fontTools.feaLib import ast

        lookups = (self._lookups("mark2base", self._base_attachments())
                   + self._lookups("mark2liga", self._liga_attachments()))
        if not lookups:
            return None
        feature = ast.FeatureBlock("mark")
        feature.statements.extend(lookups)
        return feature

    def _mkmk_feature(self):
        """ufo2ft's ``_makeMkmkFeature``: a lookup per base anchor key of the mark
        glyphs (sorted), each with its mark filtering set."""
        from fontTools.feaLib import ast

        by_key = {}
        for name, anchors in self.lists.items():
            if name not in self.mark_glyphs:
                continue
            for a in anchors:
                if a.mark_class is None or a.is_mark or a.number is not None:
                    continue   # (ufo2ft warns of a numbered anchor in a mark glyph)
                by_key.setdefault(a.key, []).append(_Pos("mark", name, [a]))
        if not by_key:
            return None
        feature = ast.FeatureBlock("mkmk")
        for key, attachments in sorted(by_key.items(), key=lambda kv: kv[0]):
            feature.statements.append(self._mkmk_lookup(key, attachments))
        return feature

    def _mkmk_lookup(self, key, attachments):
        """ufo2ft's ``_makeMarkToMarkLookup``: "mark2mark_<key>", its filtering
        set class "MFS_..." (the class's marks, then the attaching glyphs not in
        it) defined in the lookup."""
        from fontTools.feaLib import ast

        name = "mark2mark_%s" % key
        glyphs = self.classes[key].glyphs
        members = list(glyphs) + [p.name for p in attachments if p.name not in glyphs]
        taken = {c.name for c in _class_definitions(self.tree)}
        mfs = ast.GlyphClassDefinition(_fea_class_name("MFS_%s" % name, taken),
                                       ast.GlyphClass(list(members)))
        lookup = ast.LookupBlock(name)
        lookup.statements.append(mfs)
        lookup.statements.append(ast.LookupFlagStatement(
            0, markFilteringSet=ast.GlyphClassName(mfs)))
        lookup.statements.extend(p.statement() for p in attachments)
        return lookup


def _define(glyph, anchor, class_name, classes):
    """ufo2ft's ``_defineMarkClass``: the definition of ``glyph`` at ``anchor`` in
    the mark class ``class_name`` of ``classes`` (name -> feaLib ``MarkClass``,
    made where missing); None where the class has the glyph at that anchor
    already; a new class "<name>_N" where it has it at another."""
    from fontTools.feaLib import ast

    at = anchor.ast_anchor()
    mark_class = classes.get(class_name)
    if mark_class is None:
        mark_class = classes[class_name] = ast.MarkClass(class_name)
    elif glyph in mark_class.glyphs:
        old = mark_class.glyphs[glyph].anchor
        if all(getattr(at, k) == getattr(old, k)
               for k in ("x", "y", "contourpoint", "xDeviceTable", "yDeviceTable")):
            return None
        new_name = _fea_class_name(class_name, classes)
        mark_class = classes[new_name] = ast.MarkClass(new_name)
    mcd = ast.MarkClassDefinition(mark_class, at, ast.GlyphName(glyph))
    mark_class.addDefinition(mcd)
    return mcd
