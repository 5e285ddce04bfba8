"""Golden-image comparison for render tests (and ``gray``, an image as gray levels).

``assert_matches_golden(image, name)`` compares an image with ``tests/golden/<name>.png``:

- a pixel *differs* when any channel differs by more than ``pixel_tol`` (0-255);
- the test fails when more than ``max_fraction`` of the pixels differ, or the sizes
  differ.  Defaults: pixel_tol = 16, max_fraction = 0.002 (0.2 %), which absorbs
  rounding and anti-aliasing changes but not a moved edge or a filled hole.

On failure the expected, actual and diff images (differing pixels red on a faded
expected image) go to ``tests/_failures/<name>-{expected,actual,diff}.png``.

Goldens are (re)written only when the environment variable ``MORPH_UPDATE_GOLDEN=1``
is set; a missing golden otherwise fails the test, never silently passes.
"""

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

GOLDEN_DIR = Path(__file__).resolve().parent / "golden"
FAILURE_DIR = Path(__file__).resolve().parent / "_failures"
PIXEL_TOL = 16
MAX_FRACTION = 0.002


def compare_images(actual, expected, pixel_tol=PIXEL_TOL):
    """(fraction of differing pixels, max channel difference, boolean diff mask)."""
    a = np.asarray(actual.convert("RGBA"), np.int16)
    e = np.asarray(expected.convert("RGBA"), np.int16)
    if a.shape != e.shape:
        return 1.0, 255, None
    delta = np.abs(a - e).max(axis=2)
    mask = delta > pixel_tol
    return float(mask.mean()), int(delta.max()), mask


def _write_failure(name, actual, expected, mask):
    FAILURE_DIR.mkdir(exist_ok=True)
    actual.save(FAILURE_DIR / ("%s-actual.png" % name))
    expected.save(FAILURE_DIR / ("%s-expected.png" % name))
    if mask is not None:
        base = np.asarray(expected.convert("RGB"), np.float32) * 0.3 + 178
        base[mask] = [255, 0, 0]
        Image.fromarray(base.astype(np.uint8), "RGB").save(FAILURE_DIR / ("%s-diff.png" % name))
    return FAILURE_DIR


def assert_matches_golden(image, name, pixel_tol=PIXEL_TOL, max_fraction=MAX_FRACTION):
    golden = GOLDEN_DIR / ("%s.png" % name)
    if os.environ.get("MORPH_UPDATE_GOLDEN") == "1":
        GOLDEN_DIR.mkdir(exist_ok=True)
        image.save(golden)
        return
    if not golden.exists():
        pytest.fail("golden image %s is missing; create it deliberately with "
                    "MORPH_UPDATE_GOLDEN=1 python -m pytest tests/render/test_png.py" % golden)
    expected = Image.open(golden)
    expected.load()
    fraction, worst, mask = compare_images(image, expected, pixel_tol)
    if fraction > max_fraction:
        where = _write_failure(name, image, expected, mask)
        size_note = "" if mask is not None else " (sizes %s vs %s)" % (image.size, expected.size)
        pytest.fail("%s differs from its golden: %.3f%% of pixels off by > %d (allowed %.3f%%), "
                    "max difference %d%s; see %s" % (name, 100 * fraction, pixel_tol,
                                                      100 * max_fraction, worst, size_note, where))


def gray(image):
    """The image as a float array of gray levels (0 black .. 255 white)."""
    return np.asarray(image.convert("L"), float)
