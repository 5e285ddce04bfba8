"""How far each phase of a stroke is from its numpy floor, and what a compiled kernel
(numba) would give instead: issue #38's "say why with figures before reaching for a
compiled dependency".

    python -m bench.numpy_floor [--sets relief,hanzi-300] [--repeat 5] [--cg-chunks 1]
                                [--venv /tmp/numpy_floor_venv] [--no-numba]
                                [--md bench/numpy_floor.md | --no-write]
                                [--json FILE] [--from-json FILE]

The default run takes 4-7 minutes on 2 shared cores (one chunk of hanzi under
callgrind is the longest part), plus a minute for the virtualenv on the first run.

What is measured is the in-process work of ``bench.stroke.run_morph`` (the Relief and
hanzi rows of ``bench/stroke_sets.md``): a set's glyphs with contours in the command's
chunks (``bench.stroke.command_chunks``), each chunk ``stroke_many`` then one
``loops_to_beziers(..., wrap=True)``, the default nib (ellipse 90 x 20 at 30 degrees
per 1000 units per em) at the command's tolerance (0.0005 em) and, for Relief, at
twice it (the setting of ``bench/stroke_sets.md``'s summary).  The phases are those of
``bench/stroke_profile.py`` (the same timers round the same functions, exclusive CPU
time, the corner pass sticky).

1. **Phase times**: CPU time (``time.process_time``) per phase, the median of
   ``--repeat`` passes after one untimed pass: of the first chunk alone (the glyphs
   that callgrind counts: the table) and of all chunks (the whole pass).
2. **Numpy calls and element work**, per phase, from one run of a chunk under
   ``valgrind --tool=callgrind`` (instruction counts, which the machine's load does not
   change): the clock calls ``os.getppid`` at every change of phase and callgrind dumps
   its counters there (``--dump-before=getppid``), so that every dump is one stretch of
   one phase.  In each dump:

   - *numpy calls*: calls from the interpreter (libpython) into numpy's C module,
     deallocations and attribute getters left out; a call that numpy makes through
     libpython into itself (the ufunc an operator slot such as ``array_add`` forwards
     to, the C body behind ``np.concatenate``'s dispatcher) is not counted again: an
     entry counts by the share of its libpython caller's calls that numpy did not
     make (a fixed point over the call graph).  ``a.max()`` counts two (the method,
     and the reduction its Python part calls);
   - *element instructions*: those of numpy's typed inner loops (``DOUBLE_add``,
     casts, copies, sorts, fancy-index loops), of libm, BLAS and pyclipper, and of the
     ``memcpy``/``memset``/``memmove`` numpy calls: the work that grows with the
     elements;
   - the rest (the interpreter running morph, numpy's argument parsing, dispatch,
     dtype resolution, allocation) is *overhead*: what the phase would cost with the
     same calls on empty arrays.

3. **Per-call cost**: CPU microseconds per call of typical numpy calls on 8-element
   arrays (operator, ufunc, ``np.where``, fancy and boolean indexing, reduction,
   ``np.concatenate``, ``np.empty``, slice, small ``@``), in a loop of 20,000 (the
   loop's own cost taken off), median of 5.

The *floor* of a phase is numpy calls x the median per-call cost: what the phase
cannot go below with its present number of calls, however small its arrays.  The
element share (element instructions / all instructions of the phase) times the phase's
time estimates its element work the other way; the two are printed side by side.  The
element loops run more instructions per cycle (SIMD, no branches) than the
interpreter and numpy's dispatch, so by time their share is smaller still: both
estimates lean towards element work.

4. **numba** (``--no-numba`` skips): in a separate virtualenv (``--venv``, made with
   ``python -m venv`` and ``pip install numba numpy==<this numpy>`` when missing; never
   this interpreter), the install's size on disk, the wheels a
   release has for the users' platforms (``pip install --dry-run --platform``), the
   import time, and one representative kernel rewritten as loops, the trim's chord
   distance (:func:`morph.polyline._chord_distance`, the largest distance of a piece's
   control points to its chord), on the stacks of pieces a Relief pass gives it
   (recorded here), against morph's numpy version on the same stacks (the results
   compared): the JIT's compile time on the first call without and with ``cache=True``
   (a fresh process loading the cache), and the per-call times.
"""

import argparse
import collections
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the morph command sets it

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))  # after PYTHONPATH: a checkout named there is measured

import numpy as np  # noqa: E402 - needs sys.path with the repo root

from bench.stroke_profile import (ORDER, Clock,  # noqa: E402 - needs sys.path with the repo root
                                  install, shown_args)
from bench.stamp import emit  # noqa: E402 - needs sys.path with the repo root

BROAD = (90.0, 20.0, 30.0)   # the command's default nib per 1000 units per em
SET_TOL = 0.0005             # the command's default tolerance, in em
#: the phases an in-process pass runs (no startup, parse of the UFO, font tables...)
SHOWN = [p for p in ORDER if p not in ("startup", "font tables", "compile",
                                       "sample + specimen", "imports (lazy)")]
NUMPY_SO = "_multiarray_umath"


# =========================================================================== inputs

def set_ufo(name):
    """The skeleton UFO of set ``name`` (:mod:`bench.skeletons`; Relief: the whole font
    of the shared data folder, else tests/data's subset)."""
    from bench.skeletons import shared_relief, skeleton_ufo

    if name == "relief":
        subset = ROOT / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo"
        return shared_relief() or subset
    return skeleton_ufo(name)


