"""A large CFF font subroutinized in groups of glyphs (morph.fonts.subrs).

The oracle is the glyphs' programs before subroutinizing: every charstring of the
grouped font, run with its font's subroutines, must draw the same path (fontTools'
``RecordingPen``) and give the same advance (``T2WidthExtractor``) as the glyph's
own program.  The memory bound is the groups' size: no ``tx`` run is given more than
:data:`morph.fonts.subrs.GROUP_BYTES` of programs (``tx`` holds about 70 bytes per
byte of programs it is given).
"""

import numpy as np
import ufoLib2
from fontTools.misc.psCharStrings import T2CharString, T2WidthExtractor
from fontTools.pens.recordingPen import RecordingPen
from fontTools.ttLib import TTFont

from morph.fonts import subrs
from morph.fonts.brush import ellipse_nib
from morph.fonts.cff_encoding import width_prefix
from morph.fonts.stream import SkeletonSource, compile_outlines
from morph.fonts.stroke import CONTOURS_PER_GLYPH, stroke_ufo

DEFAULT, NOMINAL = 600, 550


def _programs(n, seed=0):
    """``n`` glyphs' unspecialized programs without advances, each a few of a dozen
    shared closed polygons moved (so that ``tx`` finds subroutines) and one of its
    own, and their width prefixes (advances 500-700)."""
    rng = np.random.default_rng(seed)
    shapes = [rng.integers(-200, 200, (rng.integers(4, 9), 2)) for _ in range(12)]
    outlines = []
    for _ in range(n):
        contours = []
        for k in rng.choice(12, 3, replace=False):
            pts = shapes[k] + rng.integers(0, 400, 2)
            contours.append([np.array([pts[i], pts[(i + 1) % len(pts)]], float)
                             for i in range(len(pts))])
        own = rng.integers(0, 600, (5, 2))
        contours.append([np.array([own[i], own[(i + 1) % 5]], float) for i in range(5)])
        outlines.append(contours)
    bodies = [data for data, _ in compile_outlines(outlines, "cff")]
    widths = rng.choice([500, 600, 700], n)
    return bodies, [width_prefix(int(w), DEFAULT, NOMINAL) for w in widths], widths


def _drawn(program, gsubrs=(), lsubrs=()):
    """(path, advance) of a Type 2 program run with these subroutines."""
    from fontTools.cffLib import PrivateDict

    private = PrivateDict()
    private.defaultWidthX, private.nominalWidthX = DEFAULT, NOMINAL
    private.Subrs = [T2CharString(bytecode=b) for b in lsubrs]
    gs = [T2CharString(bytecode=b) for b in gsubrs]
    pen = RecordingPen()
    T2CharString(bytecode=program, private=private, globalSubrs=gs).draw(pen)
    widths = T2WidthExtractor(private.Subrs, gs, NOMINAL, DEFAULT)
    widths.execute(T2CharString(bytecode=program, private=private, globalSubrs=gs))
    return pen.value, widths.width


def test_grouped_subroutines_draw_the_same_glyphs():
    """Three groups: every charstring with the font's subroutines draws its glyph's
    path with its advance; the subroutines are shared (the font is smaller than its
    programs); the calls moved one too far draw other paths (the check can
    fail)."""
    bodies, prefixes, widths = _programs(90)
    limit = sum(map(len, bodies)) // 3 + 1
    assert len(subrs.groups([len(b) for b in bodies], limit)) == 3
    gsubrs, lsubrs, chars = subrs.grouped_subroutines(bodies, prefixes, limit=limit)
    assert gsubrs or lsubrs
    assert sum(map(len, gsubrs + lsubrs + chars)) < 0.8 * sum(map(len, bodies))
    for body, prefix, width, char in zip(bodies, prefixes, widths, chars):
        path, advance = _drawn(char, gsubrs, lsubrs)
        assert (path, advance) == (_drawn(prefix + body)[0], width)
    off = [subrs._renumbered([c], (len(gsubrs), 1, len(gsubrs) + 1),
                             (len(lsubrs), 1, len(lsubrs) + 1))[0] for c in chars[-30:]]
    wrong = 0
    for char, moved in zip(chars[-30:], off):
        try:
            wrong += _drawn(moved, gsubrs + [b"\x0b"], lsubrs + [b"\x0b"])[0] != _drawn(
                char, gsubrs, lsubrs)[0]
        except Exception:  # noqa: BLE001 - a call to a wrong subroutine may not run at all
            wrong += 1
    assert wrong > 0


