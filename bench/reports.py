"""Regenerate the committed reports of bench/ and docs/performance.md with one command.

    python -m bench.reports                    # every report, in place (hours: see --list)
    python -m bench.reports --only methods,qac # some of them
    python -m bench.reports --quick            # every script on a small case, into --out
    python -m bench.reports --check            # headline numbers against the scripts (~20 s)
    python -m bench.reports --list             # the reports, their commands and costs
    python -m bench.reports --performance      # docs/performance.md, evaluation figures

Every report starts with a stamp line (:func:`bench.stamp.stamp`: the command, morph's
version, the commit, the date and the machine); a script that does not write one gets
it from here.  A report marked ``snapshot`` below costs too much to remake on every
change (or needs data fetched from the network); its stamp says when and at which commit
it was made, and ``--only NAME`` remakes it.

``--quick`` runs each script with a small case and writes into ``--out`` (default: a
fresh temporary folder), so that it shows every script still runs without touching the
committed reports.  ``--check`` recomputes a few headline numbers of each report on a
small, fast case and exits 1 when one no longer matches (``tests/test_reports.py`` runs
it in the default test suite).
"""

import argparse
import importlib
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "bench"
PERFORMANCE = ROOT / "docs" / "performance.md"


class Report:
    """One committed report: ``bench/NAME.md`` written by ``python -m bench.MODULE ARGS``
    (``{md}`` in the arguments stands for the output path).  ``quick``: the arguments of a
    small run; ``cost``: how long the full run takes on 2 cores; ``snapshot``: not
    remade on every change; ``check``: ``"module:function"`` returning [(what, reported,
    computed)] rows; ``needs``: modules the script imports that the test extra may lack;
    ``runs``: several commands that each write a section (bench/sweep.py)."""

    def __init__(self, name, module, args=(), quick=None, cost="", snapshot=False,
                 check=None, needs=(), runs=None):
        self.name, self.module, self.args = name, module, list(args)
        self.quick = None if quick is None else list(quick)
        self.cost, self.snapshot, self.check, self.needs = cost, snapshot, check, needs
        self.runs = runs

    @property
    def path(self):
        return BENCH / (self.name + ".md")

    def commands(self, md, quick=False):
        """The command lines that write the report to ``md``."""
        runs = self.runs if self.runs is not None else [self.args]
        if quick:
            runs = [self.quick if self.quick is not None else self.args]
        return [[sys.executable, "-m", self.module] + [a.replace("{md}", str(md)) for a in r]
                for r in runs]