def set_inputs(name):
    """(chunks [(glyph names, skeleton paths)], nib region, [tolerances]) of set
    ``name`` as ``bench/stroke.py``'s set rows take it: the glyphs with a contour of
    more than one point, the default nib scaled to the em, the command's tolerance
    (and twice it for Relief, the setting of the summary)."""
    from bench.stroke import command_chunks
    from morph.fonts.brush import ellipse_nib
    from morph.parse.ufo import load_ufo

    font = load_ufo(set_ufo(name), lazy=False)
    names = [g.name for g in sorted(font, key=lambda g: g.name)
             if any(len(c) > 1 for c in g.contours)]
    upm = float(font.info.unitsPerEm or 1000)
    nib = ellipse_nib(BROAD[0] * upm / 1000, BROAD[1] * upm / 1000, BROAD[2])
    chunks = command_chunks(font, names)
    tols = [SET_TOL * upm] + ([2 * SET_TOL * upm] if name == "relief" else [])
    return chunks, nib, tols


def one_pass(chunks, nib, tol):
    """The in-process work of ``bench.stroke.run_morph``: each chunk stroked together,
    then all its loops exported in one call."""
    from morph.budget import plan
    from morph.export import loops_to_beziers
    from morph.stroke import stroke_many

    geometry, export = plan(tol)[:2]
    out = []
    for _, sets in chunks:
        regions = stroke_many(sets, nib, geometry)
        out.append(loops_to_beziers([lp for r in regions for lp in r], export, wrap=True))
    return out


def timed_phases(clock, chunks, nib, tol, repeat):
    """{phase: median CPU s of ``repeat`` passes} (after one untimed pass: lazy
    imports, caches of quadrature nodes), and the median pass's whole CPU s."""
    import gc

    one_pass(chunks, nib, tol)
    gc.freeze()    # as the command freezes what its process holds when it starts
    try:
        passes = clock.passes(lambda: one_pass(chunks, nib, tol), repeat)
    finally:
        gc.unfreeze()
    phases = {p: statistics.median(s.get(p, 0.0) for s in passes) for p in ORDER}
    return phases, statistics.median(sum(s.values()) for s in passes)


# =========================================================================== per call

def _tiny_calls():
    """{name: (statement, setup)} of typical numpy calls on 8-element arrays."""
    setup = ("import numpy as np; a = np.linspace(0, 1, 8); b = a[::-1].copy(); "
             "m = a > 0.5; i = np.array([0, 3, 5]); s = np.ones((3, 3))")
    return {"operator a + b": ("a + b", setup), "ufunc np.hypot(a, b)": ("np.hypot(a, b)", setup),
            "np.where(m, a, b)": ("np.where(m, a, b)", setup),
            "fancy index a[i]": ("a[i]", setup), "boolean mask a[m]": ("a[m]", setup),
            "reduction a.max()": ("a.max()", setup),
            "np.maximum.reduce(a)": ("np.maximum.reduce(a)", setup),
            "np.concatenate((a, b))": ("np.concatenate((a, b))", setup),
            "np.empty(8)": ("np.empty(8)", setup), "slice a[1:-1]": ("a[1:-1]", setup),
            "np.cumsum(a)": ("np.cumsum(a)", setup), "3x3 matmul s @ s": ("s @ s", setup)}


def per_call_us(number=20000, repeat=5):
    """{name: CPU microseconds per call} of :func:`_tiny_calls`, the loop's own cost
    (a ``pass`` statement) taken off; the median of ``repeat`` timings."""
    import timeit

    def cpu(stmt, setup):
        t = timeit.Timer(stmt, setup, timer=time.process_time)
        return statistics.median(t.repeat(repeat, number)) / number

    empty = cpu("pass", "")
    return {k: 1e6 * max(cpu(*v) - empty, 0.0) for k, v in _tiny_calls().items()}


# =========================================================================== callgrind

class MarkClock(Clock):
    """A :class:`Clock` that, while ``marking``, logs the phase of each stretch that
    ends at a change of phase and calls ``os.getppid`` there: under callgrind
    (``--dump-before=getppid``) every dump is then one stretch of one phase."""

    def __init__(self):
        super().__init__()
        self.marking, self.log = False, []

    def mark(self, phase):
        if self.marking:
            self.log.append(phase)
            os.getppid()

    def enter(self, phase):
        old = self.stack[-1]
        super().enter(phase)
        if self.stack[-1] != old:
            self.mark(old)

    def leave(self):
        old = self.stack[-1]
        super().leave()
        if self.stack[-1] != old:
            self.mark(old)


def cg_worker(name, tol, nchunks, log_path):
    """One pass over the first ``nchunks`` chunks of set ``name`` with marks (the
    child of :func:`callgrind_phases`); the phases of the dumps go to ``log_path``."""
    chunks, nib, _ = set_inputs(name)
    chunks = chunks[:nchunks]
    clock = MarkClock()
    install(clock)
    # untimed: lazy imports and caches, on a few glyphs (the pass under callgrind is slow)
    one_pass([(chunks[0][0][:4], chunks[0][1][:4])], nib, tol)
    clock.stack = ["other"]
    clock.marking = True
    os.getppid()            # dump 1: everything before the pass
    one_pass(chunks, nib, tol)
    clock.mark(clock.stack[-1])
    clock.marking = False
    glyphs = sum(len(c) for c, _ in chunks)
    Path(log_path).write_text(json.dumps({"log": clock.log, "glyphs": glyphs}))


