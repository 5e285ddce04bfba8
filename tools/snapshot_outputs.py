"""Hash the outputs a refactor must not change: gallery, frames, sums, fonts.

    python tools/snapshot_outputs.py OUTDIR [--skip gallery,fonts] > hashes.txt

Writes into OUTDIR (kept for inspection) and prints ``sha256  relative/path`` per
file, sorted.  Compare two runs with ``diff``.  Which code is measured is the one
``import morph`` finds: run with PYTHONPATH at the checkout to measure.

- gallery/: every figure of gallery/make_gallery.py (PNG and SVG) at 400 pixels;
- frames/: ``morph glyph T M --frames 10``;
- sums/: about 20 results as raw control points (float bytes, so any change in
  any bit shows) and a few as the SVG the CLI writes: glyph pairs, SVG shapes,
  offsets and insets, a stroke;
- fonts/: ``morph brush`` (TrueType and CFF) and ``morph stroke`` (OTF and TTF)
  on a few glyphs, with SOURCE_DATE_EPOCH fixed so the files are reproducible.
"""

import argparse
import hashlib
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

GLYPH_PAIRS = [("T", "M"), ("o", "period"), ("a", "g"), ("B", "x"), ("ampersand", "O"),
               ("e", "comma"), ("S", "l")]
RELIEF = "tests/data/relief/Relief-SingleLine-subset.ufo"


def code_root():
    import morph
    return Path(morph.__file__).resolve().parent.parent


def region_bytes(region):
    """Every control point of every piece, loop by loop, as bytes."""
    h = hashlib.sha256()
    for loop in region:
        h.update(b"loop")
        for p in loop:
            a = np.ascontiguousarray(np.asarray(p, dtype=float))
            h.update(str(a.shape).encode())
            h.update(a.tobytes())
    return h.hexdigest()


def sums(out):
    from morph import minkowski_sum, offset_region, inset_region, stroke_paths, svg_paths
    from morph.parse import glyph_region, svg_region
    from morph.fonts.brush import ellipse_nib

    root = code_root()
    out.mkdir(parents=True, exist_ok=True)
    lines = []
    for a, b in GLYPH_PAIRS:
        r = minkowski_sum(glyph_region(a).region, glyph_region(b).region, 0.1)
        lines.append("sum %s %s %s" % (a, b, region_bytes(r)))
    bird = svg_region(str(root / "morph/data/bird.svg"))
    fly = svg_region(str(root / "morph/data/butterfly.svg"))
    nib = ellipse_nib(80, 30, 30)
    for tol in (1e-3, 1e-5):
        lines.append("sum bird butterfly %g %s" % (tol, region_bytes(minkowski_sum(bird, fly, tol))))
    lines.append("sum bird nib %s" % region_bytes(minkowski_sum(bird, nib, 1e-4)))
    for name in ("e", "g"):
        g = glyph_region(name).region
        lines.append("sum %s nib %s" % (name, region_bytes(minkowski_sum(g, nib, 0.1))))
        for r in (20.0, 60.0):
            lines.append("offset %s %g %s" % (name, r, region_bytes(offset_region(g, r, 0.1))))
            lines.append("inset %s %g %s" % (name, r, region_bytes(inset_region(g, r, 0.1))))
    skel = svg_paths('<svg xmlns="http://www.w3.org/2000/svg"><path d="M0 0 C 40 80 120 80 160 0'
                     ' S 260 -60 300 20" stroke="black" fill="none"/></svg>')
    lines.append("stroke svg %s" % region_bytes(stroke_paths(skel, ellipse_nib(30, 8, 30), 1e-3)))
    (out / "sums.txt").write_text("\n".join(lines) + "\n")


def cli(args, env, out):
    """Run ``morph ARGS``; a failure other than bad input (exit 2) is recorded in
    OUT/cli-errors.txt (part of the snapshot: a fixed bug shows as a change)."""
    r = subprocess.run([sys.executable, "-m", "morph.cli"] + args, env=env,
                       capture_output=True, text=True)
    if r.returncode == 2:
        raise SystemExit("morph %s failed (%d):\n%s" % (" ".join(args), r.returncode, r.stderr))
    if r.returncode or "internal error" in r.stderr:
        with open(out / "cli-errors.txt", "a") as f:
            f.write("%s %s -> %d %s\n" % (args[0], Path(args[args.index("-o") + 1]).name,
                                           r.returncode,
                                        r.stderr.strip().replace(str(out), "OUT")))


def cli_outputs(out, env, skip):
    root = code_root()
    cli(["glyph", "T", "M", "--frames", "10", "-o", str(out / "frames")], env, out)
    s = out / "sums"
    s.mkdir(parents=True, exist_ok=True)
    cli(["sum", "T", "M", "-o", str(s / "tm.svg")], env, out)
    cli(["sum", "o", str(root / "morph/data/bird.svg"), "-o", str(s / "o-bird.svg")], env, out)
    cli(["offset", "g", "-r", "0.04", "-o", str(s / "g-offset.svg")], env, out)
    cli(["offset", "g", "-r", "-0.01", "-o", str(s / "g-inset.svg")], env, out)
    if "fonts" in skip:
        return
    f = out / "fonts"
    f.mkdir(parents=True, exist_ok=True)
    for suffix in ("ttf", "otf"):
        src = [] if suffix == "ttf" else [str(root / "morph/fonts/data/NotoSans-Regular.otf")]
        cli(["brush"] + src + ["-o", str(f / ("brush-%s.%s" % (suffix, suffix))),
                               "--glyphs", "a,g,o,T,M,e", "--jobs", "1"], env, out)
        cli(["stroke", str(root / RELIEF), "-o", str(f / ("stroke-%s.%s" % (suffix, suffix))),
             "--glyphs", "a,b,g,o,S", "--jobs", "1"], env, out)


def gallery(out):
    root = code_root()
    spec = importlib.util.spec_from_file_location("make_gallery", root / "gallery/make_gallery.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    from morph.render import write_svg

    out.mkdir(parents=True, exist_ok=True)
    for fig in mod.FIGURES:
        img, shapes, tol = mod.render(fig, 400)
        img.save(str(out / (fig.__name__ + ".png")))
        write_svg(str(out / (fig.__name__ + ".svg")), shapes, size=400, tol=tol)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--skip", default="", help="comma separated: gallery, fonts")
    args = ap.parse_args(argv)
    skip = set(filter(None, args.skip.split(",")))
    out = args.out.resolve()
    env = dict(os.environ, SOURCE_DATE_EPOCH="0", MORPH_JOBS="1")
    env.pop("MORPH_DEBUG", None)
    out.mkdir(parents=True, exist_ok=True)
    os.environ["SOURCE_DATE_EPOCH"] = "0"
    sums(out / "sums")
    cli_outputs(out, env, skip)
    if "gallery" not in skip:
        gallery(out / "gallery")
    for p in sorted(out.rglob("*")):
        if p.is_file():
            print("%s  %s" % (hashlib.sha256(p.read_bytes()).hexdigest(), p.relative_to(out)))
    sums_txt = (out / "sums" / "sums.txt").read_text()
    for line in sums_txt.splitlines():
        label, digest = line.rsplit(" ", 1)
        print("%s  sums.txt:%s" % (digest, label.replace(" ", "_")))


if __name__ == "__main__":
    main()