REPORTS = [
    Report("methods", "bench.methods", ["--md", "{md}"], cost="1-2 min",
           check="bench.methods:check"),
    Report("qac", "bench.qac", ["--md", "{md}"], cost="5-25 min", check="bench.qac:check"),
    Report("coincident", "bench.coincident", ["--md", "{md}"],
           quick=["--md", "{md}", "--repeat", "1"], cost="2-20 min", snapshot=True,
           check="bench.reports:check_coincident"),
    Report("adaptive", "bench.adaptive", ["--repeat", "5", "--md", "{md}"],
           quick=["--repeat", "1", "--md", "{md}"], cost="2-10 min", snapshot=True,
           needs=("scipy",)),
    Report("scaling", "bench.scaling", ["--md", "{md}"],
           quick=["--n", "10,30", "--cubics", "100", "--repeat", "1", "--md", "{md}"],
           cost="3-10 min", snapshot=True),
    Report("inset", "bench.inset", ["--n", "60", "--seed", "5", "--md", "{md}"],
           quick=["--n", "4", "--seed", "5", "--fonts", "ttf,cff", "--md", "{md}"],
           cost="2-10 min", snapshot=True, needs=("shapely", "fontpkg_lobster")),
    Report("peers", "bench.peers", ["--md", "{md}"], quick=["--quick", "--md", "{md}"],
           cost="5-10 min", snapshot=True, needs=("pathops", "kurbopy", "mapbox_earcut")),
    Report("stroke", "bench.stroke", ["--md", "{md}"],
           quick=["--glyphs", "A-C", "--no-peers", "--md", "{md}"],
           cost="3.5 min of CPU with the peer cache, 6 without",
           snapshot=True, needs=("shapely", "pathops")),
    Report("stroke_sets", "bench.stroke", ["--only-sets", "--sets-md", "{md}"],
           quick=["--only-sets", "--sets", "hershey-sans", "--ff-accuracy-sets", "1",
                  "--sets-md", "{md}"],
           cost="12 min of CPU with the peer cache, 15 without, skeleton sets fetched "
                "with npm", snapshot=True, needs=("shapely",)),
    Report("stroke_profile", "bench.stroke_profile", ["--md", "{md}"],
           quick=["--runs", "stroke:hershey-sans", "--repeat", "1", "--md", "{md}"],
           cost="10-20 min, skeleton sets fetched with npm", snapshot=True),
    Report("relief_profile", "bench.relief_profile", ["--md", "{md}"],
           quick=["--tols", "1", "--repeat", "1", "--md", "{md}"], cost="2-4 min",
           snapshot=True),
    Report("numpy_floor", "bench.numpy_floor", ["--md", "{md}"],
           quick=["--sets", "relief", "--repeat", "1", "--no-numba", "--md", "{md}"],
           cost="4-7 min under valgrind's callgrind; a virtualenv with numba made on the "
                "first run (pip)", snapshot=True),
    Report("compile_profile", "bench.compile_profile", ["--md", "{md}"],
           quick=["--repeat", "1", "--md", "{md}"], cost="2-4 min", snapshot=True),
    Report("stroke_memory", "bench.stroke_memory", ["--md", "{md}"],
           quick=["--pairs", "hershey-sans:1", "--md", "{md}"],
           cost="10-20 min, skeleton sets fetched with npm", snapshot=True),
    Report("stroke_memory_all", "bench.stroke_memory", ["--pairs", "hanzi-all:2", "--md", "{md}"],
           quick=["--pairs", "hershey-sans:2", "--md", "{md}"],
           cost="4-10 min on an idle machine (every Make Me a Hanzi character), fetched with npm",
           snapshot=True),
    Report("stroke_memory_sizes", "bench.stroke_memory",
           ["--pairs", "hanzi-300:1,hanzi-300:2,hanzi-3000:1,hanzi-3000:2,hanzi-all:2,"
            "hanzi-variants-30000:2", "--nice", "10", "--md", "{md}"],
           quick=["--pairs", "hershey-sans:1", "--md", "{md}"],
           cost="15 min of CPU (~800 s: 30,000 glyphs take 500), skeleton sets fetched with npm",
           snapshot=True),
    Report("stroke_overlaps", "bench.stroke_overlaps", ["--md", "{md}"],
           quick=["--runs", "hershey-sans:otf,noto-brush:ttf", "--unrounded", "", "--md",
                  "{md}"],
           cost="5-10 min, skeleton sets fetched with npm", snapshot=True,
           needs=("shapely", "pathops")),
    Report("font_writer", "bench.font_writer",
           ["--runs", "300:.otf,300:.ttf,300:.ufo,3000:.otf,3000:.ttf,3000:.ufo,30000:.ttf,"
            "30000:.otf", "--md", "{md}"],
           quick=["--runs", "300:.otf", "--md", "{md}"],
           cost="20-40 min (the writer alone), skeleton sets fetched with npm", snapshot=True),
    Report("stroke_profile_stream", "bench.stroke_profile",
           ["--runs", "stroke:hanzi-300", "--repeat", "1", "--before",
            "bench/stroke_profile.json", "--before-label",
            "the profile before streaming (bench/stroke_profile.json)", "--md", "{md}"],
           quick=["--runs", "stroke:hershey-sans", "--repeat", "1", "--before",
                  "bench/stroke_profile.json", "--md", "{md}"],
           cost="5-10 min, skeleton sets fetched with npm", snapshot=True),
    Report("brush_fontforge", "bench.brush_fontforge", ["--md", "{md}"],
           quick=["--glyphs", "A-C", "--ff-accuracy", "1", "--md", "{md}"],
           cost="30 s with the peer cache, 2-5 min without",
           snapshot=True, needs=("shapely",)),
    Report("brush", "bench.brush", ["--fonts", "ttf,cff,ebg", "--nibs", "80,30,30;60,8,30",
                                    "--compare-jobs", "--fontbakery", "--md", "{md}"],
           quick=["--fonts", "ttf", "--glyphs", "A-C", "--md", "{md}"], cost="5-10 min",
           snapshot=True, needs=("shapely", "fontbakery", "fontpkg_eb_garamond")),
    Report("export", "bench.export", ["--md", "{md}"], quick=["--quick", "--md", "{md}"],
           cost="20-30 min", snapshot=True, check="bench.reports:check_export",
           needs=("kurbopy",)),
    Report("export_sweep", "bench.export_sweep", ["--cases", "3000", "--seed", "0",
                                                  "--md", "{md}"],
           quick=["--cases", "40", "--seed", "0", "--md", "{md}"], cost="4-8 min",
           snapshot=True, needs=("scipy",)),
    Report("icons", "bench.icons", ["--per-set", "150", "--timeout", "60", "--jobs", "2",
                                    "-o", "{md}"],
           quick=["--per-set", "2", "--timeout", "60", "--jobs", "1", "-o", "{md}"],
           cost="5-10 min, icon packages fetched with npm", snapshot=True,
           needs=("shapely",)),
    Report("varfont", "bench.varfont", ["--part", "stroke", "--skeleton", "none", "--measure",
                                        "a,e,g,k,o,s,y,period,H,O,S,eacute", "--out", "{md}"],
           quick=["--part", "stroke", "--skeleton", "none", "--positions", "2", "--random",
                  "0", "--no-fontforge", "--glyphs", "a,s,period", "--out", "{md}"],
           cost="10-20 min", snapshot=True, needs=("scipy",)),
    Report("varfont_brush", "bench.varfont", ["--part", "brush", "--out", "{md}"],
           quick=["--part", "brush", "--positions", "2", "--random", "0", "--cases", "1",
                  "--serif", "", "--out", "{md}"], cost="20-40 min", snapshot=True,
           needs=("scipy",)),
    Report("sweep", "bench.sweep", cost="hours (each mode a section)", snapshot=True,
           needs=("shapely", "fontpkg_lobster", "fontpkg_cormorant", "fontpkg_amiri"),
           runs=[["--mode", m, "--md", "{md}"] + extra for m, extra in (
               ("pairs", ["--jobs", "2"]), ("random", ["--n", "100"]),
               ("fonts", ["--n", "90"]), ("stroke", ["--n", "100"]))],
           quick=["--mode", "random", "--n", "2", "--seed", "1", "--md", "{md}"]),
]
BY_NAME = {r.name: r for r in REPORTS}