def callgrind_phases(name, tol, nchunks, tmp):
    """Start :func:`cg_worker` under callgrind; {phase: Counter of the dumps' counts
    (:func:`dump_counts`)} and the glyphs of the pass."""
    out, log = Path(tmp) / ("%s.cg" % name), Path(tmp) / ("%s.json" % name)
    cmd = ["valgrind", "--tool=callgrind", "--dump-before=getppid", "--dump-line=no",
           "--callgrind-out-file=%s" % out, sys.executable, "-m", "bench.numpy_floor",
           "--cg-worker", json.dumps([name, tol, nchunks, str(log)])]
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if proc.returncode:
        raise SystemExit("callgrind run of %s failed:\n%s" % (name, proc.stderr[-3000:]))
    got = json.loads(log.read_text())
    per = collections.defaultdict(collections.Counter)
    for k, phase in enumerate(got["log"]):
        dump = Path("%s.%d" % (out, k + 2))     # dump 1 is before the pass
        per[phase].update(dump_counts(dump))
        per[phase]["stretches"] += 1
        dump.unlink()
    for extra in Path(tmp).glob("%s.cg*" % name):
        extra.unlink()
    return per, got["glyphs"]


#: numpy's functions whose work is a loop over the elements (matched on the function's
#: name): the typed inner loops of ufuncs and reductions (``DOUBLE_add``), casts and
#: copies, fancy and boolean indexing's loops, sorts, einsum's sums of products, and
#: the few array functions that loop inline (``PyArray_Where``, ``PyArray_TakeFrom``);
#: some of these also have a fixed part, so the element share is an upper bound
ELEMENT = re.compile(r"^(BOOL|U?BYTE|U?SHORT|U?INT|U?LONG|U?LONGLONG|HALF|C?FLOAT|C?DOUBLE"
                     r"|C?LONGDOUBLE|OBJECT|TIMEDELTA|DATETIME)_|_to_contig|_to_strided"
                     r"|_contig_to_|_contig_cast|_strided_cast|_aligned_cast"
                     r"|^mapiter_\w*(get|set)$|sort|partition|avx2_vector|avx512"
                     r"|sum_of_products|^PyArray_(TakeFrom|PutTo|TransferNDimToStrided"
                     r"|TransferStridedToNDim|Where|Nonzero|Repeat)$|^array_boolean_subscript$"
                     r"|^npyiter_copy_(to|from)_buffers$|^raw_array_\w+$|_fill$|^reduce_loop$")
SCALAR = re.compile(r"_(setitem|getitem)$")    # one element of a Python scalar: per call
MEMFUNCS = re.compile(r"^__(memcpy|memmove|memset)")


def _is_numpy(ob):
    return "/numpy/" in ob or "numpy.libs" in ob


def _is_element_object(ob):
    """libm, BLAS and pyclipper's C++ (the polygon clipping of the trim's Clipper
    phase): all their instructions are element work."""
    return "libm.so" in ob or "openblas" in ob or "_pyclipper" in ob


def _parse_dump(path):
    """(summary Ir, {(object, function): self Ir}, {(caller object, caller, callee
    object, callee): [calls, inclusive Ir]}) of one callgrind dump."""
    names, objs = {}, {}
    self_ir, edges = collections.Counter(), collections.defaultdict(lambda: [0, 0])
    ob = fn = cob = cfn = pending = None
    total = 0

    def name(table, text):
        m = re.match(r"\((\d+)\)(?: (.*))?", text)
        if m is None:
            return text
        if m.group(2) is not None:
            table[m.group(1)] = m.group(2)
        return table[m.group(1)]

    with open(path) as f:
        for line in f:
            head = line[:1]
            if head.isdigit() or head in "+-*":
                parts = line.split()
                if pending is not None:
                    edges[pending][1] += int(parts[1]) if len(parts) > 1 else 0
                    pending = None
                elif len(parts) > 1:
                    self_ir[ob, fn] += int(parts[1])
            elif line.startswith("ob="):
                ob = name(objs, line[3:].strip())
            elif line.startswith("fn="):
                fn, cob = name(names, line[3:].strip()), None
            elif line.startswith("cob="):
                cob = name(objs, line[4:].strip())
            elif line.startswith("cfn="):
                cfn = name(names, line[4:].strip())
            elif line.startswith("calls="):
                pending = (ob, fn, cob or ob, cfn)
                edges[pending][0] += int(line[6:].split()[0])
                cob = None
            elif line.startswith("summary:"):
                total = int(line.split()[1])
    return total, self_ir, edges


def _counted(callee):
    """Whether an entry into numpy's C module at ``callee`` counts as a numpy call:
    not a deallocation nor an attribute getter (``a.shape``: tens of instructions)."""
    return not (callee.endswith("_dealloc") or callee.endswith("_get"))


def _nested_share(edges, rounds=8):
    """{libpython function: the share of its calls made, directly or through other
    libpython functions, by numpy} (a fixed point over the call graph)."""
    into, direct, inner = collections.Counter(), collections.Counter(), []
    for (ob, fn, cob, cfn), (calls, _) in edges.items():
        if "libpython" not in cob:
            continue
        into[cfn] += calls
        if _is_numpy(ob):
            direct[cfn] += calls
        elif "libpython" in ob and fn != cfn:
            inner.append((fn, cfn, calls))
    share = {f: direct[f] / into[f] for f in into if into[f]}
    for _ in range(rounds):
        got = collections.Counter(direct)
        for fn, cfn, calls in inner:
            got[cfn] += calls * share.get(fn, 0.0)
        share = {f: min(1.0, got[f] / into[f]) for f in into if into[f]}
    return share