def test_tx_runs_as_cffsubrs_executable_without_its_package(monkeypatch):
    """The ``tx`` runner is cffsubr's executable, found from the package's spec:
    the group it subroutinizes is byte for byte what cffsubr's own runner makes of
    it, and without the executable in the package's folder (a spec without
    locations) the runner is cffsubr's."""
    import importlib.util
    import os
    import subprocess
    import tempfile

    import cffsubr

    run = subrs.tx_runner()
    assert run.func is subrs._run_exe and os.path.dirname(run.args[0]) == os.path.dirname(
        cffsubr.__file__)
    bodies, _, _ = _programs(30)
    with tempfile.NamedTemporaryFile(suffix=".cff", delete=False) as f:
        f.write(subrs._group_cff(bodies))
    try:
        outputs = [r("-cff", "+S", "+b", f.name, check=True, stdout=subprocess.PIPE).stdout
                   for r in (run, cffsubr._run_embedded_tx)]
    finally:
        os.remove(f.name)
    assert outputs[0] == outputs[1] and len(outputs[0]) > 0
    spec = importlib.util.spec_from_loader("cffsubr", loader=None)   # no folder
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: spec)
    assert subrs.tx_runner() is cffsubr._run_embedded_tx


def test_tokens_and_numbers_read_every_operand_form():
    """The token walk steps over one-, two-, three- and five-byte operands and
    escaped operators; the integer forms decode and encode back."""
    values = [0, 107, -107, 108, -108, 1131, -1131, 1132, -1132, 32767, -32768]
    code, size = subrs._encoded(values)
    assert size.tolist() == [1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3]
    data = np.frombuffer(code.tobytes() + b"\xff\0\x01\0\0" + b"\x0c\x22" + b"\x0e",
                         np.uint8)
    tok = subrs._tokens(data, np.array([0]), np.array([len(data)]))
    assert len(tok) == len(values) + 3
    assert subrs._numbers(data, tok[:len(values)]).tolist() == values


def _skeleton_ufo(path, n, seed=1):
    """A skeleton UFO of ``n`` distinct glyphs of two open polylines each."""
    rng = np.random.default_rng(seed)
    font = ufoLib2.Font()
    font.info.familyName, font.info.unitsPerEm = "Groups", 1000
    for k in range(n):
        g = font.newGlyph("g%03d" % k)
        g.width, g.unicodes = 600 + 50 * (k % 3), [0xE000 + k]
        pen = g.getPointPen()
        for _ in range(2):
            pen.beginPath()
            for j, p in enumerate(rng.integers(100, 700, (3, 2)).tolist()):
                pen.addPoint(tuple(p), "move" if j == 0 else "line")
            pen.endPath()
    font.save(str(path))
    return path


