"""The font writer of ``morph stroke`` alone: memory and CPU time against the number of
glyphs, with the stroking taken out.

    python -m bench.font_writer [--sizes 300,3000,30000] [--kinds .otf,.ttf,.ufo]
                                [--runs 300:.otf,30000:.ttf,...]
                                [--before PATH_TO_ANOTHER_CHECKOUT] [--before-sizes 300,3000]
                                [--md bench/font_writer.md | --no-write]

Every glyph of a ``hanzi-xN`` skeleton UFO (N glyphs, named after N code points from
U+4E00; glyph k has the stroke medians of the k mod 300-th character of the
``hanzi-300`` set of :mod:`bench.skeletons`) is written by
``morph.fonts.stroke.stroke_ufo`` with ``--jobs 1``, its stroke replaced by the
recorded result of the real one: ``morph.fonts.stroke._chunk_job`` of the
``hanzi-300`` glyphs (their integer contours at the default nib and tol, recorded
once into the bench cache; a .ttf's quadratic contours recorded apart) is returned
for every chunk.  So the run measures what the writer does with N real glyphs:
reading the skeletons, the font tables, compiling and saving, not the geometry.

Each run is a fresh process; reported: its peak resident memory (``VmHWM``), its
CPU time (user + sys, from the kernel) per glyph, and the output's size.  The
``--before`` checkout (e.g. a worktree of the main branch) is run the same way at
``--before-sizes``, for the writer that kept the glyphs as ufoLib2 objects until
ufo2ft compiled the font.  CPU times, not wall times: the machine is shared.
"""

import argparse
import os
import pickle
import resource
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if __name__ == "__main__" and str(ROOT) not in sys.path:  # run by its path: bench.* found
    sys.path.append(str(ROOT))
BASE = 300  # glyphs of hanzi-300 whose strokes are recorded


def _recorded(kind):
    """{index in hanzi-300: _chunk_job result} for an output suffix, recorded once."""
    from bench.skeletons import cache_dir, skeleton_ufo

    flavor = "ttf" if kind == ".ttf" else "cff"
    path = cache_dir() / ("hanzi-300-strokes-%s.pickle" % flavor)
    if path.exists():
        return pickle.loads(path.read_bytes())
    from morph import budget
    from morph.fonts.brush import ellipse_nib
    from morph.fonts.jobs import glyph_chunks
    from morph.fonts.stroke import _chunk_job, _stroke_work
    from morph.fonts.stream import SkeletonSource

    source = SkeletonSource(skeleton_ufo("hanzi-300"))
    names = source.keys()
    nib = ellipse_nib(90 * 1.024, 20 * 1.024, 30)
    tols = budget.plan(0.5 * 1.024, flavor == "ttf")
    out = {}
    for chunk in glyph_chunks(names):
        work = _stroke_work(source, chunk, {}, nib, tols, {n: 0 for n in chunk}, None)
        for r in _chunk_job(work):
            out[names.index(r["name"])] = {"contours": r["contours"], "region": [],
                                           "fallback": None, "seconds": r["seconds"]}
    path.write_bytes(pickle.dumps(out))
    return out


def skeleton_copies(n):
    """The ``hanzi-xN`` skeleton UFO (see the module docstring), built once."""
    import ufoLib2

    from bench.skeletons import cache_dir, skeleton_ufo

    path = cache_dir() / ("hanzi-x%d.ufo" % n)
    if path.exists():
        return path
    src = ufoLib2.Font.open(skeleton_ufo("hanzi-300"))
    names = list(src.keys())
    font = ufoLib2.Font(info=src.info)
    for k in range(n):
        g = src[names[k % len(names)]]
        new = font.newGlyph("uni%04X" % (0x4E00 + k))
        new.width = g.width
        new.unicodes = [0x4E00 + k]
        g.drawPoints(new.getPointPen())
    font.lib["public.glyphOrder"] = list(font.keys())
    font.save(str(path))
    return path


def worker(n, kind, out):
    """One run (in this process): the writer over hanzi-xN with recorded strokes."""
    import morph.fonts.stroke as stroke
    from morph.fonts.brush import ellipse_nib

    recorded = _recorded(kind)

    def chunk_job(chunk):
        return [dict(recorded[(int(job[0][3:], 16) - 0x4E00) % BASE], name=job[0])
                for job in chunk]

    stroke._chunk_job = chunk_job
    ufo = skeleton_copies(n)
    def cpu_now():  # this process and its children (cffsubr's tx)
        a, b = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        return a.ru_utime + a.ru_stime + b.ru_utime + b.ru_stime

    t0 = cpu_now()
    stats = stroke.stroke_ufo(str(ufo), out, ellipse_nib(90 * 1.024, 20 * 1.024, 30),
                              tol=0.5 * 1.024, overwrite=True, jobs=1)
    cpu = cpu_now() - t0
    with open("/proc/self/status") as f:
        hwm = [int(line.split()[1]) for line in f if line.startswith("VmHWM:")][0]
    print("RESULT %d %s %.3f %d %d" % (n, kind, cpu, hwm, stats["points"]))