def dump_counts(path):
    """Counter of one dump: ``ir`` (all instructions), ``element`` (numpy's element
    loops, libm, BLAS, the mem* calls of numpy), ``numpy_ir`` (numpy's own), ``calls``
    (numpy calls from the interpreter).  An entry from a libpython function that numpy
    itself calls (``object_vacall`` of an operator slot forwarding to its ufunc,
    ``cfunction_vectorcall_*`` of ``np.concatenate``'s dispatcher calling its C body,
    the interpreter running ``a.max()``'s Python part) counts in the share of that
    function's calls that did not come from numpy (:func:`_nested_share`)."""
    total, self_ir, edges = _parse_dump(path)
    out = collections.Counter(ir=total)
    for (ob, fn), ir in self_ir.items():
        if _is_element_object(ob):
            out["element"] += ir
        elif _is_numpy(ob):
            out["numpy_ir"] += ir
            if ELEMENT.search(fn or "") and not SCALAR.search(fn or ""):
                out["element"] += ir
    share = _nested_share(edges)
    for (ob, fn, cob, cfn), (calls, incl) in edges.items():
        if _is_numpy(ob) and MEMFUNCS.match(cfn or ""):
            out["element"] += incl
        elif "libpython" in ob and _is_numpy(cob) and _counted(cfn or ""):
            out["calls"] += calls * (1.0 - share.get(fn, 0.0))
    return out



# =========================================================================== numba

def chord_distance_loops(parts):
    """:func:`morph.polyline._chord_distance` written as loops over the pieces and
    their inner control points (the same formulas: :func:`morph.polyline._to_chords`),
    for numba."""
    m, k = parts.shape[0], parts.shape[1]
    out = np.zeros(m)
    for i in range(m):
        ax, ay = parts[i, 0, 0] / parts[i, 0, 2], parts[i, 0, 1] / parts[i, 0, 2]
        bx = parts[i, k - 1, 0] / parts[i, k - 1, 2]
        by = parts[i, k - 1, 1] / parts[i, k - 1, 2]
        cx, cy = bx - ax, by - ay
        length = math.hypot(cx, cy)
        point = length == 0
        safe = length if length > 0 else 1.0
        best = 0.0
        for j in range(1, k - 1):
            px, py = parts[i, j, 0] / parts[i, j, 2], parts[i, j, 1] / parts[i, j, 2]
            rx, ry = px - ax, py - ay
            dist = abs(cx * ry - cy * rx) / safe
            along = (rx * cx + ry * cy) / safe / safe
            if along < 0 or point:
                dist = math.hypot(rx, ry)
            if along > 1 and not point:
                dist = math.hypot(px - bx, py - by)
            best = max(best, dist)
        out[i] = best
    return out


def chord_ends_loops(parts):
    """The ends (ax, ay, bx, by) of each piece of a stack, as loops: a second, small
    kernel, whose compile and cache load are what each further kernel adds."""
    m, k = parts.shape[0], parts.shape[1]
    out = np.empty((m, 4))
    for i in range(m):
        out[i, 0], out[i, 1] = parts[i, 0, 0] / parts[i, 0, 2], parts[i, 0, 1] / parts[i, 0, 2]
        out[i, 2] = parts[i, k - 1, 0] / parts[i, k - 1, 2]
        out[i, 3] = parts[i, k - 1, 1] / parts[i, k - 1, 2]
    return out


def record_chord_stacks(chunks, nib, tol, path):
    """Run one pass with :func:`morph.polyline._chord_distance` recording its stacks
    (C-contiguous copies) into ``path`` (.npz); the number of calls."""
    import morph.polyline as pl

    orig, stacks = pl._chord_distance, []

    def recording(parts):
        stacks.append(np.ascontiguousarray(parts, dtype=float))
        return orig(parts)

    pl._chord_distance = recording
    try:
        one_pass(chunks, nib, tol)
    finally:
        pl._chord_distance = orig
    np.savez(path, *stacks)
    return len(stacks)


def _cpu(fn, repeat=5):
    """Median CPU s of ``repeat`` calls of ``fn``."""
    out = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        out.append(time.process_time() - t0)
    return statistics.median(out)


def numba_worker(stacks_path, out_path, cold):
    """In the virtualenv: import numba, compile :func:`chord_distance_loops` with
    ``cache=True`` (``cold``: the cache folder empty; else loaded from it), then
    :func:`chord_ends_loops` (what a further kernel adds); when ``cold``, compile the
    first again without the cache, time it and morph's numpy version on the recorded
    stacks and compare their results; JSON to ``out_path``."""
    t0 = time.process_time()
    import numba

    got = {"import_s": time.process_time() - t0, "numba": numba.__version__,
           "numpy": np.__version__}
    from morph.polyline import _chord_distance

    with np.load(stacks_path) as z:
        stacks = [z["arr_%d" % k] for k in range(len(z.files))]
    cached = numba.njit(cache=True)(chord_distance_loops)
    t0 = time.process_time()
    cached(stacks[0])
    got["first_call_cache_s"] = time.process_time() - t0
    second = numba.njit(cache=True)(chord_ends_loops)
    t0 = time.process_time()
    second(stacks[0])
    got["second_kernel_cache_s"] = time.process_time() - t0
    if cold:
        plain = numba.njit(cache=False)(chord_distance_loops)
        t0 = time.process_time()
        plain(stacks[0])
        got["first_call_nocache_s"] = time.process_time() - t0
        for st in stacks:   # every layout and shape compiled before the timing
            plain(st)
        got["numpy_s"] = _cpu(lambda: [_chord_distance(st) for st in stacks])
        got["numba_s"] = _cpu(lambda: [plain(st) for st in stacks])
        diff = [float(np.max(np.abs(plain(st) - _chord_distance(st)), initial=0.0))
                for st in stacks]
        got.update(calls=len(stacks), max_abs_diff=max(diff),
                   differ=sum(d > 0 for d in diff),
                   pieces=sum(len(st) for st in stacks))
    Path(out_path).write_text(json.dumps(got))



#: the platforms whose wheels a release is asked for (pip's --platform tags)
PLATFORMS = ("manylinux_2_28_x86_64", "manylinux_2_28_aarch64", "win_amd64", "win_arm64",
             "macosx_14_0_arm64", "macosx_14_0_x86_64", "musllinux_1_2_x86_64")


