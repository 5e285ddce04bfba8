"""`morph sum` against the polygon script as whole processes: alternated runs, medians.

    python bench/processes.py                       # the cases below, 7 runs each
    python bench/processes.py --runs 11 --cases "O M 1e-4,S g 1e-5"
    python bench/processes.py --stages --cases "O M 1e-4"   # where a morph process spends

Each case runs, in turn and after one warm-up run of each, the three commands

    morph:   python -m morph.cli sum A B --tol T -o m.svg --force
    dc:      python bench/dc_sum.py A B --font F --tol T -o d.svg
    dc-1:    the same with OPENBLAS_NUM_THREADS=1

with bytecode cached in a private folder (as after a pip install: this machine sets
PYTHONDONTWRITEBYTECODE, under which every process compiles its modules again).
``morph`` sets OPENBLAS_NUM_THREADS=1 itself before numpy loads (OpenBLAS starting
its thread pool costs ~50 ms CPU); dc-1 is the polygon script given the same
setting, so the comparison shows what is morph's own.  Wall time is perf_counter
around the child; CPU is the child's user + system time from rusage.  Reported:
medians over the runs, and the median of the run-by-run ratios morph / dc (taken
pair by pair, so a drift of the shared machine's speed cancels).  Output: a markdown
table on stdout.
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTO = str(ROOT / "morph" / "fonts" / "data" / "NotoSans-Regular.ttf")
CASES = "O M 1e-4,O M 1e-5,S g 1e-4,S g 1e-5,a g 1e-4 lobster,a g 1e-5 lobster"


def font_path(name):
    """The font of a case: the bundled Noto Sans, or ``lobster`` (fontpkg-lobster,
    in the bench extra)."""
    if name == "noto":
        return NOTO
    if name == "lobster":
        import fontpkg_lobster

        return str(next(Path(fontpkg_lobster.__file__).parent.rglob("Lobster-Regular.ttf")))
    return name


def run(cmd, env, cwd):
    """(wall s, CPU s) of one child process; raises when it fails."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-500:]))
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def case(a, b, tol, font, runs, env, tmp):
    f = font_path(font)
    cmds = {
        "morph": ([sys.executable, "-m", "morph.cli", "sum", a, b, "--tol", tol]
                  + ([] if font == "noto" else ["--font", f])
                  + ["-o", os.path.join(tmp, "m.svg"), "--force"], env),
        "dc": ([sys.executable, str(ROOT / "bench" / "dc_sum.py"), a, b, "--font", f,
                "--tol", tol, "-o", os.path.join(tmp, "d.svg")], env),
    }
    cmds["dc-1"] = (cmds["dc"][0], dict(env, OPENBLAS_NUM_THREADS="1"))
    times = {k: [] for k in cmds}
    for k, (cmd, e) in cmds.items():  # warm-up: bytecode, page cache
        run(cmd, e, tmp)
    for i in range(runs):
        order = list(cmds)[i % 3:] + list(cmds)[:i % 3]  # rotate who goes first
        for k in order:
            times[k].append(run(cmds[k][0], cmds[k][1], tmp))
    return times


STAGES = r"""
import os, sys, time
c0 = time.process_time()
laps = [("interpreter and site", c0)]
def lap(name):
    laps.append((name, time.process_time()))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import numpy
lap("numpy")
import morph.cli
lap("click, morph.cli")
from morph.parse import load_font, load_shape
font = sys.argv[4] if len(sys.argv) > 4 else None
load_font(font)
lap("fontTools, open font, glyph names")
a, b = load_shape(sys.argv[1], font), load_shape(sys.argv[2], font)
lap("read both glyphs")
from morph.budget import plan
from morph.minkowski import minkowski_sum
st, et = plan(a.em_to_units(float(sys.argv[3])))
loops = minkowski_sum(a.region, b.region, st)
lap("sum (imports included)")
from morph.render import write_svg
write_svg(os.devnull, [loops], tol=et)
lap("SVG export (imports included)")
prev = 0.0
for name, c in laps:
    print("%s\t%.6f" % (name, c - prev))
    prev = c
print("total\t%.6f" % laps[-1][1])
"""


def stages(a, b, tol, font, runs, env, tmp):
    """CPU seconds of each stage of the `morph sum` path in fresh processes (medians
    over ``runs``): {stage: seconds}, in order."""
    cmd = [sys.executable, "-c", STAGES, a, b, tol] + ([] if font == "noto"
                                                       else [font_path(font)])
    subprocess.run(cmd, env=env, cwd=tmp, check=True, capture_output=True)  # warm-up
    out = {}
    for _ in range(runs):
        p = subprocess.run(cmd, env=env, cwd=tmp, check=True, capture_output=True, text=True)
        for line in p.stdout.splitlines():
            name, sec = line.split("\t")
            out.setdefault(name, []).append(float(sec))
    return {k: med(v) for k, v in out.items()}


def med(xs):
    return statistics.median(xs)


def ratio(times, a, b, j):
    return med([x[j] / y[j] for x, y in zip(times[a], times[b])])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--cases", default=CASES,
                    help="comma-separated 'A B TOL [FONT]', FONT noto (default), lobster "
                         "or a path")
    ap.add_argument("--stages", action="store_true",
                    help="instead: CPU of each stage of the morph process (fresh processes, "
                         "medians), one column per case")
    args = ap.parse_args(argv)
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               PYTHONPYCACHEPREFIX=tempfile.mkdtemp(prefix="processes-pycache-"))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env.pop("OPENBLAS_NUM_THREADS", None)
    if args.stages:
        cols = []
        with tempfile.TemporaryDirectory() as tmp:
            for spec in args.cases.split(","):
                a, b, tol, *font = spec.split()
                cols.append(("%s + %s %s" % (a, b, tol),
                             stages(a, b, tol, font[0] if font else "noto", args.runs, env, tmp)))
        print("| stage (CPU ms) | " + " | ".join(c for c, _ in cols) + " |")
        print("|---|" + "---|" * len(cols))
        for name in cols[0][1]:
            print("| %s | " % name + " | ".join("%.0f" % (st[name] * 1e3) for _, st in cols)
                  + " |")
        return
    print("| case | font | tol (em) | morph wall / CPU | dc wall / CPU | morph/dc wall, CPU "
          "| dc-1 CPU | morph/dc-1 CPU |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for spec in args.cases.split(","):
            a, b, tol, *font = spec.split()
            font = font[0] if font else "noto"
            t = case(a, b, tol, font, args.runs, env, tmp)
            m = [med([x[j] for x in t["morph"]]) for j in (0, 1)]
            d = [med([x[j] for x in t["dc"]]) for j in (0, 1)]
            print("| %s + %s | %s | %s | %.2f / %.2f s | %.2f / %.2f s | %.2f, %.2f | %.2f s "
                  "| %.2f |" % (a, b, Path(font_path(font)).stem, tol, m[0], m[1], d[0], d[1],
                                ratio(t, "morph", "dc", 0), ratio(t, "morph", "dc", 1),
                                med([x[1] for x in t["dc-1"]]), ratio(t, "morph", "dc-1", 1)),
                  flush=True)


if __name__ == "__main__":
    sys.exit(main())
