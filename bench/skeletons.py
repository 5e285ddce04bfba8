"""Skeleton fonts for the stroke benchmarks, fetched at bench time and converted to UFOs.

    python -m bench.skeletons [hershey-sans hershey-script hanzi-300 ...] [--cache DIR]

Sets (each a skeleton UFO: every contour an open polyline, y up):

- ``hershey-sans``, ``hershey-script``: the Hershey fonts' single-stroke sans
  (``HersheySans1``) and script (``HersheyScript1``) faces, from the npm package
  ``hersheytext`` (MIT; the Hershey data's own notice is kept in the SVG files it
  ships).  Its SVG fonts hold one ``<glyph d=...>`` per character in font units
  (y up, units per em from ``<font-face>``, 1000 when absent), drawn with ``M`` and
  ``L`` only; every ``M`` starts an open contour.  The glyphs with an outline (94
  each: ASCII 33-126) are written.
- ``hanzi-N``: N Chinese characters' stroke medians (the centre line of every
  stroke, as a list of points) from the npm package ``hanzi-writer-data`` (data of
  Make Me a Hanzi; Arphic Public License: fetched into the cache, never committed).
  Its coordinates are font units of a 1024 em, y up, baseline at 0 (the package's
  SVG transform is ``translate(0, 900) scale(1, -1)``), so they are written as they
  are with advance 1024.  The N characters are spread evenly over the package's
  characters sorted by code point (index ``round(k (M - 1) / (N - 1))``), so 300 and
  3000 are samples of the same mix; ``hanzi-all`` is every character (9574).
- ``relief``: the whole Relief SingleLine UFO (SIL OFL), a real centre-line font of
  584 glyphs, 384 of them composites, from the shared data folder
  (``relief-singleline`` beside the repository, see its README): not fetched, and
  :func:`available` leaves it out where the folder is absent.
- ``hanzi-variants-N``: N distinct glyphs (up to 65,535) made of the hanzi under
  affine maps, for fonts larger than the real set (:mod:`bench.skeleton_variants`).

The packages are fetched with ``npm pack`` (the npm registry) into the cache
(default ``bench/cache/``, git-ignored; ``MORPH_BENCH_CACHE`` or ``--cache``
overrides) once; the UFOs are written there too, so nothing fetched is committed.
:func:`skeleton_ufo` returns the UFO's path, building what is missing.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tarfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PACKAGES = {"hersheytext": "2.0.0", "hanzi-writer-data": "2.0.1"}
HERSHEY = {"hershey-sans": "HersheySans1", "hershey-script": "HersheyScript1"}
HANZI_EM = 1024


def cache_dir(cache=None):
    path = Path(cache or os.environ.get("MORPH_BENCH_CACHE") or ROOT / "bench" / "cache")
    path.mkdir(parents=True, exist_ok=True)
    return path


def package_dir(name, cache=None):
    """The unpacked npm package ``name`` (version :data:`PACKAGES`) in the cache."""
    cache = cache_dir(cache)
    version = PACKAGES[name]
    out = cache / ("%s-%s" % (name, version))
    if (out / "package" / "package.json").exists():
        return out / "package"
    tgz = cache / ("%s-%s.tgz" % (name, version))
    if not tgz.exists():
        proc = subprocess.run(["npm", "pack", "%s@%s" % (name, version)], cwd=str(cache),
                              capture_output=True, text=True)
        if proc.returncode != 0 or not tgz.exists():
            raise SystemExit("bench.skeletons: npm pack %s@%s failed: %s"
                             % (name, version, proc.stderr.strip()[-300:]))
    with tarfile.open(tgz) as tar:
        tar.extractall(out, filter="data")
    return out / "package"


# =========================================================================== Hershey

def _svg_contours(d):
    """The open polylines of an SVG path made of M and L commands (absolute)."""
    contours = []
    for cmd, args in re.findall(r"([MLml])([^MLml]*)", d):
        nums = [float(v) for v in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", args)]
        pts = list(zip(nums[0::2], nums[1::2]))
        if cmd == "M":
            contours.append(pts)
        elif cmd == "L" and contours:
            contours[-1] += pts
        else:
            raise ValueError("only absolute M and L occur in the Hershey SVG fonts, not %r" % cmd)
    return [c for c in contours if len(c) >= 2]


def hershey_glyphs(face, cache=None):
    """[(name, unicode, advance, contours)] of a Hershey SVG font, and its units per em."""
    text = (package_dir("hersheytext", cache) / "svg_fonts" / (face + ".svg")).read_text()
    em = re.search(r'<font-face[^>]*units-per-em="([\d.]+)"', text)
    upm = float(em.group(1)) if em else 1000.0
    out = []
    for attrs in re.findall(r"<glyph\s([^>]*)/>", text):
        a = dict(re.findall(r'([\w-]+)="([^"]*)"', attrs))
        if not a.get("d"):
            continue
        uni = a.get("unicode", "")
        uni = uni.replace("&quot;", '"').replace("&amp;", "&").replace("&lt;", "<")
        m = re.fullmatch(r"&#x([0-9A-Fa-f]+);", uni)
        code = int(m.group(1), 16) if m else (ord(uni) if len(uni) == 1 else None)
        if code is None or not 33 <= code <= 126:
            continue  # the ASCII set; the faces' other glyphs repeat names
        out.append((a.get("glyph-name") or "uni%04X" % code, code,
                    float(a.get("horiz-adv-x", upm)), _svg_contours(a["d"])))
    return out, upm


# =========================================================================== hanzi

def hanzi_chars(cache=None):
    pkg = package_dir("hanzi-writer-data", cache)
    chars = sorted(p.stem for p in pkg.glob("*.json") if len(p.stem) == 1)
    return pkg, chars


def hanzi_sample(n, cache=None):
    """``n`` characters spread evenly over the package's, by code point (None: all)."""
    pkg, chars = hanzi_chars(cache)
    if n is None or n >= len(chars):
        return pkg, chars
    m = len(chars)
    idx = sorted({round(k * (m - 1) / max(1, n - 1)) for k in range(n)})
    return pkg, [chars[i] for i in idx]