def run(n, kind, tmp, checkout=None):
    out = Path(tmp) / ("hanzi-x%d%s" % (n, kind))
    from bench.skeletons import cache_dir

    # the script by its path: this bench/ first on sys.path, the measured morph from
    # PYTHONPATH, the cache (recorded strokes, skeletons) this checkout's
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(checkout or ROOT),
               MORPH_BENCH_CACHE=str(cache_dir()))
    proc = subprocess.run([sys.executable, str(ROOT / "bench" / "font_writer.py"),
                           "--worker", str(n), kind, str(out)], cwd=str(ROOT), env=env,
                          capture_output=True, text=True)
    line = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT")]
    if proc.returncode != 0 or not line:
        return {"n": n, "kind": kind, "error": (proc.stderr.strip().splitlines() or ["?"])[-1]}
    _, _, _, cpu, hwm, points = line[0].split()
    size = (sum(p.stat().st_size for p in out.rglob("*") if p.is_file()) if out.is_dir()
            else out.stat().st_size)
    return {"n": n, "kind": kind, "cpu": float(cpu), "mb": int(hwm) / 1024.0,
            "points": int(points), "size": size / 1e6}


def main(argv=None):
    import tempfile

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="300,3000,30000")
    ap.add_argument("--kinds", default=".otf,.ttf,.ufo")
    ap.add_argument("--runs", help="size:kind,... instead of every size with every kind "
                                   "('': none, e.g. only --before)")
    ap.add_argument("--before", help="another checkout's root, run as the writer before")
    ap.add_argument("--before-label", default="the writer before")
    ap.add_argument("--before-sizes", default="300,3000")
    ap.add_argument("--md", default=str(ROOT / "bench" / "font_writer.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--worker", nargs=3, help=argparse.SUPPRESS)
    opt = ap.parse_args(argv)
    if opt.worker:
        worker(int(opt.worker[0]), opt.worker[1], opt.worker[2])
        return 0
    argv = sys.argv[1:] if argv is None else argv
    kinds = opt.kinds.split(",")
    # the strokes recorded before any run is timed
    for kind in set(kinds) | {r.split(":")[1] for r in (opt.runs or "").split(",") if r}:
        _recorded(kind)
    from bench.proctree import started

    rows, begun = [], started()
    with tempfile.TemporaryDirectory() as tmp:
        plan = ([(None, int(n), k) for n, k in (r.split(":") for r in opt.runs.split(",") if r)]
                if opt.runs is not None
                else [(None, int(n), k) for n in opt.sizes.split(",") for k in kinds])
        if opt.before:
            plan += [(opt.before, int(n), k) for n in opt.before_sizes.split(",") for k in kinds]
        for checkout, n, kind in plan:
            skeleton_copies(n)
            r = run(n, kind, tmp, checkout)
            r["who"] = opt.before_label if checkout else "streamed (this checkout)"
            print(r, flush=True)
            rows.append(r)
            text = markdown(rows, argv, len(plan), begun)  # after every run: a long run's rows
            if not opt.no_write:                     # are kept if it is stopped
                Path(opt.md).write_text(text)
    print(text)
    return 0


def markdown(rows, argv, planned, begun):
    from bench.proctree import measured_header

    md = measured_header(
        "The font writer of `morph stroke` against the font's size", "font_writer", argv,
        len(rows), planned, "CPU times, not wall times.  The stroking is replaced by recorded "
        "strokes of the hanzi-300 glyphs (see the script's docstring): the writer alone, "
        "`--jobs 1`, one process.", begun)
    md += ["", "| writer | output | glyphs | peak RSS MB | CPU s | CPU ms / glyph | points | "
           "output MB |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            md.append("| %s | %s | %d | failed: %s | | | | |" % (r["who"], r["kind"], r["n"],
                                                               r["error"]))
            continue
        md.append("| %s | %s | %d | %.0f | %.1f | %.2f | %d | %.1f |"
                  % (r["who"], r["kind"], r["n"], r["mb"], r["cpu"], 1000 * r["cpu"] / r["n"],
                     r["points"], r["size"]))
    return "\n".join(md) + "\n"


if __name__ == "__main__":
    sys.exit(main())
