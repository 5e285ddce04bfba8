"""A skeleton UFO of N distinct glyphs (up to 65,535) made from the hanzi medians, for
measuring ``morph stroke`` on fonts larger than any real skeleton set.

    python -m bench.skeleton_variants 30000 [--seed 0] [--cache DIR]

The set ``hanzi-variants-N`` (:func:`variants_ufo`, also reached through
:func:`bench.skeletons.skeleton_ufo`): glyph k is the skeleton of the ``k mod M``-th
character of ``hanzi-all`` (M = 9,574, in the source's glyph order) under map
``k // M``: map 0 is the identity (so the first M glyphs are the real set), every
other map an affine map of its own drawn for that glyph from a generator seeded
with ``(seed, k)`` (deterministic): a mirror (left-right, half of them), a rotation
of up to 6 degrees, a slant (shear) of up to 0.25 and a scale of 0.85-1 on each
axis, about the em's centre, coordinates rounded to integers.  So no two glyphs
share an outline (nothing a compiler or subroutinizer could share beyond what real
fonts share), and the strokes cost about what the real characters' do.  Glyphs are
named ``u`` + the code point, unicodes from U+F0000 (Plane 15 private use), advance
1024 as the source.

The UFO is written as a stream: each source ``.glif`` is read, its points mapped
and written out, then dropped, so building 30,000 glyphs holds one glyph at a time
(the source's contents and the new glyph names are the only lists).  It is written
into the bench cache beside ``hanzi-all`` (built first when missing) and reused.
"""

import argparse
import math
import plistlib
import re
import shutil
import sys

import numpy as np

__all__ = ["variants_ufo", "variant_map", "PLANE15", "MAX_GLYPHS"]

PLANE15 = 0xF0000           # the first code point of Plane 15 (private use)
MAX_GLYPHS = 65535          # a font's glyph count is a 16-bit number
CENTRE = (512.0, 388.0)     # the hanzi em's centre: x 0-1024, y -124-900

_POINT = re.compile(rb'<point\s+x="([-+0-9.eE]+)"\s+y="([-+0-9.eE]+)"\s+type="(\w+)"\s*/>')

_GLIF_HEAD = ("<?xml version='1.0' encoding='UTF-8'?>\n"
              '<glyph name="%s" format="2">\n  <advance width="%s"/>\n'
              '  <unicode hex="%X"/>\n  <outline>\n')
_GLIF_TAIL = "  </outline>\n</glyph>\n"


def variant_map(k, m, seed=0):
    """The 2x3 affine map ``[[a, b, tx], [c, d, ty]]`` of glyph ``k`` (source glyph
    ``k mod m``): the identity for ``k < m``, else the glyph's own map (module
    docstring) about :data:`CENTRE`."""
    if k < m:
        return np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    rng = np.random.default_rng([seed, k])
    mirror = -1.0 if rng.random() < 0.5 else 1.0
    angle = math.radians(rng.uniform(-6.0, 6.0))
    slant = rng.uniform(-0.25, 0.25)
    sx, sy = rng.uniform(0.85, 1.0, 2)
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    lin = rot @ np.array([[1.0, slant], [0.0, 1.0]]) @ np.diag([mirror * sx, sy])
    c = np.array(CENTRE)
    return np.column_stack([lin, c - lin @ c])


def _contours(glif):
    """The open polylines of a skeleton ``.glif`` (bytes): a list of (n, 2) arrays.
    Every contour of the hanzi skeletons is a ``move`` and ``line`` points."""
    out = []
    for block in glif.split(b"<contour>")[1:]:
        pts = _POINT.findall(block.split(b"</contour>")[0])
        if any(t not in (b"move", b"line") for _, _, t in pts):
            raise ValueError("bench.skeleton_variants: a skeleton point that is not "
                             "move/line")
        out.append(np.array([(float(x), float(y)) for x, y, _ in pts]))
    return out


def _glif(name, code, advance, contours, affine):
    parts = [_GLIF_HEAD % (name, advance, code)]
    for pts in contours:
        q = np.rint(pts @ affine[:, :2].T + affine[:, 2]).astype(int)
        parts.append("    <contour>\n")
        parts += ['      <point x="%d" y="%d" type="%s"/>\n' % (x, y, "line" if j else "move")
                  for j, (x, y) in enumerate(q.tolist())]
        parts.append("    </contour>\n")
    parts.append(_GLIF_TAIL)
    return "".join(parts)


def _source_glyphs(src):
    """[(name, .glif path)] of the source UFO in its glyph order."""
    contents = plistlib.loads((src / "glyphs" / "contents.plist").read_bytes())
    lib = src / "lib.plist"
    order = (plistlib.loads(lib.read_bytes()).get("public.glyphOrder") if lib.exists()
             else None) or sorted(contents)
    return [(n, src / "glyphs" / contents[n]) for n in order if n in contents]


def _write_plist(path, value):
    path.write_bytes(plistlib.dumps(value))


def build(path, n, seed, src):
    """Write ``hanzi-variants-n`` at ``path`` from the skeleton UFO ``src``."""
    if not 1 <= n <= MAX_GLYPHS:
        raise SystemExit("bench.skeleton_variants: N must be 1-%d, not %d" % (MAX_GLYPHS, n))
    sources = _source_glyphs(src)
    tmp = path.with_name(path.name + ".part")
    shutil.rmtree(tmp, ignore_errors=True)
    (tmp / "glyphs").mkdir(parents=True)
    names, contents = [], {}
    advance = re.compile(rb'<advance\s+width="([-+0-9.eE]+)"')
    for k in range(n):
        _, glif_path = sources[k % len(sources)]
        glif = glif_path.read_bytes()
        width = advance.search(glif)
        name = "u%05X" % (PLANE15 + k)
        file_name = "u%05X.glif" % (PLANE15 + k)
        text = _glif(name, PLANE15 + k, width.group(1).decode() if width else "1024",
                     _contours(glif), variant_map(k, len(sources), seed))
        (tmp / "glyphs" / file_name).write_text(text)
        names.append(name)
        contents[name] = file_name
    _write_plist(tmp / "glyphs" / "contents.plist", contents)
    info = plistlib.loads((src / "fontinfo.plist").read_bytes())
    info["familyName"] = "Hanzi Variants %d" % n
    _write_plist(tmp / "fontinfo.plist", info)
    _write_plist(tmp / "lib.plist", {"public.glyphOrder": names})
    _write_plist(tmp / "layercontents.plist", [["public.default", "glyphs"]])
    _write_plist(tmp / "metainfo.plist", {"creator": "org.morph.bench.skeleton_variants",
                                         "formatVersion": 3})
    shutil.rmtree(path, ignore_errors=True)
    tmp.rename(path)
    return path


def variants_ufo(n, seed=0, cache=None):
    """The path of the ``hanzi-variants-n`` skeleton UFO (seed 0; another seed gets
    its own name), built into the bench cache when missing."""
    from bench.skeletons import cache_dir, skeleton_ufo

    cache = cache_dir(cache)
    path = cache / ("hanzi-variants-%d%s.ufo" % (n, "-s%d" % seed if seed else ""))
    if (path / "metainfo.plist").exists():
        return path
    return build(path, n, seed, skeleton_ufo("hanzi-all", cache))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", type=int, nargs="+")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cache")
    opt = ap.parse_args(argv)
    for n in opt.n:
        print(variants_ufo(n, opt.seed, opt.cache))
    return 0


if __name__ == "__main__":
    sys.exit(main())