def hanzi_glyphs(n, cache=None):
    pkg, chars = hanzi_sample(n, cache)
    out = []
    for ch in chars:
        medians = json.loads((pkg / (ch + ".json")).read_text())["medians"]
        contours = [[(float(x), float(y)) for x, y in m] for m in medians if len(m) >= 2]
        out.append(("uni%04X" % ord(ch), ord(ch), float(HANZI_EM), contours))
    return out, float(HANZI_EM)


# =========================================================================== UFO

def write_ufo(path, family, glyphs, upm):
    """A skeleton UFO of ``glyphs`` [(name, unicode, advance, polylines)]."""
    import ufoLib2

    font = ufoLib2.Font()
    font.info.familyName = family
    font.info.styleName = "Regular"
    font.info.unitsPerEm = upm
    font.info.ascender = round(0.8 * upm)
    font.info.descender = -round(0.2 * upm)
    font.info.xHeight = round(0.5 * upm)
    font.info.capHeight = round(0.7 * upm)
    order = []
    for name, code, advance, contours in glyphs:
        g = font.newGlyph(name)
        g.width = advance
        if code is not None:
            g.unicodes = [code]
        pen = g.getPointPen()
        for pts in contours:
            pen.beginPath()
            for k, p in enumerate(pts):
                pen.addPoint(p, "move" if k == 0 else "line")
            pen.endPath()
        order.append(name)
    font.glyphOrder = order
    font.save(str(path), overwrite=True)
    return path


def shared_relief():
    """The whole Relief SingleLine UFO of the shared data folder, or None."""
    for data in (ROOT.parent.parent / "shared" / "data", Path("/work/shared/data")):
        path = data / "relief-singleline" / "Relief-SingleLine.ufo"
        if (path / "metainfo.plist").exists():
            return path
    return None


def available(names):
    """The sets of ``names`` this machine can build (``relief`` only with the shared
    data folder; the npm sets are fetched when missing)."""
    return [n for n in names if n != "relief" or shared_relief() is not None]


def skeleton_ufo(name, cache=None):
    """The path of the skeleton UFO of set ``name`` (see the module doc), built when
    missing."""
    if name == "relief":
        if shared_relief() is None:
            raise SystemExit("bench.skeletons: no shared data folder with Relief SingleLine")
        return shared_relief()
    cache = cache_dir(cache)
    path = cache / (name + ".ufo")
    if (path / "metainfo.plist").exists():
        return path
    if name.startswith("hanzi-variants-"):
        from bench.skeleton_variants import variants_ufo

        return variants_ufo(int(name.rsplit("-", 1)[1]), cache=cache)
    if name in HERSHEY:
        glyphs, upm = hershey_glyphs(HERSHEY[name], cache)
        family = "Hershey %s Skeleton" % name.split("-")[1].title()
    elif name.startswith("hanzi-"):
        n = None if name == "hanzi-all" else int(name.split("-")[1])
        glyphs, upm = hanzi_glyphs(n, cache)
        family = "Hanzi Medians %s" % name.split("-")[1]
    else:
        raise SystemExit("bench.skeletons: unknown set %r (hershey-sans, hershey-script, "
                         "hanzi-N, hanzi-all, hanzi-variants-N, relief)" % name)
    return write_ufo(path, family, glyphs, upm)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sets", nargs="*", default=["hershey-sans", "hershey-script", "hanzi-300"])
    ap.add_argument("--cache")
    opt = ap.parse_args(argv)
    for s in opt.sets:
        path = skeleton_ufo(s, opt.cache)
        print(path)


if __name__ == "__main__":
    sys.exit(main())
