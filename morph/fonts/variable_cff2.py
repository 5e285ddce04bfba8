"""CFF2 output of a brushed variable font: the fitted cubics of every master as
blended CFF2 charstrings, the advances as HVAR.

Each master's contours are drawn with their points rounded to integers (as the
TrueType output's are), merged into one charstring per glyph by fontTools'
``CFF2CharStringMergePen`` over the glyph's own masters' grid model
(:func:`morph.fonts.variable_grid.grid_model`: integer deltas, every master
exactly its own rounded outline; the charstring's coordinates are relative, so a
master reproduced within a rounding per coordinate would carry that error along
the contour), into a CFF2 table whose variation store holds every glyph's
regions, one VarData per distinct set of glyph masters (the charstring's
``vsindex`` picks it).  The
overlapping contours need no flag: CFF2 charstrings are filled nonzero.  The
advances vary through HVAR (CFF2 has no phantom points), built by fontTools
varLib's HVAR builder from the same model.

Every coordinate carries a delta per master beyond the default, so a glyph with
many masters can pass the 65,535 bytes a reader takes for a charstring: its program
is then split into local subroutines (:func:`split_long_charstrings`, which the
stroke command's CFF2 output goes through too).
"""

import numpy as np

__all__ = ["write_cff2", "split_long_charstrings", "MAX_CHARSTRING", "MAX_BLEND_MASTERS"]

#: tables of TrueType outlines and hinting a CFF2 font has no use for
_TRUETYPE = ("glyf", "loca", "gvar", "CFF ", "CFF2", "VORG", "fpgm", "prep", "cvt ",
             "cvar", "HVAR", "VVAR", "hdmx", "LTSH", "VDMX", "DSIG")


def write_cff2(font, plan, results, moved, widths):
    """Replace the outlines of ``font`` by a CFF2 table and HVAR.

    ``plan``: the brush's plan (``plan.masters(name)``: a glyph's own fitted
    masters, their locations, source masters and grid model); ``results``: (name,
    per master cubic contours or None, seconds) of every glyph; ``moved``: per
    brushed glyph, (x shift, advance growth) at each of its masters; ``widths(s,
    name)``: the advance at source master ``s``.  Every glyph's blends run over its
    own masters' regions: one VarData per distinct set of masters, chosen by the
    charstring's ``vsindex``; a charstring longer than a reader takes is split
    into subroutines (:func:`split_long_charstrings`).  Returns the brushed
    glyphs' default shifts ((x, 0) each) for the anchors.

    Raises:
        MorphError: a glyph with more than :data:`MAX_BLEND_MASTERS` masters."""
    from ..errors import MorphError

    contours = {name: c for name, c, _ in results if c is not None}
    charstrings, advances, lsbs, models = {}, {}, {}, {}
    for name in font.getGlyphOrder():
        masters = plan.masters(name)
        n = len(masters.locs)
        if n > MAX_BLEND_MASTERS:
            raise MorphError("glyph %r needs %d masters, more than the %d a CFF2 blend "
                             "takes (its operand stack holds 513 values); write a "
                             "TrueType variable font (.ttf) instead"
                             % (name, n, MAX_BLEND_MASTERS))
        shift = moved.get(name, [(0.0, 0)] * n)
        per = contours.get(name)
        charstrings[name], lsbs[name] = _charstring(name, per, [s for s, _ in shift],
                                                    masters.model)
        models[name] = masters.model
        advances[name] = [int(round(widths(masters.source(m), name))) + shift[m][1]
                          for m in range(n)]
    _cff2_table(font, charstrings, models, plan.tags)
    split_long_charstrings(font)
    for name in font.getGlyphOrder():
        font["hmtx"][name] = (advances[name][0], lsbs[name])
    _hvar(font, models, advances, plan.tags)
    return {name: (shift[0][0], 0.0) for name, shift in moved.items()}


def _charstring(name, per, shifts, model):
    """(blended CFF2 charstring, the default master's left side bearing) of one
    glyph from its cubic contours at every master (None: no contours)."""
    from fontTools.pens.boundsPen import BoundsPen
    from fontTools.varLib.cff import CFF2CharStringMergePen

    pen = CFF2CharStringMergePen([], name, len(model.locations), 0, roundTolerance=1e-6)
    bounds = BoundsPen(None)
    for m in range(len(model.locations)):
        if m:
            pen.restart(m)
        for loop in (per[m] if per is not None else []):
            pts = np.round(np.asarray(loop, float) + np.array([shifts[m], 0.0])).astype(int)
            pts = pts.tolist()
            for p in ([pen, bounds] if m == 0 else [pen]):
                p.moveTo(tuple(pts[0][0]))
                for c in pts:
                    p.curveTo(tuple(c[1]), tuple(c[2]), tuple(c[3]))
                p.closePath()
    cs = pen.getCharString(var_model=model, optimize=True)
    return cs, (int(bounds.bounds[0]) if bounds.bounds else 0)


