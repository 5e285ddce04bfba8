"""Feature files (``.fea``) of fonts whose glyphs moved: the explicit anchors of
mark, mark-to-mark, ligature and cursive statements moved like their glyphs'
anchors (:func:`move_feature_anchors`), only the numbers rewritten in place so
the text (comments, layout) is kept.  Read with fontTools.feaLib.
"""

from ..errors import MorphError, ParseError, one_line

__all__ = ["move_feature_anchors", "moved_features", "vary_feature_anchors"]


def move_feature_anchors(text, glyph_names, offset_of):
    """Feature-file text with its explicit anchors moved like their glyphs' anchors.

    ``offset_of(glyph_name)`` gives the ``(dx, dy)`` by which that glyph's anchors
    moved (None: unchanged).  Every ``<anchor x y>`` of a mark class definition
    (``markClass``), a mark-to-base / ligature / mark-to-mark or cursive statement is
    moved by the offset of the statement's glyphs (the marks of a ``markClass``, the
    bases of a ``pos base`` ...); only the numbers are rewritten, the rest of the text
    (comments, layout) is kept.  Anchors in included files are not moved.

    Raises:
        ParseError: the text does not parse (fontTools.feaLib; ``.source`` is the text).
        MorphError: one statement's glyphs moved by different offsets.
    """
    return moved_features(text, glyph_names, offset_of)[0]


def moved_features(text, glyph_names, offset_of):
    """``(text, tree)``: :func:`move_feature_anchors`'s text, and feaLib's syntax tree
    of it: the text's tree with the same anchors moved to the same numbers, so that
    a compiler need not parse the text again; None for a text that includes files
    (its includes are resolved where the font is, not here).

    Raises:
        ParseError, MorphError: as :func:`move_feature_anchors`.
    """
    import re

    tree = _parse(text, glyph_names)
    moves = []
    for anchor, glyph_set in _statement_anchors(tree.statements):
        offset = _common_offset(anchor, glyph_set, offset_of)
        if offset is not None:
            moves.append((anchor, _fea_number(anchor.x + offset[0]),
                          _fea_number(anchor.y + offset[1])))
    text = _rewrite_anchors(text, [(a, "anchor %s %s" % (x, y)) for a, x, y in moves])
    if re.search(r"\binclude\s*\(", text):
        return text, None
    for anchor, x, y in moves:   # as the rewritten text parses
        anchor.x, anchor.y = int(x), int(y)
    return text, tree


def vary_feature_anchors(text, glyph_names, masters):
    """Feature-file text of a variable font whose glyphs moved by other offsets at
    each master: every explicit anchor (as :func:`move_feature_anchors` finds them)
    whose glyphs moved differently between the masters, or whose value differs
    between the masters' own feature files, becomes a variable anchor, ``<anchor
    (TAG=v,...:x ...) (TAG=v,...:y ...)>`` with one value per master (feaLib's
    variable scalars, user coordinates; compiled by ufo2ft's variable compilers into
    GPOS anchors with deltas), one that moved alike at every master is moved as
    :func:`move_feature_anchors` moves it.

    ``masters``: ``(location, offset_of)`` or ``(location, offset_of, own_text)`` per
    master, ``location`` a dict axis tag -> user value, ``offset_of`` as for
    :func:`move_feature_anchors`, ``own_text`` the master's own feature file (None:
    ``text``): its anchors, in the same statements as ``text``'s, give that master's
    values.

    Raises:
        ParseError, MorphError: as :func:`move_feature_anchors`; MorphError: a
            master's feature file whose anchors are not those of ``text``.
    """
    anchors = list(_statement_anchors(_parse(text, glyph_names).statements))
    own = [_own_anchors(m[2] if len(m) > 2 else None, len(anchors), glyph_names, k)
           for k, m in enumerate(masters)]
    moves = []
    for i, (anchor, glyph_set) in enumerate(anchors):
        if anchor is None or anchor.x is None:
            continue
        offsets = [_common_offset(anchor, glyph_set, m[1]) or (0.0, 0.0) for m in masters]
        at = [anchor if o is None else o[i][0] for o in own]
        if all(o == (0.0, 0.0) for o in offsets) and \
                all((a.x, a.y) == (anchor.x, anchor.y) for a in at):
            continue
        xs = [_fea_number(a.x + o[0]) for a, o in zip(at, offsets)]
        ys = [_fea_number(a.y + o[1]) for a, o in zip(at, offsets)]
        moves.append((anchor, "anchor %s %s" % (_scalar(masters, xs), _scalar(masters, ys))))
    return _rewrite_anchors(text, moves)


