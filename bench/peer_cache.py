"""The bench cache of the figures that do not depend on morph's code.

The comparison reports (``bench/stroke.py``, ``bench/brush_fontforge.py``) measure
morph against an independent Clipper reference and against FontForge.  Neither
changes when morph changes, and they take most of a report's time (FontForge's
outlines are also judged against the reference, glyph by glyph), so they are
kept here: the references, FontForge's outlines, points, "Internal Error" counts
and judged errors.  What depends on the machine's state is never cached: morph's
output and times, and FontForge's times, which the reports measure in every run,
in rounds interleaved with morph's (:mod:`bench.paired`).

Entries are pickles in the bench cache (``MORPH_BENCH_CACHE``, default
``bench/cache/``, git-ignored; :func:`bench.skeletons.cache_dir`) under
``peers/KIND/``, one file per key.  A key is the SHA-256 (:func:`digest`) of
everything the entry is a function of:

- the input's content: the skeleton's numbers (or the source font file's bytes),
  never a glyph's name alone, so an edited glyph misses;
- the nib (its outline's numbers) and the tolerance or accuracy;
- the version of what computes it: FontForge's version (:func:`fontforge_version`)
  and the bytes of the worker script, or the oracle's source files and the versions
  of pyclipper and shapely; for judged errors, the judge's parameters and source.

Every entry records when, at which commit and with which peer version it was
measured (:func:`provenance`); the reports say so (:func:`measured_note`).
The reference polygons are flattened by ``morph.polyline.flatten`` (tested on its
own), which is not part of their key: a reference is within its tolerance of the
exact stroke whichever version flattened it, and keeping the one measured earlier
keeps the oracle independent of the code it judges.
"""

import functools
import hashlib
import inspect
import os
import pickle
import subprocess
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SYSTEM_PYTHON = "/usr/bin/python3"


# ------------------------------------------------------------------------ keys

def _feed(h, obj):
    """Feed ``obj`` (nested lists, tuples, dicts, arrays, numbers, strings, bytes,
    None) into the hash ``h``, each value tagged with its type and length, so that
    different structures never hash alike."""
    if isinstance(obj, np.ndarray) or isinstance(obj, np.generic):
        a = np.ascontiguousarray(np.asarray(obj, dtype=float))
        h.update(b"a%r" % (a.shape,))
        h.update(a.tobytes())
    elif isinstance(obj, (list, tuple)):
        h.update(b"l%d" % len(obj))
        for x in obj:
            _feed(h, x)
    elif isinstance(obj, dict):
        h.update(b"d%d" % len(obj))
        for k in sorted(obj):
            _feed(h, k)
            _feed(h, obj[k])
    elif isinstance(obj, bool) or obj is None:
        h.update(b"b%r" % (obj,))
    elif isinstance(obj, (int, float)):
        h.update(b"f" + float(obj).hex().encode())
    elif isinstance(obj, str):
        b = obj.encode()
        h.update(b"s%d:" % len(b) + b)
    elif isinstance(obj, bytes):
        h.update(b"y%d:" % len(obj) + obj)
    else:
        raise TypeError("cannot key a %s" % type(obj).__name__)


def digest(*parts):
    """The hex SHA-256 of ``parts`` (see :func:`_feed`)."""
    h = hashlib.sha256()
    _feed(h, list(parts))
    return h.hexdigest()


def file_digest(*paths):
    """The SHA-256 of the files' bytes (paths relative to the repository root)."""
    return digest([(str(p), (ROOT / p).read_bytes()) for p in paths])


def source_digest(*objs):
    """The SHA-256 of the Python source of functions or modules."""
    return digest([inspect.getsource(o) for o in objs])


# ------------------------------------------------------------------------ store

def _path(kind, key):
    from bench.skeletons import cache_dir

    return cache_dir() / "peers" / kind / key[:2] / (key[2:] + ".pickle")


def get(kind, key):
    """The entry stored under ``key`` in ``kind``, or None (absent or unreadable)."""
    path = _path(kind, key)
    try:
        with open(path, "rb") as f:
            return pickle.load(f)
    except (OSError, EOFError, pickle.UnpicklingError):
        return None


def put(kind, key, value):
    """Store ``value`` under ``key`` (written to a temporary file, then renamed, so that
    an interrupted run leaves no half entry)."""
    path = _path(kind, key)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp%d" % os.getpid())
    with open(tmp, "wb") as f:
        pickle.dump(value, f, protocol=pickle.HIGHEST_PROTOCOL)
    os.replace(tmp, path)
    return value


