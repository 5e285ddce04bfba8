"""The line every committed report starts with: how it was made, at which version and
commit, when, and on what machine (so that a reader can tell a report from a stale one).

``python -m bench.reports`` regenerates every report; ``tests/test_reports.py`` checks
their headline numbers against the scripts on small cases.
"""

import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def commit(paths=("morph",)):
    """The repository's commit, with "+ uncommitted changes" when ``paths`` (the code
    measured: morph/, and the script) differ from it; "unknown" outside a git
    checkout."""
    def git(*args):
        return subprocess.run(("git",) + args, cwd=ROOT, capture_output=True, text=True,
                              timeout=30)
    try:
        head = git("rev-parse", "--short", "HEAD")
        if head.returncode:
            return "unknown"
        dirty = git("status", "--porcelain", "--", *paths).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head.stdout.strip() + (" + uncommitted changes" if dirty else "")


def machine():
    """CPU count, processor and OS, and the load average while the report is made."""
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return "%d CPUs (%s, %s), load average %.1f, Python %s" % (
        os.cpu_count() or 0, platform.machine(), platform.system(), load,
        platform.python_version())


def stamp(command=None, seconds=None, script=None):
    """Markdown line: ``Made by `command` with morph VERSION at commit C on DATE (UTC),
    on MACHINE[, in S s].``  ``command`` defaults to this process's command line;
    ``script`` (a path relative to the repository) is checked for changes with morph/
    (default: the running script)."""
    from morph import __version__

    if command is None:
        command = "python " + " ".join([_module_name(sys.argv[0])] + sys.argv[1:])
    tail = "" if seconds is None else ", in %.0f s" % seconds
    if script is None and Path(sys.argv[0]).resolve().is_relative_to(ROOT):
        script = str(Path(sys.argv[0]).resolve().relative_to(ROOT))
    paths = ("morph",) + ((script,) if script else ())
    return "Made by `%s` with morph %s at commit %s on %s (UTC), on %s%s." % (
        command.strip(), __version__, commit(paths), time.strftime("%Y-%m-%d %H:%M",
                                                                  time.gmtime()),
        machine(), tail)


def emit(text, opt):
    """Print a report's ``text`` and write it to ``opt.md`` unless ``opt.no_write``;
    returns 0, the script's exit status."""
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text)
    return 0


def _module_name(argv0):
    """``-m bench.x`` for a script of bench/ (how the reports are run), else argv0."""
    p = Path(argv0)
    if p.parent.name == "bench" and p.suffix == ".py":
        return "-m bench." + p.stem
    return argv0