# ------------------------------------------------------------------------- stamps

STAMP = re.compile(r"^(Made by|Snapshot made by) `.*$", re.M)


def put_stamp(path, line):
    """Put ``line`` (a stamp) into the report at ``path``: in place of its stamp line, or
    as the first paragraph after its title."""
    text = Path(path).read_text(encoding="utf-8")
    if STAMP.search(text):
        text = STAMP.sub(lambda m: line, text, count=1)
    else:
        head, _, rest = text.partition("\n")
        text = head + "\n\n" + line + "\n" + ("\n" + rest.lstrip("\n") if rest else "")
    Path(path).write_text(text, encoding="utf-8")


def snapshot_stamp(report):
    """The stamp of a committed report not remade now: the commit and date that last
    changed it (the code it measured is that commit's parent or, as the report says,
    an earlier commit), and the command that remakes it."""
    rel = report.path.relative_to(ROOT)
    out = subprocess.run(["git", "log", "-1", "--format=%h %ad", "--date=format:%Y-%m-%d",
                          "--", str(rel)], cwd=ROOT, capture_output=True, text=True)
    commit, _, date = out.stdout.strip().partition(" ")
    return ("Snapshot made by `python -m bench.reports --only %s` (%s on 2 shared CPUs), "
            "committed at commit %s on %s; dated: remake it to measure the code as it is."
            % (report.name, report.cost, commit or "unknown", date or "unknown"))


# ------------------------------------------------------------------------- running

def missing(report):
    """The modules of ``report.needs`` that cannot be imported here."""
    out = []
    for m in report.needs:
        try:
            importlib.import_module(m)
        except ImportError:
            out.append(m)
    return out