def ensure_venv(venv):
    """The virtualenv's python, made (``python -m venv``, ``pip install numba
    numpy==<this numpy>``, binary wheels only) when missing; and the install's CPU s
    (None when it existed)."""
    py = Path(venv) / "bin" / "python"
    if py.exists():
        return py, None
    t0 = time.time()
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(py), "-m", "pip", "install", "--quiet", "--only-binary=:all:",
                    "numba", "numpy==%s" % np.__version__], check=True)
    return py, time.time() - t0


def wheel_platforms(py, numba_version, llvmlite_version):
    """{platform: [numba wheel, llvmlite wheel], or the last release with a wheel
    there ("last wheel: numba X"), or None} of :data:`PLATFORMS` for Python 3.11, from
    pip's resolver (``--dry-run --report``, no install)."""
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for plat in PLATFORMS:
            rep = Path(tmp) / (plat + ".json")
            proc = subprocess.run([str(py), "-m", "pip", "install", "--dry-run", "--quiet",
                            "--ignore-installed", "--only-binary=:all:", "--no-deps",
                            "--platform", plat, "--python-version", "3.11", "--target",
                            str(Path(tmp) / "t"), "--report", str(rep),
                            "numba==" + numba_version, "llvmlite==" + llvmlite_version],
                           capture_output=True, text=True, timeout=300)
            if rep.exists():
                out[plat] = [i["download_info"]["url"].rsplit("/", 1)[-1]
                             for i in json.loads(rep.read_text())["install"]]
            else:   # the releases that have a wheel there: the last one, if any
                found = re.search(r"numba.*?from versions: ([^)]*)\)", proc.stderr)
                final = [x.strip() for x in (found.group(1) if found else "").split(",")
                         if re.fullmatch(r"[\d.]+", x.strip())]
                out[plat] = None if not final else "last wheel: numba " + final[-1]
    return out


def _du(path):
    return sum(f.stat().st_size for f in Path(path).rglob("*") if f.is_file())


def numba_figures(venv, stacks_path):
    """What numba gives (see the module doc, part 4)."""
    py, install_s = ensure_venv(venv)
    site = next(Path(venv).glob("lib/python*/site-packages"))
    versions = dict(d.name.removesuffix(".dist-info").split("-")[:2]
                    for d in site.glob("*.dist-info"))
    sizes = {p: _du(site / p) for p in ("numba", "llvmlite", "numpy")}
    meta = (site / ("numba-%s.dist-info" % versions["numba"]) / "METADATA").read_text()
    needs = re.findall(r"^Requires-(?:Dist: (?:numpy|llvmlite)|Python:)\s*(.*)$", meta, re.M)
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    runs = []
    with tempfile.TemporaryDirectory() as cache:
        env["NUMBA_CACHE_DIR"] = cache
        for cold in (True, False):
            out = Path(cache) / ("run%d.json" % len(runs))
            proc = subprocess.run([str(py), "-m", "bench.numpy_floor", "--numba-worker",
                                   json.dumps([str(stacks_path), str(out), cold])], cwd=ROOT,
                                  env=env, capture_output=True, text=True)
            if proc.returncode:
                raise SystemExit("numba worker failed:\n" + proc.stderr[-3000:])
            runs.append(json.loads(out.read_text()))
    bare = subprocess.run([str(py), "-c", "import time, numpy; t = time.process_time(); "
                           "import numba; print(time.process_time() - t)"], env=env,
                          capture_output=True, text=True)
    return {"versions": versions, "sizes": sizes, "install_s": install_s, "cold": runs[0],
            "requires": needs,
            "warm": runs[1], "import_again_s": float(bare.stdout.strip() or "nan"),
            "wheels": wheel_platforms(py, versions["numba"], versions["llvmlite"])}



# =========================================================================== runs

def measure(opt, tmp):
    """Everything the report shows: {"calls_us", "sets": [...], "numba"}.  The timings
    first, alone; then the callgrind runs (instruction counts, whatever else runs)
    beside the numba part."""
    names = opt.sets.split(",")
    out = {"calls_us": per_call_us(), "sets": []}
    print("per call:", {k: round(v, 2) for k, v in out["calls_us"].items()}, flush=True)
    clock = Clock()
    install(clock)
    stacks = Path(tmp) / "stacks.npz"
    for name in names:
        chunks, nib, tols = set_inputs(name)
        glyphs = sum(len(c) for c, _ in chunks)
        row = {"name": name, "glyphs": glyphs, "chunks": [len(c) for c, _ in chunks],
               "tols": tols, "timed": [], "repeat": opt.repeat}
        for tol in tols:
            phases, total = timed_phases(clock, chunks, nib, tol, opt.repeat)
            row["timed"].append({"tol": tol, "phases": phases, "total": total})
            print("%s tol %g: %.2f ms / glyph" % (name, tol, 1000 * total / glyphs), flush=True)
        # the chunk that callgrind counts, timed alone: the table's times and counts
        # are of the same glyphs
        row["first"] = timed_phases(clock, chunks[:opt.cg_chunks], nib, tols[0], opt.repeat)[0]
        if name == "relief" and not opt.no_numba:
            row["chord_calls"] = record_chord_stacks(chunks, nib, tols[0], stacks)
        out["sets"].append(row)
    children = {n: _start_callgrind(n, opt.cg_chunks, tmp) for n in names}
    if stacks.exists():
        out["numba"] = numba_figures(opt.venv, stacks)
    for row in out["sets"]:
        row["cg"], row["cg_glyphs"] = _finish_callgrind(children[row["name"]])
    return out


