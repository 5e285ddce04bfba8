"""Peak memory of ``morph stroke`` against the number of glyphs (hanzi medians).

    python -m bench.stroke_memory [--sets hanzi-300,hanzi-3000] [--jobs 1,2] [--keep DIR]
                                  [--md bench/stroke_memory.md | --no-write]

Each run is the command ``morph stroke SET.ufo -o OUT.otf --jobs J --force`` on a
skeleton set of :mod:`bench.skeletons` (hanzi-N: N characters' stroke medians, spread
evenly over hanzi-writer-data; fetched at bench time).  Measured: the peak resident
memory of the command's process (its ``VmHWM``, read from ``/proc`` while it runs) and of its
whole process tree (the command and its workers: the sum of their ``VmRSS`` from
``/proc``, sampled every 0.1 s, so a peak shorter than that may be missed), the
CPU time of the tree (user + sys of every process, from the kernel), the command
process's own CPU time, the wall time, and the serial head and tail: how long the
command worked before its first worker did and after its last one had finished
(:func:`bench.proctree.watch`), and the load average (1 minute) as the run starts
and ends.  The machine is shared, so the wall time is an upper bound; the CPU time
is the fairer figure.
"""

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run(ufo, jobs, out):
    from bench.proctree import watch

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT))
    return watch([sys.executable, "-m", "morph.cli", "stroke", str(ufo), "-o", str(out),
                  "--jobs", str(jobs), "--force"], env=env, cwd=str(Path(out).parent))


def main(argv=None):
    from bench.skeletons import skeleton_ufo

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", default="hanzi-300,hanzi-3000")
    ap.add_argument("--jobs", default="1,2")
    ap.add_argument("--pairs", help="set:jobs,... instead of every set with every --jobs")
    ap.add_argument("--md", default=str(ROOT / "bench" / "stroke_memory.md"))
    ap.add_argument("--keep", help="write the fonts into this folder and keep them (e.g. "
                    "for bench.stroke_overlaps --written)")
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    from bench.proctree import started

    rows, begun = [], started()
    pairs = ([p.split(":") for p in opt.pairs.split(",")] if opt.pairs else
             [(s, j) for s in opt.sets.split(",") for j in opt.jobs.split(",")])
    with tempfile.TemporaryDirectory() as tmp:
        for s, j in pairs:
            ufo = skeleton_ufo(s)
            glyphs = sum(1 for _ in (ufo / "glyphs").glob("*.glif"))
            load = os.getloadavg()[0]
            out = Path(opt.keep or tmp) / (s + ".otf")
            out.parent.mkdir(parents=True, exist_ok=True)
            r = run(ufo, int(j), out)
            r.update(set=s, jobs=int(j), glyphs=glyphs, load=(load, os.getloadavg()[0]))
            print({k: v for k, v in r.items() if k != "output"}, flush=True)
            rows.append(r)
            text = markdown(rows, argv, len(pairs), begun)  # after every run: a long run's
            if not opt.no_write:                     # rows are kept if it is stopped
                Path(opt.md).write_text(text)
    print(text)
    return 0


def markdown(rows, argv, planned, begun):
    from bench.proctree import measured_header

    md = measured_header("Peak memory of `morph stroke` against the font's size",
                         "stroke_memory", argv, len(rows), planned,
                         "wall times are upper bounds.", begun)
    md += ["", "| set | glyphs | --jobs | peak RSS, command process MB | peak RSS, process tree "
           "MB (sampled) | CPU s (tree) | CPU ms / glyph | command process CPU s (sampled) | "
           "wall s | serial head s | serial tail s | load average (1 min) at start, end | "
           "exit |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %d | %d | %.0f | %.0f | %.1f | %.1f | %.1f | %.1f | %s | %s | %s "
                  "| %d |"
                  % (r["set"], r["glyphs"], r["jobs"], r["max_mb"], r["tree_mb"], r["cpu"],
                     1000 * r["cpu"] / max(1, r["glyphs"]), r["main_cpu"], r["wall"],
                     "-" if r["head"] is None else "%.1f" % r["head"],
                     "-" if r["tail"] is None else "%.1f" % r["tail"],
                     "%.1f, %.1f" % r["load"] if r.get("load") else "-", r["rc"]))
    md += ["", "The serial head is the time before the first worker gains CPU time (reading "
           "the source's glyph shells, the plan), the tail the time after the last one "
           "did (compiling and saving the font, the sample and specimen); with `--jobs 1` "
           "there are no workers.", "", "The commands' last lines:", ""]
    md += ["- %s --jobs %d: `%s`" % (r["set"], r["jobs"], r["line"]) for r in rows]
    return "\n".join(md) + "\n"


if __name__ == "__main__":
    sys.exit(main())