def _own_anchors(text, count, glyph_names, k):
    """A master's own feature-file anchors (None: no text of its own)."""
    if text is None:
        return None
    found = list(_statement_anchors(_parse(text, glyph_names).statements))
    if len(found) != count:
        raise MorphError("the feature file of master %d has %d anchors, the default's %d: "
                         "masters' feature files must differ in anchor values only"
                         % (k, len(found), count))
    return found


def _scalar(masters, values):
    """A number, or feaLib's variable scalar of one value per master."""
    if len(set(values)) == 1:
        return values[0]
    return "(%s)" % " ".join("%s:%s" % (",".join("%s=%s" % (tag, _fea_location(v))
                                                 for tag, v in m[0].items()), value)
                             for m, value in zip(masters, values))


def _fea_location(v):
    return ("%.4f" % v).rstrip("0").rstrip(".")


def _parse(text, glyph_names):
    import io

    from .deferred import feature_parser

    try:
        return feature_parser().Parser(io.StringIO(text), glyphNames=set(glyph_names)).parse()
    except Exception as exc:  # feaLib's FeatureLibError and include errors
        raise ParseError("cannot parse the features: %s" % one_line(exc), text) from exc


def _statement_anchors(statements):
    """(anchor, glyph set it belongs to) of every anchor in feaLib statements, blocks
    included: mark classes (the marks), mark-to-base / -mark / -ligature (the bases),
    cursive entry and exit (the glyphs)."""
    from fontTools.feaLib import ast

    for st in statements:
        if isinstance(st, ast.MarkClassDefinition):
            yield st.anchor, st.glyphSet()
        elif isinstance(st, ast.MarkBasePosStatement):
            yield from ((anchor, st.base.glyphSet()) for anchor, _ in st.marks)
        elif isinstance(st, ast.MarkMarkPosStatement):
            yield from ((anchor, st.baseMarks.glyphSet()) for anchor, _ in st.marks)
        elif isinstance(st, ast.MarkLigPosStatement):
            yield from ((anchor, st.ligatures.glyphSet())
                        for component in st.marks for anchor, _ in component)
        elif isinstance(st, ast.CursivePosStatement):
            yield st.entryAnchor, st.glyphclass.glyphSet()
            yield st.exitAnchor, st.glyphclass.glyphSet()
        if hasattr(st, "statements"):
            yield from _statement_anchors(st.statements)


def _common_offset(anchor, glyph_set, offset_of):
    """The one offset by which the glyphs of an anchor moved (None: not moved, or a
    null anchor).  Raises MorphError when they moved by different offsets."""
    if anchor is None or anchor.x is None:
        return None
    offsets = {offset_of(g) for g in glyph_set} - {None}
    if len(offsets) > 1:
        raise MorphError("anchor at line %d: its glyphs %s moved by different offsets"
                         % (anchor.location.line, ", ".join(sorted(glyph_set))))
    return offsets.pop() if offsets else None


def _rewrite_anchors(text, moves):
    """The feature text with each ``anchor x y`` in ``moves`` (anchor, its new text)
    rewritten in place; anchors of included files are left alone.

    Raises:
        MorphError: an anchor not found where feaLib located it.
    """
    import re

    lines = text.split("\n")
    number = r"(-?\d+(?:\.\d+)?)"
    pattern = re.compile(r"anchor\s+" + number + r"\s+" + number)
    # later positions first, so earlier columns stay valid
    for anchor, new in sorted(moves, key=lambda m: (m[0].location.line,
                                                   m[0].location.column), reverse=True):
        loc = anchor.location
        if loc.file != "<features>":
            continue
        line = lines[loc.line - 1]
        m = pattern.match(line, loc.column - 1)
        if m is None:
            raise MorphError("cannot find the anchor of line %d in the features" % loc.line)
        lines[loc.line - 1] = line[:m.start()] + new + line[m.end():]
    return "\n".join(lines)


def _fea_number(v):
    return str(int(round(v)))
