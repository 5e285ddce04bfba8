"""The bench cache of the figures that do not depend on morph's code.

The comparison reports (``bench/stroke.py``, ``bench/brush_fontforge.py``) measure
morph against an independent Clipper reference and against FontForge.  Neither
changes when morph changes, and they take most of a report's time (FontForge's
outlines are also judged against the reference, glyph by glyph), so they are
kept here and a remade report measures only morph again.  morph's own output is
never cached.

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
