"""Subroutinizing a large CFF font in groups of glyphs, so that the subroutinizer's
memory does not grow with the font.

ufo2ft subroutinizes a CFF font with cffsubr's ``tx`` over the whole font; ``tx``
holds about 70 bytes for every byte of charstrings it reads (146 MB for 3,000
stroked hanzi, 2.2 MB of unspecialized charstrings; 475 MB for 9,574, 6.9 MB).  A font whose
charstrings pass :data:`GROUP_BYTES` is therefore subroutinized in consecutive
groups of glyphs of at most that many bytes each (:func:`grouped_subroutines`):

- each group is a small name-keyed CFF of its glyphs' programs without their
  advances (every glyph of the default width 0, so that ``tx`` writes no width),
  given to ``tx`` with at most :data:`MAX_SUBRS` / groups subroutines in each of its
  two INDEXes (``tx``'s own bound for a whole font, shared out);
- the groups' global and local subroutines are laid end to end in the font's two
  INDEXes, every ``callgsubr`` and ``callsubr`` operand moved to its subroutine's
  new number (the operands are found by walking the programs' tokens with array
  operations, :func:`_tokens`; a program of hints, which no stroked or brushed glyph
  has, is refused: the caller then subroutinizes the whole font);
- each charstring is given its advance back in front (the caller's width prefix
  for the font's default and nominal widths): the width is the first operand of a
  program's first stack-clearing operator, and a subroutine call keeps the
  argument stack, so a width put before a call is read as the width.

Subroutines are shared within a group only, so the font is a little larger than
one ``tx`` run over it would write; its glyphs draw the same paths.  The groups
depend on the glyphs' programs and order alone (not on ``--jobs``).
"""

import io
import os
import subprocess
from array import array
from functools import partial

import numpy as np

__all__ = ["GROUP_BYTES", "MAX_SUBRS", "font_subroutines", "grouped_subroutines", "NotGrouped",
           "Packed"]

#: The most charstring bytes (unspecialized programs) ``tx`` subroutinizes at once:
#: 239 MB of ``tx``'s memory for 3.4 MB (two groups of the 9,574 stroked hanzi, whose
#: font is then 4.6 % larger than one ``tx`` run makes it; 146 MB for 2.2 MB).
GROUP_BYTES = 4_000_000
#: ``tx``'s bound on the subroutines of one INDEX (its ``-maxs`` default), shared by
#: the groups so that the font has no more than a whole-font run could give it.
MAX_SUBRS = 32765

_CALLSUBR, _CALLGSUBR, _ENDCHAR = 10, 29, 14
#: hint operators (hstem, vstem, hintmask, cntrmask, hstemhm, vstemhm): a hintmask's
#: mask bytes depend on the stems before it, which the token walk does not count
_HINTS = (1, 3, 18, 19, 20, 23)
#: the length of a token by its first byte (an operand or an operator)
_TOKEN = np.ones(256, np.int64)
_TOKEN[12] = 2                    # escape: a two-byte operator
_TOKEN[28] = 3                    # shortint
_TOKEN[247:255] = 2
_TOKEN[255] = 5                   # 16.16 fixed


class NotGrouped(Exception):
    """The programs cannot be subroutinized in groups (hints, a subroutinizer that
    wrote something else than expected): subroutinize the whole font."""


class Packed:
    """Byte strings kept end to end in one buffer with their ends (what a CFF INDEX
    holds): a sequence of bytes without an object per string."""

    def __init__(self):
        self.data, self.ends = bytearray(), array("q")

    def append(self, *parts):
        """One string, the concatenation of ``parts``."""
        for part in parts:
            self.data += part
        self.ends.append(len(self.data))

    def sizes(self):
        return np.diff(np.frombuffer(self.ends, np.int64), prepend=0)

    def __len__(self):
        return len(self.ends)

    def __getitem__(self, k):
        start = self.ends[k - 1] if k else 0
        return bytes(memoryview(self.data)[start:self.ends[k]])

    def __iter__(self):
        return (self[k] for k in range(len(self)))


def font_subroutines(programs, limit=None, jobs=1):
    """:func:`grouped_subroutines` of a font's charstrings ``programs`` (in glyph
    order: ``sizes``, an array of their lengths with their width prefixes;
    ``prefix(k)``; ``bodies(a, b)``, the programs ``a`` to ``b`` without their
    prefixes, read when asked; ``prefixed()``, whether every program starts with its
    prefix) when they hold more than ``limit`` bytes (None: :data:`GROUP_BYTES`),
    else None (the caller has ``tx`` subroutinize the whole font, as ufo2ft does);
    None too when the programs cannot be grouped (:class:`NotGrouped`).  The
    charstrings come back :class:`Packed`; the programs are read a group at a time.
    ``jobs``: how many groups ``tx`` subroutinizes at once (each run holds about 70
    bytes per byte it reads, :data:`GROUP_BYTES`)."""
    limit = GROUP_BYTES if limit is None else limit
    if int(np.sum(programs.sizes)) <= limit or not programs.prefixed():
        return None     # small, or a program whose advance is not written as the prefix
    try:
        return _grouped(programs.body_sizes(), programs.bodies, programs.prefix, None, limit,
                        jobs)
    except NotGrouped:
        return None


