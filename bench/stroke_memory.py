"""Peak memory and time of ``morph stroke`` against the number of glyphs (hanzi medians).

    python -m bench.stroke_memory [--sets hanzi-300,hanzi-3000] [--jobs 1,2]
                                  [--pairs hanzi-300:1,hanzi-variants-30000:2,...]
                                  [--nice 10] [--keep DIR] [--md bench/stroke_memory.md | --no-write]

Each run is the command ``morph stroke SET.ufo -o OUT.otf --jobs J --force`` (under
``nice -n N`` with ``--nice``) on a skeleton set of :mod:`bench.skeletons`: hanzi-N,
N characters' stroke medians spread evenly over hanzi-writer-data (fetched at bench
time), hanzi-all every one of them (9,574), and hanzi-variants-N, N distinct glyphs
made of them by affine maps (:mod:`bench.skeleton_variants`), for fonts larger than
the real set.  Measured (:func:`bench.proctree.watch`): the peak resident memory of
the command's process (its ``VmHWM``, read from ``/proc`` while it runs) and of its
whole process tree (the command, its workers and the subroutinizer's process: the
sum of their ``VmRSS``, sampled every 0.1 s, so a peak shorter than that may be
missed), the largest of any one of the other processes, the command process's RSS
at the end of the serial head, its peak while the workers work and its peak in the
serial tail (sampled: where memory goes by phase), the CPU time of the tree (user +
sys of every process, from the kernel), the wall time, the serial head and tail
(how long the command worked before its first worker did and after its last one
had finished), the output's size, and the load average (1 minute) as the run
starts and ends.  The machine is shared, so the wall time is an upper bound; the
CPU time is the fairer figure.  The report also keeps the progress lines the
command printed (piped: a status line every few seconds) for the longest run.
"""

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run(ufo, jobs, out, nice=0):
    from bench.proctree import watch

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT))
    cmd = [sys.executable, "-m", "morph.cli", "stroke", str(ufo), "-o", str(out),
           "--jobs", str(jobs), "--force"]
    if nice:
        cmd = ["nice", "-n", str(nice)] + cmd   # nice execs the command: the same process
    return watch(cmd, env=env, cwd=str(Path(out).parent))


def phases(r):
    """The command process's RSS (MB, sampled) at the end of the serial head, its
    peak while the workers worked and its peak in the serial tail (None where the
    run had no workers)."""
    if r["jobs"] < 2 or r["head"] is None or r["tail"] is None:
        return None, None, None
    end = r["wall"] - r["tail"]
    rss = r["main_rss"]
    head = max([mb for t, mb in rss if t <= r["head"]] or [0.0])
    during = max([mb for t, mb in rss if r["head"] < t <= end] or [0.0])
    tail = max([mb for t, mb in rss if t > end] or [0.0])
    return head, during, tail


def main(argv=None):
    from bench.skeletons import skeleton_ufo

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", default="hanzi-300,hanzi-3000")
    ap.add_argument("--jobs", default="1,2")
    ap.add_argument("--pairs", help="set:jobs,... instead of every set with every --jobs")
    ap.add_argument("--nice", type=int, default=0, help="run the commands under nice -n N")
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
            r = run(ufo, int(j), out, opt.nice)
            r["line"] = r["line"].replace(str(out.parent) + os.sep, "")  # no machine paths
            r.update(set=s, jobs=int(j), glyphs=glyphs, load=(load, os.getloadavg()[0]),
                     size=out.stat().st_size if out.exists() else None)
            print({k: v for k, v in r.items() if k not in ("output", "main_rss")}, flush=True)
            rows.append(r)
            text = markdown(rows, argv, len(pairs), begun)  # after every run: a long run's
            if not opt.no_write:                     # rows are kept if it is stopped
                Path(opt.md).write_text(text)
    print(text)
    return 0


def _f(v, fmt="%.1f"):
    return "-" if v is None else fmt % v