# ------------------------------------------------------------------------ provenance

@functools.lru_cache(maxsize=None)
def fontforge_version():
    """"FontForge V (python3-fontforge D)": ``fontforge.version()`` in the system
    Python and the Debian package's version; None where FontForge is missing."""
    if not os.path.exists(SYSTEM_PYTHON):
        return None
    proc = subprocess.run([SYSTEM_PYTHON, "-c", "import fontforge; print(fontforge.version())"],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        return None
    deb = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "python3-fontforge"],
                         capture_output=True, text=True).stdout.strip()
    return "FontForge %s%s" % (proc.stdout.strip(), " (python3-fontforge %s)" % deb if deb else "")


@functools.lru_cache(maxsize=None)
def oracle_version():
    """The Clipper reference's version: its source files, pyclipper and shapely."""
    import pyclipper
    import shapely

    return "pyclipper %s, shapely %s (GEOS %s), oracle %s" % (
        pyclipper.__version__, shapely.__version__, shapely.geos_version_string,
        file_digest("tests/oracles/stroke_reference.py", "tests/oracles/reference.py")[:12])


def provenance(peer):
    """When (UTC), at which commit and with which ``peer`` version an entry is measured,
    and the load average then."""
    from bench.stamp import commit

    return {"utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
            "commit": commit(("morph", "bench", "tests/oracles")), "peer": peer,
            "load": round(os.getloadavg()[0], 1)}


def measured_note(entries, fresh=0):
    """A sentence fragment saying when, at which commits and with which peer versions
    ``entries`` (provenance dicts) were measured; ``fresh`` of them now."""
    if not entries:
        return "none"
    times = sorted(e["utc"] for e in entries)
    commits = sorted({e["commit"] for e in entries})
    peers = sorted({e["peer"] for e in entries})
    when = times[0] if times[0] == times[-1] else "%s to %s" % (times[0], times[-1])
    cached = len(entries) - fresh
    return ("measured %s UTC at commit %s with %s (%s)"
            % (when, ", ".join(commits), "; ".join(peers),
               "all from the cache" if not fresh else "all now" if not cached
               else "%d from the cache, %d now" % (cached, fresh)))


def cached(kind, key, compute, peer):
    """(value, provenance, fresh): the entry ``key`` of ``kind``, or ``compute()``
    stored there with its :func:`provenance` (``peer``: the peer's version)."""
    hit = get(kind, key)
    if hit is not None:
        return hit["value"], hit["provenance"], False
    prov = provenance(peer)
    value = compute()
    put(kind, key, {"value": value, "provenance": prov})
    return value, prov, True


# ------------------------------------------------------------------------ self-check

def check(folder):
    """Check that the cache misses when its input changes, in a fresh cache under
    ``folder``: two glyphs' references and FontForge's outlines are made, then read
    back; a glyph moved by 1 unit, another tol and another nib are made again; FontForge's
    times are measured in rounds, never read back.  [(what, passed)]."""
    from bench import stroke as bs
    from bench.skeletons import write_ufo
    from morph.parse.ufo import load_ufo

    os.environ["MORPH_BENCH_CACHE"] = str(Path(folder) / "cache")
    spec = ("ellipse", 90.0, 20.0, 30.0)
    glyphs = [("a", 0x61, 500.0, [[(100.0, 0.0), (100.0, 400.0), (300.0, 500.0)]]),
              ("b", 0x62, 500.0, [[(50.0, 50.0), (400.0, 50.0)],
                                  [(200.0, 0.0), (200.0, 300.0)]])]
    moved = [glyphs[0], glyphs[1][:3] + ([glyphs[1][3][0], [(200.0, 0.0), (200.0, 301.0)]],)]

    def font(name, gl):
        path = Path(folder) / name
        write_ufo(path, "Cache Check", gl, 1000.0)
        return load_ufo(path, lazy=False)

    made = []
    real = bs.stroke_polygon

    def counted(paths, nib, tol):
        made.append(len(paths))
        return real(paths, nib, tol)

    out = []
    a = np.array([[0.0, 1.0], [2.0, 3.0]])
    out.append(("digest: equal numbers alike, a moved number, another tol, another "
                "nesting apart", digest([a], 0.5) == digest([a.copy()], 0.5)
                and digest([a], 0.5) != digest([a + [[0, 0], [0, 1e-4]]], 0.5)
                and digest([a], 0.5) != digest([a], 0.25)
                and digest([1, [2, 3]]) != digest([[1, 2], 3])
                and digest("ab", "c") != digest("a", "bc")))
    bs.stroke_polygon = counted
    try:
        one, two = font("one.ufo", glyphs), font("two.ufo", moved)
        refs, keys, note = bs.references(one, ["a", "b"], spec, 0.05)
        out.append(("references: made the first time", len(made) == 2
                    and note.endswith("(all now)")))
        again, keys2, note = bs.references(one, ["a", "b"], spec, 0.05)
        out.append(("references: read back the second time, the same polygons",
                    len(made) == 2 and keys2 == keys and note.endswith("(all from the cache)")
                    and all(again[n].equals_exact(refs[n], 0.0) for n in "ab")))
        refs3, keys3, note = bs.references(two, ["a", "b"], spec, 0.05)
        out.append(("references: the glyph with a point moved 1 unit made again, 1 unit "
                    "taller; the other read back", len(made) == 3
                    and note.endswith("(1 from the cache, 1 now)")
                    and keys3["a"] == keys["a"] and keys3["b"] != keys["b"]
                    and abs(refs3["b"].bounds[3] - refs["b"].bounds[3] - 1.0) < 0.05))
        bs.references(one, ["a"], spec, 0.04)
        bs.references(one, ["a"], ("ellipse", 90.0, 20.0, 31.0), 0.05)
        out.append(("references: another tol, another nib made again", len(made) == 5))
    finally:
        bs.stroke_polygon = real
    if fontforge_version() is None:
        return out + [("FontForge: not installed, its cache not checked", True)]
    return out + _check_fontforge(bs, folder, spec, (one, refs, keys), (two, refs3, keys3))


