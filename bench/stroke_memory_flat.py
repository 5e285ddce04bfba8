"""Where the memory of ``morph stroke``'s command process goes, by phase, and how it grows
with the font (hanzi medians).

    python -m bench.stroke_memory_flat [--sets hanzi-300,hanzi-3000] [--jobs 2]
                                       [--before DIR --before-label TEXT] [--nice 10]
                                       [--md bench/stroke_memory_flat.md | --no-write]

Each run is ``morph stroke SET.ufo -o OUT.otf --jobs J --force`` run in a child Python
process (the command's own process: the workers are its children) that marks three
moments: the end of the serial head (the sink of stroked glyphs made), the start of the
tail (every glyph received, the font about to be compiled) and its end (the font
compiled and saved).  At each it reads the process's ``VmRSS`` and ``VmHWM`` (peak) from
``/proc``, its CPU time and its children's (the subroutinizer ``tx``, once the workers
are done), and, in a second run of the same command under ``tracemalloc`` (stopped in the
forked workers), the bytes Python holds and their peak in the phase, and at the start of
the tail the lines of code that allocated what is held (what the command keeps per
glyph).  ``--before DIR``: the same runs with the code in DIR (e.g. ``git archive main``
unpacked), for a before / after table.  The CPU times are the fairer figures on a shared
machine; the tail's CPU is that of the compile and save alone (untraced run).
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


# ====================================================================== child

def _status(key):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024.0
    return None


def _mark(trace):
    import tracemalloc

    cur, peak = tracemalloc.get_traced_memory() if trace else (0, 0)
    if trace:
        tracemalloc.reset_peak()
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {"cpu": time.process_time(), "kids": kids.ru_utime + kids.ru_stime,
            "rss": _status("VmRSS"), "hwm": _status("VmHWM"), "cur": cur / 1e6,
            "peak": peak / 1e6}


def _top_lines(limit=10):
    """The lines of code holding the most traced bytes: (file:line, MB, blocks)."""
    import tracemalloc

    stats = tracemalloc.take_snapshot().statistics("lineno")
    out = []
    for s in stats[:limit]:
        frame = s.traceback[0]
        name = frame.filename
        for root in sys.path:
            if root and name.startswith(root.rstrip("/") + "/"):
                name = name[len(root.rstrip("/")) + 1:]
                break
        out.append(("%s:%d" % (name, frame.lineno), s.size / 1e6, s.count))
    return out


def child(ufo, out, jobs, trace, result):
    """Run the command in this process with the phase marks (see the module
    docstring); the marks go to the JSON file ``result``."""
    import tracemalloc

    if trace:
        tracemalloc.start(1)
        os.register_at_fork(after_in_child=tracemalloc.stop)
    from morph.cli import main
    from morph.fonts import stroke

    marks, cls = {}, stroke._StreamedGlyphs
    init, finish = cls.__init__, cls.finish

    def marked_init(self, *a, **k):
        marks["head"] = _mark(trace)
        init(self, *a, **k)

    def marked_finish(self, *a, **k):
        marks["workers"] = _mark(trace)
        if trace:
            marks["top"] = _top_lines()
        finish(self, *a, **k)
        marks["tail"] = _mark(trace)

    cls.__init__, cls.finish = marked_init, marked_finish
    code = main.main(["stroke", str(ufo), "-o", str(out), "--jobs", str(jobs), "--force"],
                     standalone_mode=False)
    marks["rc"] = code or 0
    Path(result).write_text(json.dumps(marks))


# ====================================================================== parent

def run(root, ufo, jobs, trace, nice, keep=None):
    """The marks of one run of the code at ``root`` (``keep``: copy the font there)."""
    with tempfile.TemporaryDirectory() as tmp:
        result = Path(tmp) / "marks.json"
        cmd = [sys.executable, str(Path(__file__).resolve()), "--child", str(ufo),
               str(Path(tmp) / "out.otf"), str(jobs), str(int(trace)), str(result)]
        if nice:
            cmd = ["nice", "-n", str(nice)] + cmd
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
                   PYTHONPATH=str(root))
        done = subprocess.run(cmd, env=env, cwd=tmp, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True)
        if done.returncode:
            raise SystemExit("%s failed:\n%s" % (" ".join(cmd), done.stderr[-2000:]))
        marks = json.loads(result.read_text())
        marks["size"] = (Path(tmp) / "out.otf").stat().st_size
        if keep is not None:
            Path(keep).parent.mkdir(parents=True, exist_ok=True)
            (Path(tmp) / "out.otf").replace(keep)
    return marks


def row(code, name, glyphs, jobs, plain, traced):
    h, w, t = plain["head"], plain["workers"], plain["tail"]
    th, tw, tt = traced["head"], traced["workers"], traced["tail"]
    return {"code": code, "set": name, "glyphs": glyphs, "jobs": jobs,
            "hwm": t["hwm"], "rss": (h["rss"], w["hwm"], t["hwm"]),
            "py": (th["cur"], tw["cur"], tt["peak"]), "py_work_peak": tw["peak"],
            "tail_cpu": (t["cpu"] - w["cpu"], t["kids"] - w["kids"]),
            "top": traced.get("top", []), "size": plain["size"]}


def table(rows):
    md = ["| code | set | glyphs | --jobs | peak RSS MB | RSS MB: after head, peak to tail "
          "start, peak in tail | Python MB (tracemalloc): after head, held at tail start, "
          "peak in tail | tail CPU s: command, tx | output MB |",
          "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append("| %s | %s | %d | %d | %.0f | %s | %s | %.2f, %.2f | %.2f |" % (
            r["code"], r["set"], r["glyphs"], r["jobs"], r["hwm"],
            ", ".join("%.0f" % v for v in r["rss"]), ", ".join("%.1f" % v for v in r["py"]),
            r["tail_cpu"][0], r["tail_cpu"][1], r["size"] / 1e6))
    return md


def growth(rows):
    """Per code version and --jobs: MB per 1,000 glyphs from the smallest font to the
    largest (peak RSS; Python's bytes held at the tail's start and peak in the tail)."""
    out = []
    for code in dict.fromkeys(r["code"] for r in rows):
        for j in sorted({r["jobs"] for r in rows}):
            same = sorted((r for r in rows if r["code"] == code and r["jobs"] == j),
                          key=lambda r: r["glyphs"])
            if len(same) < 2:
                continue
            a, b = same[0], same[-1]
            k = (b["glyphs"] - a["glyphs"]) / 1000.0
            out.append("- %s, `--jobs %d`, %d to %d glyphs, per 1,000 glyphs: peak RSS "
                       "%+.1f MB, Python's bytes held at the tail's start %+.1f MB, their "
                       "peak in the tail %+.1f MB." % (
                           code, j, a["glyphs"], b["glyphs"], (b["hwm"] - a["hwm"]) / k,
                           (b["py"][1] - a["py"][1]) / k, (b["py"][2] - a["py"][2]) / k))
    return out


def top_lines(rows):
    md = []
    for r in rows:
        if r["top"]:
            md += ["", "What the command process holds at the tail's start (%s, %s, %d "
                   "glyphs), by the line that allocated it:" % (r["code"], r["set"],
                                                                r["glyphs"]), "",
                   "| line | MB | blocks |", "|---|---|---|"]
            md += ["| `%s` | %.2f | %d |" % tuple(t) for t in r["top"]]
    return md


def markdown(rows, argv, planned, begun):
    from bench.proctree import measured_header

    md = measured_header("Memory of `morph stroke`'s command process by phase",
                         "stroke_memory_flat", argv, len(rows), planned,
                         "the CPU times are the command process's own and its children's "
                         "(`tx`) in the tail.", begun)
    md += ["", "The head ends when the glyph sink is made, the tail starts when every "
           "glyph is in (the font compiled and saved after it; the sample and specimen "
           "not counted).  RSS figures from an untraced run, Python's bytes from a run "
           "of the same command under tracemalloc.", ""]
    return "\n".join(md + table(rows) + [""] + growth(rows) + top_lines(rows)) + "\n"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--child"]:     # the script run as a file: its morph from PYTHONPATH
        ufo, out, jobs, trace, result = argv[1:6]
        child(ufo, out, int(jobs), trace == "1", result)
        return 0
    from bench.skeletons import skeleton_ufo

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", default="hanzi-300,hanzi-3000")
    ap.add_argument("--jobs", default="2")
    ap.add_argument("--before", help="also run the code in this folder first")
    ap.add_argument("--before-label", default="before",
                    help="its rows' label (e.g. the branch and commit it holds)")
    ap.add_argument("--nice", type=int, default=0)
    ap.add_argument("--keep", help="keep the fonts in this folder (CODE-SET-JOBS.otf)")
    ap.add_argument("--md", default=str(ROOT / "bench" / "stroke_memory_flat.md"))
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args(argv)
    from bench.proctree import started

    begun = started()
    codes = ([(opt.before_label, Path(opt.before))] if opt.before else []) + [
        ("this (%s)" % begun[1], ROOT)]
    plan = [(c, s, int(j)) for c in codes for s in opt.sets.split(",")
            for j in opt.jobs.split(",")]
    rows = []
    for (code, root), s, j in plan:
        ufo = skeleton_ufo(s)
        glyphs = sum(1 for _ in (ufo / "glyphs").glob("*.glif"))
        keep = opt.keep and Path(opt.keep) / ("%s-%s-%d.otf" % (code.split()[0], s, j))
        plain, traced = run(root, ufo, j, False, opt.nice, keep), run(root, ufo, j, True, opt.nice)
        rows.append(row(code, s, glyphs, j, plain, traced))
        print({k: v for k, v in rows[-1].items() if k != "top"}, flush=True)
        text = markdown(rows, argv, len(plan), begun)
        if not opt.no_write:
            Path(opt.md).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