def groups(sizes, limit=GROUP_BYTES):
    """Consecutive groups (start, stop) of programs of ``sizes`` bytes, each at most
    ``limit`` bytes (or one program), the same number of bytes within a program."""
    cum = np.concatenate([[0], np.cumsum(sizes)])
    count = max(1, int(-(-cum[-1] // limit)))
    edges = np.searchsorted(cum, cum[-1] * np.arange(1, count) / count)
    edges = sorted(set(np.clip(edges, 1, len(sizes) - 1).tolist()) | {0, len(sizes)})
    return list(zip(edges[:-1], edges[1:]))


def grouped_subroutines(bodies, prefixes, run_tx=None, limit=GROUP_BYTES):
    """(global subroutines, local subroutines, charstrings) of a name-keyed CFF font
    whose glyphs (in order, ``.notdef`` first) have the Type 2 programs ``bodies``
    without their advances and the width prefixes ``prefixes``
    (:func:`morph.fonts.cff_encoding.width_prefix` for the font's default and nominal
    widths), subroutinized in groups (module docstring), as lists of bytes.
    ``run_tx(args, path)`` runs ``tx`` (None: cffsubr's).  Raises
    :class:`NotGrouped` when the programs do not allow it."""
    gsubrs, lsubrs, chars = _grouped([len(b) for b in bodies], lambda a, b: bodies[a:b],
                                     prefixes.__getitem__, run_tx, limit)
    return gsubrs, lsubrs, list(chars)


def _grouped(sizes, bodies, prefix, run_tx, limit, jobs=1):
    """:func:`grouped_subroutines` of the programs of ``sizes`` bytes (without their
    advances), ``bodies(a, b)`` giving those of glyphs a to b, ``prefix(k)`` glyph
    k's width prefix; the charstrings :class:`Packed`.  Each group's programs are
    read as it is subroutinized, its output packed; ``jobs`` groups at once."""
    spans = groups(sizes, limit)
    budget = max(1, MAX_SUBRS // len(spans))
    parts = _in_threads(lambda span: bodies(*span), spans,
                        lambda group: _subroutinized_group(group, budget, run_tx), jobs)
    n_global = sum(len(g) for g, _, _ in parts)
    n_local = sum(len(loc) for _, loc, _ in parts)
    if max(n_global, n_local) > 65535:
        raise NotGrouped("more subroutines than an INDEX holds")
    out_global, out_local, out_chars = [], [], Packed()
    for i, (a, _) in enumerate(spans):
        gsubrs, lsubrs, chars = parts[i]
        parts[i] = None         # each group's output dropped as it is moved
        moved = _renumbered_in_parts(gsubrs + lsubrs + list(chars),
                                     (len(gsubrs), len(out_global), n_global),
                                     (len(lsubrs), len(out_local), n_local))
        out_global += moved[:len(gsubrs)]
        out_local += moved[len(gsubrs):len(gsubrs) + len(lsubrs)]
        for k, c in enumerate(moved[len(gsubrs) + len(lsubrs):]):
            out_chars.append(prefix(a + k), c)
    return out_global, out_local, out_chars


def _in_threads(read, items, work, jobs):
    """``[work(read(item)) for item in items]`` with up to ``jobs`` works running at
    once in threads (``tx`` runs in its own process; the thread waits on it without
    the GIL).  Each item is read in this thread, in order, when a thread is free for
    it: at most ``jobs`` items read and not yet worked on at a time."""
    if jobs <= 1 or len(items) <= 1:
        return [work(read(item)) for item in items]
    from concurrent.futures import ThreadPoolExecutor

    out, running = [], []
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        for item in items:
            if len(running) == jobs:
                out.append(running.pop(0).result())
            running.append(pool.submit(work, read(item)))
        out.extend(f.result() for f in running)
    return out


def bias(count):
    """The Type 2 subroutine number bias of an INDEX of ``count`` subroutines."""
    return 107 if count < 1240 else 1131 if count < 33900 else 32768


def _group_cff(bodies):
    """A name-keyed CFF table of ``bodies`` (glyphs g1, g2 ... after an empty
    ``.notdef``), no advances (default and nominal width 0), nothing else."""
    from .cff_encoding import _CffDictWriter, _index

    w = _CffDictWriter()
    names = [w.sid("g%d" % k) for k in range(1, len(bodies) + 1)]
    charset = b"\0" + np.asarray(names, ">u2").tobytes()
    charstrings = _index([bytes([_ENDCHAR])] + list(bodies))
    name_index = _index([b"Group"])
    strings = _index([t.encode("latin-1") for t in w.strings])

    def top(at_charset, at_charstrings, at_private):
        return _index([w.offset([15], at_charset) + w.offset([17], at_charstrings)
                       + w.offset([18], 0, at_private)])

    at_charset = 4 + len(name_index) + len(top(0, 0, 0)) + len(strings) + 2
    at_charstrings = at_charset + len(charset)
    at_private = at_charstrings + len(charstrings)
    return b"".join([bytes([1, 0, 4, 4]), name_index,
                     top(at_charset, at_charstrings, at_private), strings, b"\0\0",
                     charset, charstrings])


def tx_runner():
    """cffsubr's runner of its ``tx`` executable (``run(*args, **subprocess_kwargs)``,
    cffsubr's ``_run_embedded_tx``), None where this cffsubr has none.

    The executable is found where cffsubr keeps it, the package's folder, from the
    package's spec: cffsubr's ``__init__`` is not run.  It imports fontTools.ttLib,
    ``importlib.resources`` (with ``typing``, ``zipfile``, ``tempfile``) and ``enum``
    for its own API, about 22 M instructions of a process whose site did not load them
    (a ``morph stroke`` of a .otf uses none of them; cffsubr locates ``tx`` in the
    same folder, through ``importlib.resources``).  Where the file is not there (a
    zipped install) or the package has another layout, cffsubr's own runner is used."""
    import importlib.util

    spec = importlib.util.find_spec("cffsubr")
    folders = list(spec.submodule_search_locations or []) if spec is not None else []
    exe = "tx.exe" if os.name == "nt" else "tx"
    for folder in folders:
        path = os.path.join(folder, exe)
        if os.path.isfile(path) and os.access(path, os.X_OK) \
                and os.path.isfile(os.path.join(folder, "__init__.py")):
            return partial(_run_exe, path)
    import cffsubr

    return getattr(cffsubr, "_run_embedded_tx", None)


def _run_exe(path, *args, **kwargs):
    """``subprocess.run`` of the executable ``path`` with ``args``, what cffsubr's
    ``_run_embedded_tx`` does with its ``tx``."""
    return subprocess.run([path] + [str(a) for a in args], **kwargs)


def _tx(args, path):
    """``tx`` (cffsubr's, :func:`tx_runner`) on the file ``path``; its output's bytes."""
    run = tx_runner()
    if run is None:  # another cffsubr: the caller has it subroutinize the whole font
        raise NotGrouped("this cffsubr does not run tx with arguments")
    try:
        return run(*args, path, check=True, stdout=subprocess.PIPE,
                   stderr=subprocess.PIPE).stdout
    except subprocess.CalledProcessError as exc:
        raise NotGrouped("tx: %s" % exc.stderr.decode(errors="replace").strip()) from exc


def _subroutinized_group(bodies, budget, run_tx=None):
    """(global subroutines, local subroutines, charstrings) ``tx`` makes of one
    group's programs (at most ``budget`` subroutines in each INDEX): lists of bytes,
    the charstrings :class:`Packed`."""
    import tempfile

    from fontTools.cffLib import CFFFontSet

    with tempfile.NamedTemporaryFile(prefix="morph-tx-", delete=False) as f:
        f.write(_group_cff(bodies))
    try:
        data = (run_tx or _tx)(["-cff", "+S", "+b", "-maxs", str(budget)], f.name)
    finally:
        os.remove(f.name)
    cff = CFFFontSet()
    cff.decompile(io.BytesIO(data), None)
    top = cff.topDictIndex[0]
    private = top.Private
    if getattr(private, "defaultWidthX", 0) != 0 or top.charset[1:] != [
            "g%d" % k for k in range(1, len(bodies) + 1)]:
        raise NotGrouped("tx changed the group's widths or glyph order")
    index = top.CharStrings.charStringsIndex

    def raw(items):
        return [bytes(items[k].bytecode) for k in range(len(items))]

    lsubrs = raw(private.Subrs) if "Subrs" in private.rawDict else []
    chars = Packed()
    for k in range(1, len(index)):
        chars.append(index[k].bytecode)
    return raw(cff.GlobalSubrs), lsubrs, chars


def _tokens(data, starts, ends):
    """The first byte of every token of the programs ``data[starts[i]:ends[i]]``, in
    order: each program walked one token a step, all programs at once."""
    pos, end = starts[starts < ends], ends[starts < ends]
    out = []
    while len(pos):
        out.append(pos)
        pos = pos + _TOKEN[data[pos]]
        keep = pos < end
        pos, end = pos[keep], end[keep]
    return np.sort(np.concatenate(out)) if out else np.zeros(0, np.int64)


def _numbers(data, at):
    """The integer operands whose tokens start at ``at`` (one, two or three bytes)."""
    b0 = data[at].astype(np.int64)
    b1 = data[np.minimum(at + 1, len(data) - 1)].astype(np.int64)
    b2 = data[np.minimum(at + 2, len(data) - 1)].astype(np.int64)
    short = (b1 << 8) | b2
    return np.select([(b0 >= 32) & (b0 <= 246), (b0 >= 247) & (b0 <= 250),
                      (b0 >= 251) & (b0 <= 254), b0 == 28],
                     [b0 - 139, (b0 - 247) * 256 + b1 + 108, -(b0 - 251) * 256 - b1 - 108,
                      short - ((short >> 15) << 16)])


def _encoded(values):
    """(bytes, lengths) of Type 2 integer operands ``values`` (|v| < 32768)."""
    v = np.asarray(values, np.int64)
    one, two = np.abs(v) <= 107, (np.abs(v) >= 108) & (np.abs(v) <= 1131)
    size = np.where(one, 1, np.where(two, 2, 3))
    out = np.zeros((len(v), 3), np.int64)
    m = np.abs(v) - 108
    out[:, 0] = np.where(one, v + 139, np.where(two, np.where(v > 0, 247, 251) + (m >> 8), 28))
    out[:, 1] = np.where(two, m & 255, (v >> 8) & 255)
    out[:, 2] = v & 255
    return out[np.arange(3) < size[:, None]].astype(np.uint8), size


#: The most program bytes :func:`_renumbered` takes at once: its arrays hold about 25
#: bytes for every byte of programs (80 MB for 3.2 MB), so a group is renumbered in
#: parts of this many bytes (each program moved alone, the parts give the same bytes).
RENUMBER_BYTES = 1 << 18


def _renumbered_in_parts(programs, glob, local):
    """:func:`_renumbered` of ``programs`` in consecutive parts of about
    :data:`RENUMBER_BYTES` each."""
    out, start, size = [], 0, 0
    for k, p in enumerate(programs):
        size += len(p)
        if size >= RENUMBER_BYTES or k == len(programs) - 1:
            out += _renumbered(programs[start:k + 1], glob, local)
            start, size = k + 1, 0
    return out


def _renumbered(programs, glob, local):
    """``programs`` (bytes) with every subroutine call's number moved: ``glob`` and
    ``local`` are (the group's count, its first subroutine's number in the font,
    the font's count) of the global and local subroutines."""
    sizes = np.array([len(p) for p in programs], np.int64)
    ends = np.cumsum(sizes)
    starts = ends - sizes
    data = np.frombuffer(b"".join(programs), np.uint8)
    tok = _tokens(data, starts, ends)
    if np.isin(data[tok], _HINTS).any():
        raise NotGrouped("a program with hints")
    calls = np.flatnonzero(np.isin(data[tok], (_CALLSUBR, _CALLGSUBR)))
    if not len(calls):
        return list(programs)
    at, owner = tok[calls - 1], np.searchsorted(ends, tok[calls], side="right")
    lead = data[at]
    if (calls == 0).any() or (at < starts[owner]).any() or ((lead < 32) & (lead != 28)).any():
        raise NotGrouped("a subroutine call whose number is not its operand")
    is_global = data[tok[calls]] == _CALLGSUBR
    count, first, total = (np.where(is_global, g, lo) for g, lo in zip(glob, local))
    new = _numbers(data, at) + np.vectorize(bias)(count) + first - np.vectorize(bias)(total)
    code, size = _encoded(new)
    old = _TOKEN[lead]
    keep = np.ones(len(data), bool)
    for k in range(3):                         # drop the old operands' bytes
        keep[at[old > k] + k] = False
    kept_before = np.cumsum(keep) - keep       # kept bytes before each position
    merged = np.insert(data[keep], np.repeat(kept_before[at], size), code)
    grown = np.bincount(owner, size - old, len(programs)).astype(np.int64)
    new_ends = np.cumsum(sizes + grown)
    blob = merged.tobytes()
    return [blob[a:b] for a, b in zip((new_ends - sizes - grown).tolist(), new_ends.tolist())]
