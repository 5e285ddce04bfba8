"""morph and a peer timed in the same run, interleaved: the comparison reports' rounds.

On a shared machine the same command's CPU time drifts by 20-40 % from one hour to
the next, so a peer's time measured in another run cannot be set against morph's.
The comparison reports (``bench/stroke.py``, ``bench/brush_fontforge.py``) time both
in rounds: each round times morph once, then the peer once (ABAB..., the same count
of each), and report each side's median and the median of the per-round ratios
morph / peer (:func:`ratio`), which a drift of the machine's speed hits alike on
both sides of a pair.  The peer's outlines and their judged errors do not depend on
the machine's state and stay in the bench cache (:mod:`bench.peer_cache`); its times
are measured here, in every run.
"""

import ast
import json
import os
import statistics
import subprocess
import sys
import tempfile

SYSTEM_PYTHON = "/usr/bin/python3"


# a small launcher between the bench and the child: Linux counts a process's resident
# set before its exec in its peak (ru_maxrss), so a child forked from the bench itself
# would report at least the bench's size; forked from the launcher, at least its ~10 MB
LAUNCH = ("import os, sys\n"
          "pid = os.fork()\n"
          "if pid == 0:\n"
          "    os.execvp(sys.argv[2], sys.argv[2:])\n"
          "_, status, usage = os.wait4(pid, 0)\n"
          "with open(sys.argv[1], 'w') as f:\n"
          "    f.write(repr((usage.ru_utime + usage.ru_stime, usage.ru_maxrss,\n"
          "                  os.waitstatus_to_exitcode(status))))\n")


def child_run(cmd, input=None, **kwargs):
    """(CPU seconds, peak RSS MB, exit status, stdout, stderr) of one child process
    ``cmd`` fed ``input`` (text): its own rusage from ``os.wait4`` (the kernel's user +
    sys time and peak resident set of the child and of the children it waited for),
    so that the other children of the bench, morph's and the peer's alike, never
    count in it.  The child is started by :data:`LAUNCH` (whose own time does not
    count), and its output goes through temporary files."""
    with tempfile.TemporaryDirectory() as tmp:
        usage = os.path.join(tmp, "usage")
        with open(os.path.join(tmp, "in"), "w+") as fin, \
                open(os.path.join(tmp, "out"), "w+") as fout, \
                open(os.path.join(tmp, "err"), "w+") as ferr:
            fin.write(input or "")
            fin.seek(0)
            subprocess.run([sys.executable, "-c", LAUNCH, usage] + list(cmd), stdin=fin,
                           stdout=fout, stderr=ferr, check=True, **kwargs)
            fout.seek(0)
            ferr.seek(0)
            with open(usage) as f:
                cpu, rss, code = ast.literal_eval(f.read())
            return cpu, rss / 1024.0, code, fout.read(), ferr.read()


def warm_fontforge():
    """One untimed ``import fontforge`` in the system Python, so that FontForge's first
    timed run finds its libraries in the page cache, as morph's first timed command
    finds its bytecode (:mod:`bench.pycache`)."""
    subprocess.run([SYSTEM_PYTHON, "-c", "import fontforge"], capture_output=True)


def interpreter_starts(env=None):
    """CPU seconds of a bare start of each side's interpreter, ``-c pass`` with its site
    (the .pth files of its site-packages run): (morph's
    :func:`bench.pycache.installed_python` in the environment ``env`` of morph's
    commands, FontForge's :data:`SYSTEM_PYTHON`).  Both are in every whole command of
    their side and are no work of either tool."""
    from bench.pycache import installed_python

    return (child_run([installed_python(), "-c", "pass"], env=env)[0],
            child_run([SYSTEM_PYTHON, "-c", "pass"])[0])


def starts_note(rounds, glyphs):
    """The report's sentence on :func:`interpreter_starts` measured in ``rounds`` (a
    list of its pairs), for a font of ``glyphs`` glyphs."""
    from bench.pycache import installed_python, site_pth

    ours, peer = (1000 * median([r[k] for r in rounds]) for k in (0, 1))
    return ("Interpreter start alone (`-c pass` with its site, timed in the same rounds): "
            "morph's Python %.0f ms (%.2f ms / glyph of the whole command), FontForge's "
            "system Python %.0f ms (%.2f ms / glyph of its worker); part of each side's "
            "whole command, no work of either tool. morph's commands run in a virtual "
            "environment's site, as installed (`bench/pycache.py`), whose .pth files are: %s."
            % (ours, ours / glyphs, peer, peer / glyphs,
               ", ".join(site_pth(installed_python())) or "none"))


def worker_times(script, job, names):
    """One timed run of a FontForge worker (``bench/fontforge_stroke.py`` or
    ``bench/fontforge_brush.py``) on the JSON ``job``: {"mean": in-process seconds per
    glyph, the mean over ``names``; "median": their median; "process": the worker
    process's CPU seconds}.  Raises when the worker fails."""
    cpu, _, code, out, err = child_run([SYSTEM_PYTHON, str(script)], json.dumps(job))
    if code != 0:
        raise RuntimeError("%s failed: %s" % (script, err.strip().splitlines()[-1:]))
    res = json.loads(out)
    secs = [res[n]["seconds"] for n in names]
    return {"mean": statistics.fmean(secs), "median": statistics.median(secs),
            "process": cpu}


def ratio(morph, peer):
    """The median of the per-round ratios ``morph[i] / peer[i]`` (the two lists timed in
    the same rounds), or None when either is missing or their lengths differ."""
    if not morph or not peer or len(morph) != len(peer):
        return None
    pairs = [m / p for m, p in zip(morph, peer) if m is not None and p]
    return statistics.median(pairs) if pairs else None


def ratio_cell(morph, peer):
    """:func:`ratio` for a table cell: "0.84", or "" when not measured in pairs."""
    r = ratio(morph, peer)
    return "" if r is None else "%.2f" % r


def median(values):
    """The median of ``values`` (None for none)."""
    return statistics.median(values) if values else None