def run(report, out_dir=None, quick=False):
    """Write ``report`` (to ``out_dir``/NAME.md, or in place) and stamp it; the seconds."""
    from bench.stamp import stamp

    md = (Path(out_dir) / (report.name + ".md")) if out_dir else report.path
    if md.resolve().is_relative_to(ROOT):   # no machine path in a committed report
        md = md.resolve().relative_to(ROOT)
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    t0 = time.time()
    cmds = report.commands(md, quick)
    for cmd in cmds:
        print("+", " ".join(cmd[1:]), flush=True)
        code = subprocess.run(cmd, cwd=ROOT, env=env, stdout=subprocess.DEVNULL).returncode
        if code:   # a sweep exits 1 when a case failed; its report says which
            print("  exit status %d: see the report" % code, flush=True)
        if not Path(ROOT / md).exists():
            raise SystemExit("%s wrote no report %s" % (" ".join(cmd[1:]), md))
    seconds = time.time() - t0
    shown = "python -m bench.reports --only %s%s" % (report.name, " --quick" if quick else "")
    put_stamp(md, stamp(shown, seconds, script="bench/%s.py" % report.module.split(".")[-1]))
    return seconds


# ------------------------------------------------------------------------- checks

def check_coincident():
    """Two cases of bench/coincident.md that take under a second (ten exact copies; 300
    copies, 150 each way): loops and area as ``svg_region`` reads them now against the
    report's columns."""
    from bench import coincident as C
    from bench.mdtable import cell, tables
    from morph import moments as mo
    from morph.errors import ParseError
    from morph.parse import svg_region

    table = tables(BENCH.joinpath("coincident.md").read_text(encoding="utf-8"))[0]
    cases = {"10 exact copies": " ".join([C.blob_path()] * 10),
             "300 copies, 150 each way (winding 0)":
                 " ".join(C.blob_path(k % 4, k % 2 == 1, k % 4) for k in range(300))}
    out = []
    for name, d in cases.items():
        try:   # as the script's subprocess reads it: a document that fills nothing is 0
            r = svg_region('<svg xmlns="http://www.w3.org/2000/svg"><path '
                           'fill-rule="nonzero" d="%s"/></svg>' % d)
        except ParseError:
            r = []
        out.append(("coincident.md %s: loops" % name, cell(table, name, "loops"), str(len(r))))
        out.append(("coincident.md %s: area" % name, cell(table, name, "area"),
                    "%.4f" % (mo.region_area(r) if r else 0.0)))
    return out


def check_export():
    """Section 1 of bench/export.md: certified cubics for the 90° arc of radius 2 at tol
    1e-3 ... 1e-6, against ``piece_to_cubics`` now."""
    import numpy as np

    from bench.mdtable import cell, section, tables
    from morph import piece as pc
    from morph.export import piece_to_cubics

    text = BENCH.joinpath("export.md").read_text(encoding="utf-8")
    table = tables(section(text, "1. A 90° circular arc"))[0]
    arc = pc.ellipse_arc((0, 0), 2.0, 2.0, 0.0, 0.0, np.pi / 2)[0]
    return [("export.md arc cubics at tol %s" % label, cell(table, label, "morph (certified)"),
             str(len(piece_to_cubics(arc, float(label)))))
            for label in ("1e-03", "1e-04", "1e-05", "1e-06")]


def check_performance():
    """docs/performance.md and the figures of docs/evaluation.md are what
    ``--performance`` makes of the reports now."""
    text = PERFORMANCE.read_text(encoding="utf-8") if PERFORMANCE.exists() else ""
    return [("docs/performance.md made from the reports", "current" if text
             == performance_text() else "stale", "current"),
            ("docs/evaluation.md figures made from the reports", "current" if
             EVALUATION.read_text(encoding="utf-8") == evaluation_text() else "stale",
             "current")]


def checks(names=None):
    """[(what, reported, computed)] of every report's check (and of docs/performance.md),
    and the names of reports whose check could not run here (a module missing)."""
    rows, skipped = [], []
    for r in REPORTS:
        if r.check is None or (names and r.name not in names):
            continue
        mod, fn = r.check.split(":")
        try:
            rows += getattr(importlib.import_module(mod), fn)()
        except ImportError as exc:
            skipped.append("%s (%s)" % (r.name, exc))
    if not names:
        rows += check_performance()
    return rows, skipped


# ------------------------------------------------------------------ performance.md