def table(rows):
    md = ["| set | glyphs | --jobs | peak RSS, command process MB | peak RSS, process tree "
          "MB (sampled) | largest other process MB | command process MB: after head, "
          "while workers work, in tail | CPU s (tree) | CPU ms / glyph | wall s | "
          "serial head s | serial tail s | output MB | load average (1 min) at start, end | "
          "exit |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %d | %d | %.0f | %.0f | %s | %s | %.1f | %.1f | %.1f | %s | %s | %s "
                  "| %s | %d |"
                  % (r["set"], r["glyphs"], r["jobs"], r["max_mb"], r["tree_mb"],
                     _f(r["child_mb"] or None, "%.0f"),
                     ", ".join(_f(v, "%.0f") for v in phases(r)), r["cpu"],
                     1000 * r["cpu"] / max(1, r["glyphs"]), r["wall"],
                     _f(r["head"] if r["jobs"] > 1 else None),
                     _f(r["tail"] if r["jobs"] > 1 else None), _f(r["size"] and r["size"] / 1e6, "%.2f"),
                     "%.1f, %.1f" % r["load"] if r.get("load") else "-", r["rc"]))
    return md


def growth(rows):
    """A line on how the peaks grow from the smallest to the largest font of the same
    --jobs: MB per 1,000 glyphs."""
    out = []
    for j in sorted({r["jobs"] for r in rows}):
        same = sorted((r for r in rows if r["jobs"] == j and r["rc"] == 0),
                      key=lambda r: r["glyphs"])
        if len(same) < 2 or same[-1]["glyphs"] == same[0]["glyphs"]:
            continue
        a, b = same[0], same[-1]
        k = (b["glyphs"] - a["glyphs"]) / 1000.0
        out.append("- `--jobs %d`, %d to %d glyphs: the command process's peak %+.0f MB "
                   "(%+.1f MB per 1,000 glyphs), the tree's %+.0f MB (%+.1f MB per 1,000 "
                   "glyphs)." % (j, a["glyphs"], b["glyphs"], b["max_mb"] - a["max_mb"],
                                 (b["max_mb"] - a["max_mb"]) / k, b["tree_mb"] - a["tree_mb"],
                                 (b["tree_mb"] - a["tree_mb"]) / k))
    return out


def status_lines(rows, shown=6):
    """The progress lines (piped: status lines) of the run with the most glyphs."""
    if not rows:
        return []
    r = max(rows, key=lambda r: (r["glyphs"], r["jobs"]))
    lines = [ln for ln in r["output"].splitlines() if ln.startswith("morph stroke:")]
    if not lines:
        return []
    picked = lines if len(lines) <= 2 * shown else lines[:shown] + ["..."] + lines[-shown:]
    return ["", "The progress lines of the %s --jobs %d run (piped, %d lines):" % (
        r["set"], r["jobs"], len(lines)), "", "```"] + picked + ["```"]


def markdown(rows, argv, planned, begun):
    from bench.proctree import measured_header

    md = measured_header("Peak memory of `morph stroke` against the font's size",
                         "stroke_memory", argv, len(rows), planned,
                         "wall times are upper bounds.", begun)
    md += [""] + table(rows)
    md += [""] + growth(rows)
    md += ["", "The serial head is the time before the first worker gains CPU time (reading "
           "the source's glyph shells, the plan), the tail the time after the last one "
           "did (compiling and saving the font, the sample and specimen); with `--jobs 1` "
           "there are no workers (and no phases).  The largest other process is a worker "
           "or the subroutinizer's (`tx`, run by cffsubr while the font is compiled).",
           "", "The commands' last lines:", ""]
    md += ["- %s --jobs %d: `%s`" % (r["set"], r["jobs"], r["line"]) for r in rows]
    md += status_lines(rows)
    return "\n".join(md) + "\n"


if __name__ == "__main__":
    sys.exit(main())