def _check_fontforge(bs, folder, spec, one, two):
    """:func:`check`'s part on FontForge: its outlines and errors cached, missed for an
    edited set, never its times, which rounds measure in the run.  ``one``, ``two``:
    (font, references, their keys) of the set and of the set with a point moved."""
    from bench.paired import ratio

    out = [("paired ratio: the median of the per-round ratios, none for unpaired lists",
            ratio([2.0, 4.0, 9.0], [1.0, 4.0, 3.0]) == 2.0
            and ratio([2.0, 4.0], [1.0]) is None and ratio([], []) is None)]
    judge = bs._plain_judge(*one[1:])
    rows, why = bs.run_fontforge(one[0], ["a", "b"], spec, [1.0], one[1], judge)
    out.append(("FontForge: outlines made the first time", not why
                and rows[0]["measured"].endswith("(all now)")))
    again, _ = bs.run_fontforge(one[0], ["a", "b"], spec, [1.0], one[1], judge)
    entry = get("fontforge-stroke", again[0]["outline_key"])["value"]
    out.append(("FontForge: read back the second time, the same outlines and errors; no "
                "time in the cache", again[0]["measured"].endswith("(all from the cache)")
                and again[0]["errs"] == rows[0]["errs"]
                and again[0]["points"] == rows[0]["points"] and "process_cpu" not in entry
                and not any("seconds" in g for g in entry["results"].values())))
    new, _ = bs.run_fontforge(two[0], ["a", "b"], spec, [1.0], two[1],
                              bs._plain_judge(*two[1:]))
    out.append(("FontForge: the set with a point moved measured again, its outline "
                "following the edit", new[0]["measured"].endswith("(all now)")
                and new[0]["errs"][1] <= 1.25))
    rounds = bs.FontForgeRounds(bs.fontforge_jobs(one[0], ["a", "b"], spec, [1.0]),
                                ["a", "b"], Path(folder) / "one.ufo", spec, folder)
    rounds()
    rounds()
    rounds.fill(again)
    r = again[0]
    out.append(("FontForge: times measured in the run, a round each: in process, worker, "
                "whole workflow", r["rounds"] == 2 and all(
                    len(r[k]) == 2 and min(r[k]) > 0
                    for k in ("ms_runs", "process_runs", "workflow_runs"))
                and r["workflow"]["glyphs"] == 2 and r["process_ms"] > r["ms"]))
    return out


def main(argv=None):
    import argparse
    import sys
    import tempfile

    ap = argparse.ArgumentParser(description="Check that the bench cache of peer figures "
                                             "misses when its input changes.")
    ap.add_argument("--check", action="store_true", required=True)
    ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        rows = check(tmp)
    for what, ok in rows:
        print("%s %s" % ("ok  " if ok else "FAIL", what))
    sys.exit(0 if all(ok for _, ok in rows) else 1)


if __name__ == "__main__":
    main()