def test_a_large_font_is_subroutinized_in_bounded_groups(tmp_path, monkeypatch):
    """A stroked font whose charstrings pass the group bound: no ``tx`` run reads
    more than the bound (and a program), the glyphs draw what the whole-font
    subroutinizing draws with the same advances, every other table is the same,
    ots passes it, and two workers write the same font as one."""
    import ots  # a test extra: missing, the test fails rather than skips

    ufo = _skeleton_ufo(tmp_path / "src.ufo", 40)
    nib = ellipse_nib(60.0, 15.0, 30.0)

    def stroked(name, jobs=1):
        stroke_ufo(SkeletonSource(str(ufo), light=True), tmp_path / name, nib, tol=0.5,
                   jobs=jobs)
        return TTFont(str(tmp_path / name))

    whole = stroked("whole.otf")
    seen, tx = [], subrs._tx

    def recording(args, path):      # what each tx run reads
        seen.append(open(path, "rb").read())
        return tx(args, path)

    monkeypatch.setattr(subrs, "_tx", recording)
    monkeypatch.setattr(subrs, "GROUP_BYTES", 1500)
    monkeypatch.setattr("morph.fonts.jobs.MIN_SPLIT", 1 / CONTOURS_PER_GLYPH)
    grouped = stroked("grouped.otf")
    assert len(seen) >= 3
    for data in seen:   # each group: its programs (one more at most) and its CFF's
        assert len(data) < 1500 + 500 + 500   # header, names and offsets
    gw, gg = whole.getGlyphSet(), grouped.getGlyphSet()
    assert whole.getGlyphOrder() == grouped.getGlyphOrder()
    for name in whole.getGlyphOrder():
        a, b = RecordingPen(), RecordingPen()
        gw[name].draw(a)
        gg[name].draw(b)
        assert (a.value, gw[name].width) == (b.value, gg[name].width), name
    for tag in whole.reader.keys():
        if tag not in ("CFF ", "head"):
            assert whole.reader[tag] == grouped.reader[tag], tag
    r = ots.sanitize(str(tmp_path / "grouped.otf"), capture_output=True)
    assert r.returncode == 0, r.stderr
    two = stroked("two.otf", jobs=2)
    for tag in grouped.reader.keys():
        if tag != "head":
            assert grouped.reader[tag] == two.reader[tag], tag


def test_a_group_is_renumbered_in_parts_with_bounded_memory(monkeypatch):
    """Renumbering a group's programs in parts of at most ``RENUMBER_BYTES`` gives the
    bytes one pass over them gives (each program is moved alone), with its arrays
    bounded by the part: the peak memory is under 8 times the programs' bytes (their
    renumbered copies and a part's arrays; one pass over them peaks at 25 times)."""
    import tracemalloc

    bodies, _, _ = _programs(1000)
    programs = [b"\x8b\x0a" + b for b in bodies] * 4    # each calls local subroutine 0
    size = sum(map(len, programs))
    glob, local = (10, 0, 2000), (10, 0, 2000)
    whole = subrs._renumbered(programs, glob, local)
    assert whole[0] != programs[0]
    monkeypatch.setattr(subrs, "RENUMBER_BYTES", 1 << 16)
    tracemalloc.start()
    try:
        start = tracemalloc.get_traced_memory()[0]
        parts = subrs._renumbered_in_parts(programs, glob, local)
        peak = tracemalloc.get_traced_memory()[1] - start
    finally:
        tracemalloc.stop()
    assert parts == whole
    assert peak < 8 * size, peak / size


def test_groups_subroutinized_at_once_give_the_serial_groups(monkeypatch):
    """Two ``tx`` runs at a time (``jobs=2``): the same subroutines and charstrings
    as one at a time, the runs did overlap (a slow ``tx`` shows it), and no more
    than two groups were read and not yet subroutinized at once."""
    import threading
    import time

    bodies, prefixes, _ = _programs(60)
    limit = sum(map(len, bodies)) // 4 + 1
    serial = subrs.grouped_subroutines(bodies, prefixes, limit=limit)
    state = {"now": 0, "most": 0, "read": 0, "most_read": 0}
    lock = threading.Lock()

    def slow_tx(args, path):
        with lock:
            state["now"] += 1
            state["read"] -= 1
            state["most"] = max(state["most"], state["now"])
        time.sleep(0.2)
        try:
            return subrs._tx(args, path)
        finally:
            with lock:
                state["now"] -= 1

    def reading(a, b):
        with lock:
            state["read"] += 1
            state["most_read"] = max(state["most_read"], state["read"])
        return bodies[a:b]

    parts = subrs._grouped([len(b) for b in bodies], reading, prefixes.__getitem__, slow_tx,
                           limit, jobs=2)
    assert parts[0] == serial[0] and parts[1] == serial[1]
    assert list(parts[2]) == serial[2]
    assert state["most"] == 2 and state["most_read"] <= 2