#: the longest charstring or subroutine a reader takes, in bytes (the Type 2 limit;
#: ots-sanitize refuses a CFF2 font with a longer one)
MAX_CHARSTRING = 65535

#: the most masters a glyph's CFF2 charstring can blend: a curve's sixth operand
#: is blended with its five others on the operand stack (limit 513), then the
#: default and a delta per other master, then the count (5 + 507 + 1)
MAX_BLEND_MASTERS = 507

#: the most local subroutines one Private dict can address (callsubr's operand
#: with the largest bias, 32768, reaches indices 0 to 65535)
MAX_SUBRS = 65536

#: operators that take every operand on the stack and leave it empty: a
#: charstring can be cut after any of them
_PATH_OPERATORS = frozenset((
    "rmoveto", "hmoveto", "vmoveto", "rlineto", "hlineto", "vlineto", "rrcurveto",
    "hhcurveto", "vvcurveto", "hvcurveto", "vhcurveto", "rcurveline", "rlinecurve",
    "flex", "hflex", "hflex1", "flex1"))


def split_long_charstrings(font, limit=MAX_CHARSTRING):
    """Every charstring of ``font``'s CFF2 table longer than ``limit`` bytes made a
    run of local subroutine calls (in place); returns {glyph name: bytes before}
    of the glyphs split.

    A glyph with many masters carries a delta per master region on every
    coordinate (``blend``), so its charstring can pass the 65,535 bytes a reader
    takes (Source Serif 4's e with a 60 x 15 nib: 154 masters, 334 KB).  The
    program is cut after path operators (the operand stack is empty there, so
    each part is a whole run of path operators with their blends; an operator
    longer than ``limit`` is made one per curve first) into parts of at most
    ``limit`` bytes, each one local subroutine of the glyph's Private dict
    (CFF2 subroutines may blend; they have no ``return``); the charstring keeps its
    ``vsindex`` (which must come before any blend, and which the subroutines
    inherit) and calls the parts in order.  The outline drawn is the same program
    run through.  The fonts morph writes have no subroutines before this (a Private
    dict with some is refused: the new ones would move their bias).

    Raises:
        MorphError: more parts than one Private dict can address
            (:data:`MAX_SUBRS`: 4 GB of charstrings), or one curve longer than
            ``limit`` (the operand stack of 513 keeps a blended curve within
            about 15 KB): what no CFF2 font can hold.
    """
    from ..errors import MorphError

    cff = font["CFF2"].cff
    top = cff.topDictIndex[0]
    charstrings = top.CharStrings
    split, parts = {}, {}           # parts: id(private) -> (private, [programs])
    for name in font.getGlyphOrder():
        cs = charstrings[name]
        if cs.needsDecompilation():
            if len(cs.bytecode) <= limit:
                continue
            cs.decompile()
        sizes = [_token_size(cs, k) for k in range(len(cs.program))]
        if sum(sizes) <= limit:
            continue
        private = cs.private
        if getattr(private, "Subrs", None):
            raise MorphError("glyph %r: its Private dict has subroutines already; cannot "
                             "split its %d-byte charstring" % (name, sum(sizes)))
        head, pieces = _cut(name, cs, sizes, limit)
        _, programs = parts.setdefault(id(private), (private, []))
        first = len(programs)
        programs.extend(pieces)
        split[name] = sum(sizes)
        cs.program = head + [("subr", first + k) for k in range(len(pieces))]
    for private, programs in parts.values():
        _install_subrs(cff, private, programs, [charstrings[n] for n in split])
    return split


def _install_subrs(cff, private, programs, split):
    """``programs`` made the local subroutines of ``private``, and the ("subr", k)
    calls of the charstrings ``split`` that use it made biased ``callsubr``s."""
    from fontTools.cffLib import SubrsIndex
    from fontTools.misc.psCharStrings import T2CharString

    from ..errors import MorphError

    if len(programs) > MAX_SUBRS:
        raise MorphError("%d subroutines of split charstrings, more than the %d a "
                         "Private dict addresses" % (len(programs), MAX_SUBRS))
    bias = _bias(len(programs))
    subrs = SubrsIndex(private=private, globalSubrs=cff.GlobalSubrs, isCFF2=True)
    for program in programs:
        subrs.append(T2CharString(program=program, private=private,
                                  globalSubrs=cff.GlobalSubrs))
    private.Subrs = subrs
    for cs in split:
        if cs.private is private:
            cs.program = [t for tok in cs.program for t in (
                (tok[1] - bias, "callsubr") if isinstance(tok, tuple) else (tok,))]


