"""Peak memory of ``morph stroke`` against the number of glyphs (hanzi medians).

    python -m bench.stroke_memory [--sets hanzi-300,hanzi-3000] [--jobs 1,2]
                                  [--md bench/stroke_memory.md | --no-write]

Each run is the command ``morph stroke SET.ufo -o OUT.otf --jobs J --force`` on a
skeleton set of :mod:`bench.skeletons` (hanzi-N: N characters' stroke medians, spread
evenly over hanzi-writer-data; fetched at bench time).  Measured: the peak resident
memory of the command's process (its ``VmHWM``, read from ``/proc`` while it runs) and of its
whole process tree (the command and its workers: the sum of their ``VmRSS`` from
``/proc``, sampled every 0.1 s, so a peak shorter than that may be missed), the
CPU time of the tree (user + sys of every process, from the kernel) and the wall
time.  The machine is shared, so the wall time is an upper bound.
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _tree_rss_kb(pid):
    """Sum of VmRSS (kB) of ``pid`` and its descendants (Linux /proc)."""
    children = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            continue
        children.setdefault(ppid, []).append(int(d))
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        todo += children.get(p, [])
        try:
            with open("/proc/%d/status" % p) as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        total += int(line.split()[1])
        except OSError:
            pass
    return total


def run(ufo, jobs, out):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT))
    proc = subprocess.Popen([sys.executable, "-m", "morph.cli", "stroke", str(ufo), "-o",
                             str(out), "--jobs", str(jobs), "--force"], cwd=str(Path(out).parent),
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    peak = hwm = 0
    while proc.poll() is None:
        peak = max(peak, _tree_rss_kb(proc.pid))
        try:
            with open("/proc/%d/status" % proc.pid) as f:
                hwm = max([hwm] + [int(line.split()[1]) for line in f
                                   if line.startswith("VmHWM:")])
        except OSError:
            pass
        time.sleep(0.1)
    text = proc.stdout.read()
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    lines = text.strip().splitlines()
    return {"cpu": cpu, "wall": wall, "tree_mb": peak / 1024.0,
            "max_mb": hwm / 1024.0, "line": lines[-1] if lines else "",
            "rc": proc.returncode}


def main(argv=None):
    from bench.skeletons import skeleton_ufo

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", default="hanzi-300,hanzi-3000")
    ap.add_argument("--jobs", default="1,2")
    ap.add_argument("--pairs", help="set:jobs,... instead of every set with every --jobs")
    ap.add_argument("--md", default=str(ROOT / "bench" / "stroke_memory.md"))
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    rows = []
    pairs = ([p.split(":") for p in opt.pairs.split(",")] if opt.pairs else
             [(s, j) for s in opt.sets.split(",") for j in opt.jobs.split(",")])
    with tempfile.TemporaryDirectory() as tmp:
        for s, j in pairs:
            ufo = skeleton_ufo(s)
            glyphs = sum(1 for _ in (ufo / "glyphs").glob("*.glif"))
            r = run(ufo, int(j), Path(tmp) / (s + ".otf"))
            r.update(set=s, jobs=int(j), glyphs=glyphs)
            print(r, flush=True)
            rows.append(r)
            text = markdown(rows, argv, len(pairs))  # after every run: a long run's
            if not opt.no_write:                     # rows are kept if it is stopped
                Path(opt.md).write_text(text)
    print(text)
    return 0


def markdown(rows, argv, planned):
    from bench.stroke_profile import code_version, shown_args

    md = ["# Peak memory of `morph stroke` against the font's size (bench/stroke_memory.py)",
          "",
          "Command: `python -m bench.stroke_memory%s`; measured %s UTC at %s (%d of %d runs "
          "done).  Machine: %d CPUs shared with other jobs (load average %s at the end): "
          "wall times are upper bounds." % ("".join(" " + a for a in shown_args(argv)),
                                           time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                                           code_version(), len(rows), planned,
                                           os.cpu_count() or 1,
                                           ", ".join("%.1f" % v for v in os.getloadavg())), "",
          "| set | glyphs | --jobs | peak RSS, command process MB | peak RSS, process tree MB "
          "(sampled) | CPU s (tree) | CPU ms / glyph | wall s | exit |",
          "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %d | %d | %.0f | %.0f | %.1f | %.1f | %.1f | %d |"
                  % (r["set"], r["glyphs"], r["jobs"], r["max_mb"], r["tree_mb"], r["cpu"],
                     1000 * r["cpu"] / max(1, r["glyphs"]), r["wall"], r["rc"]))
    md += ["", "The commands' last lines:", ""] + ["- %s --jobs %d: `%s`" % (r["set"], r["jobs"],
                                                                          r["line"])
                                                   for r in rows]
    return "\n".join(md) + "\n"


if __name__ == "__main__":
    sys.exit(main())