PERF_SECTIONS = (
    # (report, heading in it: None for the text before its first section, title here)
    ("peers", "1. Glyph sums", "Glyph sums in-process"),
    ("peers", "2. Glyph sums as processes", "Glyph sums as processes"),
    ("peers", "3. Glyph sums: size", "Glyph sums: size at equal measured error"),
    ("peers", "4. Glyph ⊕ nib", "Glyph ⊕ nib: size at equal measured error"),
    ("stroke", "Broad nib", "Stroking a skeleton font: broad nib"),
    ("brush", None, "Brushing a font"),
    ("scaling", None, "How the time grows with the input"),
)


def _report_part(name, heading):
    """The stamp line and the section ``heading`` of a report (None: the text before its
    first section)."""
    from bench.mdtable import section

    text = (BENCH / (name + ".md")).read_text(encoding="utf-8")
    stamp = STAMP.search(text)
    if heading is None:
        body = re.split(r"^## ", text.partition("\n")[2], flags=re.M)[0]
    else:
        body = section(text, heading)
    if stamp:
        body = body.replace(stamp.group(0), "")
    return (stamp.group(0) if stamp else "(no stamp)"), body.strip()


def performance_text():
    """docs/performance.md: an introduction, then sections copied from the reports, each
    with its report's stamp."""
    out = ["# Performance", "",
           "Made by `python -m bench.reports --performance` from the reports under "
           "`bench/`; each section names the report it comes from and when and at which "
           "commit that report was made.  Times are CPU seconds where the machine was "
           "shared (wall times there are upper bounds).  Errors are certified bounds "
           "measured by an independent oracle (`tests/oracles/measure.py`), and sizes "
           "are compared at equal measured error.", "",
           "The peers are each run the strongest way we know, in the same run as morph: "
           "the polygon method (`bench/dc_sum.py`: flatten within tol/2, convex "
           "decomposition, convex pair sums, a tree of Clipper unions), Skia's stroker "
           "(skia-pathops), FontForge's Expand Stroke, kurbo's `offset_cubic` and "
           "shapely's `buffer`; `bench/peers.md` states each recipe next to its numbers.",
           ""]
    for name, heading, title in PERF_SECTIONS:
        path = BENCH / (name + ".md")
        if not path.exists():
            continue
        try:
            stamp, body = _report_part(name, heading)
        except KeyError:
            continue
        body = re.sub(r"^(#+) ", lambda m: "#" + m.group(1) + " ", body, flags=re.M)
        out += ["## %s" % title, "", "From [bench/%s.md](../bench/%s.md). %s"
                % (name, name, stamp), "", body, ""]
    return "\n".join(out).rstrip("\n") + "\n"


# ------------------------------------------------------------------ evaluation.md

EVALUATION = ROOT / "docs" / "evaluation.md"
FIGURES = ("<!-- figures: made by python -m bench.reports --performance -->",
           "<!-- /figures -->")


def _when(text):
    """"commit C, DATE" of a report's or section's Command / stamp line."""
    m = re.search(r"commit ([0-9a-f]{7,})[^;)]*?[;)].*?(\d{4}-\d{2}-\d{2})", text)
    if m:
        return "commit %s, %s" % m.groups()
    m = re.search(r"commit ([0-9a-f]{7,}).*? on (\d{4}-\d{2}-\d{2})", text)
    return "commit %s, %s" % m.groups() if m else "undated"


def evaluation_rows():
    """(check, cases, failed, when) from the acceptance reports as they are."""
    from bench.mdtable import tables

    rows = []
    sweep = (BENCH / "sweep.md").read_text(encoding="utf-8")
    for block in re.findall(r"<!-- sweep:\w+ -->\n(.*?)<!-- /sweep:\w+ -->", sweep, re.S):
        title = block.splitlines()[0].lstrip("# ").strip()
        m = re.search(r"(\d+) of (\d+) jobs run, (\d+) failed", block)
        if m:
            rows.append(("sweep: " + title, m.group(1), m.group(3), _when(block)))  # run
    icons = (BENCH / "icons.md").read_text(encoding="utf-8")
    for t in tables(icons)[:1]:
        col = {name: k for k, name in enumerate(t[0])}
        for r in t[1:]:
            limits = int(r[col["documented limit"]])
            rows.append(("icons: %s%s" % (r[0], ", %d documented limits" % limits
                                          if limits else ""), r[col["icons"]],
                         str(int(r[col["icons"]]) - int(r[col["pass"]]) - limits),
                         _when(icons)))
    ex = (BENCH / "export_sweep.md").read_text(encoding="utf-8")
    for r in tables(ex)[0][1:]:
        rows.append(("certified cubic export: %s pieces" % r[0], r[1], r[2], _when(ex)))
    ins = (BENCH / "inset.md").read_text(encoding="utf-8")
    m = re.search(r"(\d+) cases .*?: (\d+) failed", ins)
    if m:
        rows.append(("insets against shapely", m.group(1), m.group(2), _when(ins)))
    co = (BENCH / "coincident.md").read_text(encoding="utf-8")
    t = tables(co)[0]
    rows.append(("copies of one path", str(len(t) - 1),
                 str(sum(r[-1] != "yes" for r in t[1:])), _when(co)))
    return rows