def _start_callgrind(name, nchunks, tmp):
    """:func:`callgrind_phases` of set ``name`` in a thread (its child process runs
    beside the numba part's timings: CPU times, each process its own)."""
    import concurrent.futures

    pool = concurrent.futures.ThreadPoolExecutor(1)
    folder = Path(tmp) / ("cg-" + name)
    folder.mkdir()
    tol = SET_TOL * _upm(name)
    return pool, pool.submit(callgrind_phases, name, tol, nchunks, folder)


def _finish_callgrind(child):
    pool, future = child
    try:
        return future.result()
    finally:
        pool.shutdown()


def _upm(name):
    from morph.parse.ufo import load_ufo

    return float(load_ufo(set_ufo(name)).info.unitsPerEm or 1000)



# =========================================================================== report

def phase_rows(row, per_call):
    """[(phase, ms / glyph, numpy calls / glyph, M instructions / glyph, element share,
    floor ms / glyph, element ms / glyph)] of the chunks of a set that callgrind ran, at
    its first tolerance, and the total row."""
    first, cg, m = row["first"], row["cg"], row["cg_glyphs"]
    out = []
    for p in SHOWN + ["total"]:
        keys = SHOWN if p == "total" else [p]
        ms = 1000.0 * sum(first.get(k, 0.0) for k in keys) / m
        got = collections.Counter()
        for k in keys:
            got.update(cg.get(k, {}))
        calls, ir = got["calls"] / m, got["ir"] / m
        share = got["element"] / got["ir"] if got["ir"] else 0.0
        out.append((p, ms, calls, ir / 1e6, share, calls * per_call / 1000.0, share * ms))
    return out


def set_table(row, per_call):
    md = ["| phase | ms / glyph | numpy calls / glyph | M instructions / glyph | "
          "element share of instructions | floor: calls x %.2f µs, ms / glyph | floor / "
          "phase time | element work, ms / glyph |" % per_call, "|---|---|---|---|---|---|---|---|"]
    for p, ms, calls, mir, share, floor, elem in phase_rows(row, per_call):
        if p != "total" and ms < 0.005 and calls < 1:
            continue
        cells = ["%.2f" % ms, "%.0f" % calls, "%.1f" % mir, "%.0f %%" % (100 * share),
                 "%.2f" % floor, "%.0f %%" % (100 * floor / ms if ms else 0), "%.2f" % elem]
        if p == "total":
            cells = ["**%s**" % c for c in cells]
            p = "**total**"
        md.append("| %s | %s |" % (p, " | ".join(cells)))
    return md


def calls_md(calls_us):
    med = statistics.median(calls_us.values())
    md = ["## 1. What a numpy call costs here", "",
          "CPU µs per call on 8-element float arrays (a loop of 20,000 calls, its own "
          "cost taken off, the median of 5); median of the calls: **%.2f µs**, the cost "
          "the floors below use." % med, "",
          "| call | µs |", "|---|---|"]
    md += ["| `%s` | %.2f |" % (k, v) for k, v in calls_us.items()]
    return md, med



def numba_md(nb, glyphs):
    """Section 3: numba's install, wheels, import, JIT and the kernel's speed."""
    cold, warm, mb, v = nb["cold"], nb["warm"], 1024.0 * 1024.0, nb["versions"]
    have = [p for p, w in nb["wheels"].items() if isinstance(w, list)]
    lack = ["%s (%s)" % (p, w or "no release has one") for p, w in nb["wheels"].items()
            if not isinstance(w, list)]
    return ["## 3. A compiled kernel: numba", "",
            "numba %s with llvmlite %s and numpy %s, in a separate virtualenv (`pip install "
            "--only-binary=:all: numba numpy==%s`%s); numba's metadata: %s."
            % (v["numba"], v["llvmlite"], v["numpy"], v["numpy"],
               "" if nb["install_s"] is None else
               ", %.0f s of wall time with the venv" % nb["install_s"],
               "; ".join("`%s`" % r for r in nb["requires"])), "",
            "- **size on disk**: numba %.0f MB + llvmlite %.0f MB (numpy itself: %.0f MB);"
            % (nb["sizes"]["numba"] / mb, nb["sizes"]["llvmlite"] / mb,
               nb["sizes"]["numpy"] / mb),
            "- **wheels of this release for Python 3.11** (pip's resolver, `--platform`): "
            "%s; **none** for %s: there pip installs an older release, if one has a wheel "
            "and accepts this numpy, or builds llvmlite from source (which needs LLVM);"
            % (", ".join(have) or "none", ", ".join(lack) or "-"),
            "- **import** (after numpy): %.0f, %.0f and %.0f ms of CPU in three fresh "
            "processes;" % (1000 * cold["import_s"], 1000 * warm["import_s"],
                            1000 * nb["import_again_s"]),
            "- **JIT, first call**: a process's first compile (`cache=True`, writing the "
            "cache) %.0f ms, a second small kernel then %.0f ms, the first kernel again "
            "without the cache %.0f ms; a fresh process loading the cached code: %.0f ms "
            "for the first kernel, %.0f ms for the second;"
            % (1000 * cold["first_call_cache_s"], 1000 * cold["second_kernel_cache_s"],
               1000 * cold["first_call_nocache_s"], 1000 * warm["first_call_cache_s"],
               1000 * warm["second_kernel_cache_s"]),
            "- **the kernel**: the trim's chord distance (`morph.polyline._chord_distance`, "
            "the largest distance of a piece's control points to its chord) on the %d "
            "stacks (%d pieces) a Relief pass at the command's tolerance gives it: numpy "
            "%.1f ms, numba loops %.1f ms per pass (x %.1f faster); the results equal on "
            "%d of %d stacks (largest difference %.1e); saved %.3f ms per glyph of the %d."
            % (cold["calls"], cold["pieces"], 1000 * cold["numpy_s"],
               1000 * cold["numba_s"], cold["numpy_s"] / max(cold["numba_s"], 1e-9),
               cold["calls"] - cold["differ"], cold["calls"], cold["max_abs_diff"],
               1000.0 * (cold["numpy_s"] - cold["numba_s"]) / glyphs, glyphs)]