def _cut(name, cs, sizes, limit):
    """(the program of charstring ``cs`` up to its ``vsindex``, its rest cut after
    path operators into parts of at most ``limit`` bytes); ``sizes``: each token's
    bytes.  A path operator longer than ``limit`` (the specializer joins up to 513
    operands' worth of curves into one, each operand with its blend) is first made
    one operator per curve or line (:func:`_one_per_segment`)."""
    from ..errors import MorphError

    program = cs.program
    start = program.index("vsindex") + 1 if "vsindex" in program else 0
    vsindex = program[start - 2] if start else getattr(cs.private, "vsindex", 0)
    runs, run, run_size = [], [], 0
    for k in range(start, len(program)):
        run.append(program[k])
        run_size += sizes[k]
        if program[k] in _PATH_OPERATORS or k + 1 == len(program):
            runs += [(run, run_size)] if run_size <= limit else \
                _one_per_segment(run, cs.private.getNumRegions(vsindex), vsindex)
            run, run_size = [], 0
    pieces, part, size = [], [], 0
    for run, run_size in runs:
        if run_size > limit:
            raise MorphError("glyph %r has a curve of %d blended bytes, more than the "
                             "%d a CFF2 subroutine holds" % (name, run_size, limit))
        if size + run_size > limit:
            pieces.append(part)
            part, size = [], 0
        part += run
        size += run_size
    if part:
        pieces.append(part)
    return program[:start], pieces


def _one_per_segment(run, regions, vsindex):
    """A path operator's program (its operands and blends first) as one operator per
    line or curve (fontTools' generalizer: the same segments, each blended operand
    its own blend), as (program, bytes) each."""
    from fontTools.cffLib.specializer import (commandsToProgram, generalizeCommands,
                                              programToCommands)
    from fontTools.misc.psCharStrings import T2CharString

    out = []
    for command in generalizeCommands(programToCommands(run, lambda v: regions, vsindex)):
        piece = T2CharString(program=commandsToProgram([command]))
        piece.compile(isCFF2=True)
        out.append((commandsToProgram([command]), len(piece.bytecode)))
    return out


def _token_size(cs, k):
    """Bytes of token ``k`` of ``cs``'s program as T2CharString.compile writes it
    (a hint mask's bytes counted with its operator)."""
    token = cs.program[k]
    if isinstance(token, str):
        return len(cs.opcodes[token])
    if isinstance(token, bytes):
        return len(token)
    if isinstance(token, int):
        return len(cs.getIntEncoder()(token))
    return len(cs.getFixedEncoder()(token))


def _bias(count):
    """The subroutine number bias of a subroutine INDEX of ``count`` entries (CFF2
    charstring specification, as for Type 2)."""
    return 107 if count < 1240 else (1131 if count < 33900 else 32768)


def _region_key(support):
    return tuple(sorted((t, tuple(float(v) for v in r)) for t, r in support.items()))


def _cff2_table(font, charstrings, models, tags):
    """The font's outline tables replaced by a CFF2 table of ``charstrings``; its
    variation store holds every glyph model's regions, one VarData per distinct
    model (its regions in the model's order), each charstring prefixed by its
    model's ``vsindex`` (none for VarData 0); maxp 0.5, post format 2 (the glyph
    names kept: CFF2 has none of its own)."""
    from fontTools.cffLib import VarStoreData
    from fontTools.fontBuilder import FontBuilder
    from fontTools.varLib.builder import buildVarData, buildVarRegionList, buildVarStore

    for tag in _TRUETYPE:
        if tag in font:
            del font[tag]
    regions, datas, vsindex = {}, [], {}
    for name in font.getGlyphOrder():
        model = models[name]
        if id(model) not in vsindex:
            keys = [_region_key(s) for s in model.supports[1:]]
            for k, s in zip(keys, model.supports[1:]):
                regions.setdefault(k, (len(regions), s))
            vsindex[id(model)] = len(datas)
            datas.append(buildVarData([regions[k][0] for k in keys], None, optimize=False))
        k = vsindex[id(model)]
        if k:
            charstrings[name].program[:0] = [k, "vsindex"]
    fb = FontBuilder(font=font)
    fb.isTTF = False
    fb.setupCFF2(charstrings)
    region_list = buildVarRegionList([s for _, s in sorted(regions.values(),
                                                           key=lambda r: r[0])], tags)
    store = VarStoreData(otVarStore=buildVarStore(region_list, datas))
    top = font["CFF2"].cff.topDictIndex[0]
    top.VarStore = store
    for fd in top.FDArray:
        fd.Private.vstore = store
    font["maxp"].tableVersion = 0x00005000
    post = font["post"]
    post.formatType = 2.0
    post.extraNames, post.mapping = [], {}
    font.sfntVersion = "OTTO"


def _hvar(font, models, advances, tags):
    """HVAR of the advances at each glyph's masters, over its own model (varLib's
    builder: a direct store when every glyph uses the one model, else rows mapped per
    glyph)."""
    from fontTools import varLib

    def metrics():
        return {n: models[n].getDeltasAndSupports(a, round=round)
                for n, a in advances.items()}, {}

    varLib._add_VHVAR(font, tags, varLib.HVAR_FIELDS, metrics)