def evaluation_figures():
    """The block of docs/evaluation.md between the FIGURES markers."""
    out = [FIGURES[0], "", "| check | cases | failed | the report's commit and date |", "|---|---|---|---|"]
    out += ["| %s | %s | %s | %s |" % r for r in evaluation_rows()]
    return "\n".join(out + ["", FIGURES[1]])


def evaluation_text():
    """docs/evaluation.md with its figures block remade from the reports."""
    text = EVALUATION.read_text(encoding="utf-8")
    i, j = text.index(FIGURES[0]), text.index(FIGURES[1]) + len(FIGURES[1])
    return text[:i] + evaluation_figures() + text[j:]


# ------------------------------------------------------------------------- main

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="comma-separated report names (see --list)")
    ap.add_argument("--quick", action="store_true",
                    help="a small run of every script, into --out (not the committed reports)")
    ap.add_argument("--out", help="folder for --quick (default: a new temporary folder)")
    ap.add_argument("--check", action="store_true",
                    help="headline numbers of the reports against their scripts")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--performance", action="store_true",
                    help="only write docs/performance.md from the reports")
    ap.add_argument("--skip-snapshots", action="store_true",
                    help="leave the reports marked snapshot as they are")
    ap.add_argument("--stamp-snapshots", action="store_true",
                    help="stamp the snapshot reports from the git history (no run)")
    args = ap.parse_args(argv)
    names = args.only.split(",") if args.only else None
    unknown = [n for n in names or () if n not in BY_NAME]
    if unknown:
        ap.error("unknown report(s) %s; see --list" % ", ".join(unknown))
    chosen = [r for r in REPORTS if not names or r.name in names]
    if args.list:
        for r in REPORTS:
            print("%-13s %-9s %-45s %s" % (r.name, "snapshot" if r.snapshot else "", r.cost,
                                           " ; ".join(" ".join(c[1:]) for c in
                                                      r.commands("bench/%s.md" % r.name))))
        return 0
    if args.check:
        rows, skipped = checks(names)
        bad = [row for row in rows if row[1] != row[2]]
        for what, reported, computed in rows:
            print("%s %s: report %s, now %s" % ("ok  " if reported == computed else "FAIL",
                                               what, reported, computed))
        for s in skipped:
            print("skipped:", s)
        return 1 if bad else 0
    if args.stamp_snapshots:
        for r in chosen:
            if r.snapshot and r.path.exists():
                put_stamp(r.path, snapshot_stamp(r))
        return 0
    if not args.performance:
        out_dir = None
        if args.quick:
            out_dir = Path(args.out or tempfile.mkdtemp(prefix="morph-reports-"))
            out_dir.mkdir(parents=True, exist_ok=True)
        for r in chosen:
            if r.snapshot and args.skip_snapshots and not args.quick:
                continue
            gone = missing(r)
            if gone:
                print("skip %s: needs %s" % (r.name, ", ".join(gone)), flush=True)
                continue
            print("%s: %.0f s" % (r.name, run(r, out_dir, args.quick)), flush=True)
        if args.quick:
            print("quick reports in", out_dir)
            return 0
    PERFORMANCE.parent.mkdir(exist_ok=True)
    PERFORMANCE.write_text(performance_text(), encoding="utf-8")
    EVALUATION.write_text(evaluation_text(), encoding="utf-8")
    print("wrote", PERFORMANCE.relative_to(ROOT), "and the figures of",
          EVALUATION.relative_to(ROOT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