def stroke_sets_relief():
    """(morph's whole command, FontForge worker's) ms per glyph of Relief in
    bench/stroke_sets.md's summary (the FontForge settings' range), or None."""
    from bench.mdtable import tables

    path = ROOT / "bench" / "stroke_sets.md"
    if not path.exists():
        return None
    table = tables(path.read_text(encoding="utf-8"))[0]
    head = table[0]
    rows = [r for r in table[1:] if r[0] == "relief"]
    if not rows or "whole command: morph" not in head:
        return None
    got = [(float(r[head.index("whole command: morph")]),
            float(r[head.index("whole command: FontForge worker")])) for r in rows]
    return max(m for m, _ in got), (min(f for _, f in got), max(f for _, f in got))


def conclusions_md(out, per_call):
    """Section 4: the figures the issue asks for, from the sections above."""
    rel = next((r for r in out["sets"] if r["name"] == "relief"), None)
    if rel is None:
        return []
    rows = {r[0]: r for r in phase_rows(rel, per_call)}
    total = rows.pop("total")
    at_floor = ["%s %.0f %%" % (p, 100 * r[5] / r[1]) for p, r in rows.items()
                if r[1] >= 0.02 and r[5] >= 0.5 * r[1]]
    mostly = ["%s %.0f %%" % (p, 100 * (1 - r[4])) for p, r in rows.items()
              if r[1] >= 0.02 and r[4] < 0.5 and r[5] < 0.5 * r[1]]
    n, overhead = rel["glyphs"], total[1] - total[6]
    md = ["## 4. Conclusions", "",
          "- **At the numpy floor on Relief** (numpy calls x %.2f µs is half the phase's "
          "time or more: only fewer calls, not smaller work, makes them faster): %s.  "
          "**Mostly overhead** (more than half of the instructions outside numpy's element "
          "loops, the interpreter's share of morph's own code included): %s."
          % (per_call, ", ".join(at_floor) or "none", ", ".join(mostly) or "none"),
          "- **Relief in process** (first chunk): %.2f ms per glyph, %.0f numpy calls per "
          "glyph (%.2f ms at %.2f µs each); element work %.2f ms (%.0f %% of the "
          "instructions), overhead %.2f ms.  A compiled rewrite of *every* phase that kept "
          "the element work at numpy's speed and removed all the rest would save at most "
          "%.2f ms per glyph, %.2f s over Relief's %d glyphs."
          % (total[1], total[2], total[5], per_call, total[6], 100 * total[4], overhead,
             overhead, overhead * n / 1000.0, n)]
    md.append(_largest_floors(rel, rows))
    return md + _other_sets(out, per_call) + _numba_conclusion(out.get("numba"), n,
                                                               overhead * n / 1000.0)


def _largest_floors(row, rows):
    """The line naming Relief's three largest floors and their calls per chunk."""
    top = sorted(rows.values(), key=lambda r: -r[5])[:3]
    chunk = row["cg_glyphs"]
    return ("- **Largest floors on Relief**: %s.  In numpy, what lowers them is fewer "
            "calls per chunk (fewer rounds or levels, fewer steps a round), not less work "
            "per call." % ", ".join("%s %.2f ms per glyph (%s numpy calls per chunk of %d "
                                    "glyphs)" % (r[0], r[5], format(round(r[2] * chunk), ","),
                                                 chunk) for r in top))


def _other_sets(out, per_call):
    """A line on each set other than Relief: its totals, to set Relief's apart."""
    md, rel = [], next(r for r in out["sets"] if r["name"] == "relief")
    share = phase_rows(rel, per_call)[-1][4]
    for row in out["sets"]:
        if row["name"] == "relief":
            continue
        total = phase_rows(row, per_call)[-1]
        md.append("- **%s** (first chunk): %.2f ms per glyph, %.0f numpy calls per glyph "
                  "(%.2f ms, %.0f %% of its time), element work %.0f %% of the "
                  "instructions (Relief: %.0f %%), %.1f M instructions per glyph: its "
                  "glyphs' many strokes put more elements in each call, so the floor "
                  "weighs less." % (row["name"], total[1], total[2], total[5],
                                    100 * total[5] / total[1], 100 * total[4], 100 * share,
                                    total[3]))
    return md


def _numba_conclusion(nb, glyphs, bound_s):
    """The conclusions on numba: what the measured kernel saves, what it costs a
    command, and the issue's conditions."""
    if not nb:
        return []
    cold, warm = nb["cold"], nb["warm"]
    saved = cold["numpy_s"] - cold["numba_s"]
    fixed = cold["import_s"] + warm["first_call_cache_s"]
    per_kernel = warm["second_kernel_cache_s"]
    kernels = len(SHOWN) - 2    # one kernel a phase (not "other", not "trim: rest")
    ref = stroke_sets_relief()
    whole = ("Relief's whole command takes %.1f ms per glyph against FontForge's worker "
             "%.1f-%.1f (bench/stroke_sets.md), %.2f s against %.2f-%.2f over the %d "
             "glyphs; " % ((ref[0],) + ref[1] + (ref[0] * glyphs / 1000,
                                                 ref[1][0] * glyphs / 1000,
                                                 ref[1][1] * glyphs / 1000, glyphs))
             if ref else "")
    lack = [p for p, w in nb["wheels"].items() if not isinstance(w, list)]
    return [
        "- **numba, measured**: the kernel saves %.1f ms per Relief pass (%.3f ms per "
        "glyph) and costs every command %.0f ms of import plus %.0f ms to load its cached "
        "code (%.0f ms to compile it when the cache is cold: first run, upgrade, a "
        "read-only install); net, the command gets slower by %.0f ms.  %sone kernel per "
        "phase (%d) would load in about %.0f ms (import, first kernel, %.0f ms each "
        "further one: the first load is numba's own setting up) before saving anything, "
        "against the upper bound of %.2f s above (an upper bound: the kernel measured "
        "here removes %.0f %% of its numpy time, not all of it)."
        % (1000 * saved, 1000 * saved / glyphs, 1000 * cold["import_s"],
           1000 * warm["first_call_cache_s"], 1000 * cold["first_call_cache_s"],
           1000 * (fixed - saved), whole, kernels,
           1000 * (fixed + (kernels - 1) * per_kernel), 1000 * per_kernel, bound_s,
           100 * saved / cold["numpy_s"]),
        "- **The issue's conditions**: numba is well kept (a release every few months, "
        "numpy 2.x supported) and installs without compiling where it has wheels, but "
        "this release has none for %s, and it adds %.0f MB to an install.  %s"
        % (", ".join(lack) or "no platform asked",
           (nb["sizes"]["numba"] + nb["sizes"]["llvmlite"]) / 1048576.0,
           _verdict(saved, fixed, ref, glyphs,
                    (bound_s, fixed + (kernels - 1) * per_kernel)))]


def _verdict(saved, fixed, ref, glyphs, bound=None):
    """Whether a compiled kernel pays for itself in a short command, and where a
    rewrite of every phase would leave the command (``bound``: (the most it could
    save, the loading of one kernel a phase), s), from the figures."""
    text = ("One kernel saves %.0f ms on the whole of Relief and costs %.0f ms to import "
            "and load: %s." % (1000 * saved, 1000 * fixed,
                               "a loss for the command" if fixed > saved else "a gain"))
    if ref and bound is not None:
        best = ref[0] * glyphs / 1000.0 - bound[0] + bound[1]
        text += ("  Even every phase rewritten as a kernel with all its overhead gone "
                 "would leave Relief's whole command at about %.2f s (%.2f - %.2f + %.2f "
                 "of loading), above FontForge's worker's %.2f-%.2f s: the gap is the "
                 "per-call overhead spread over every phase, and the compiled route pays "
                 "its own fixed cost in every short command."
                 % (best, ref[0] * glyphs / 1000.0, bound[0], bound[1],
                    ref[1][0] * glyphs / 1000.0, ref[1][1] * glyphs / 1000.0))
    return text


def markdown(out, argline, elapsed):
    from bench.stamp import stamp

    md = ["# How far each phase is from its numpy floor (bench/numpy_floor.py)", "",
          stamp("python -m bench.numpy_floor" + argline, elapsed), "",
          "Load average at the end: %s (2 CPUs shared with other jobs): times are CPU "
          "times (process_time), medians; instruction and call counts (callgrind) do "
          "not depend on the load.  See the script's docstring for the method."
          % ", ".join("%.1f" % v for v in os.getloadavg()), ""]
    part, per_call = calls_md(out["calls_us"])
    md += part + ["", "## 2. Phases: numpy calls, floor and element work", ""]
    for row in out["sets"]:
        md += ["### %s: %d glyphs in chunks of %s, tol %g" % (
            row["name"], row["glyphs"], ", ".join(map(str, row["chunks"])), row["tols"][0]), "",
               "The first chunk (%d glyphs): ms / glyph, the median of %d passes; calls "
               "and instructions under callgrind, per glyph.  All chunks: %s."
               % (row["cg_glyphs"], row["repeat"],
                  "; ".join("%.2f ms / glyph at tol %g" % (1000 * t["total"] / row["glyphs"],
                                                           t["tol"]) for t in row["timed"])),
               ""]
        md += set_table(row, per_call) + [""]
    if out.get("numba"):
        rel = next(r for r in out["sets"] if r["name"] == "relief")
        md += numba_md(out["numba"], rel["glyphs"]) + [""]
    md += conclusions_md(out, per_call)
    return "\n".join(md) + "\n"



def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--cg-worker"]:
        return cg_worker(*json.loads(argv[1]))
    if argv[:1] == ["--numba-worker"]:
        return numba_worker(*json.loads(argv[1]))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", default="relief,hanzi-300")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--cg-chunks", type=int, default=1,
                    help="chunks of each set run under callgrind (the first ones)")
    ap.add_argument("--venv", default=os.path.join(tempfile.gettempdir(), "numpy_floor_venv"))
    ap.add_argument("--no-numba", action="store_true")
    ap.add_argument("--md", default=str(ROOT / "bench" / "numpy_floor.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--json", help="also write the measured figures here")
    ap.add_argument("--from-json", help="write the report of an earlier run's --json "
                                        "instead of measuring")
    opt = ap.parse_args(argv)
    t0 = time.time()
    if opt.from_json:
        saved = json.loads(Path(opt.from_json).read_text())
        out, argline, elapsed = saved["out"], saved["argline"], saved["elapsed"]
    else:
        with tempfile.TemporaryDirectory() as tmp:
            out = measure(opt, tmp)
        argline = "".join(" " + a for a in shown_args(argv, ("--md", "--venv", "--json")))
        elapsed = time.time() - t0
    if opt.json:
        Path(opt.json).write_text(json.dumps({"out": out, "argline": argline,
                                              "elapsed": elapsed}))
    text = markdown(out, argline, elapsed)
    return emit(text, opt)


if __name__ == "__main__":
    sys.exit(main())
