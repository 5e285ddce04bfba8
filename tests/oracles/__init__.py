"""Independent computations that morph's results are checked against (the oracles).

The test suite and the acceptance sweeps and benchmarks of bench/ use them; bench/
imports this package, nothing under tests/ imports bench/.

- :mod:`tests.oracles.reference`: exact convolution points, polygon Minkowski sums,
  shapely regions, Hausdorff distances, winding numbers;
- :mod:`tests.oracles.stroke_reference`: a Clipper stroker for skeleton paths;
- :mod:`tests.oracles.membership`: the exact membership predicate
  x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ and the straddle and membership checks built on it;
- :mod:`tests.oracles.sweep`: the acceptance sweeps' cases and their full check
  (nib and glyph-pair oracles, :func:`~tests.oracles.sweep.verify`);
- :mod:`tests.oracles.icons`: the icon cases' checks against polygon references;
- :mod:`tests.oracles.varfont`: variable-font checks (the nib's ellipse
  metric, Clipper strokes of flattened skeletons, boundary distances);
- :mod:`tests.oracles.overlaps`: overlaps between the contours of a written glyph
  (doubly covered faces, their area and width; pathops' exact excess area);
- :mod:`tests.oracles.measure`: a certified upper bound of a result's distance to the
  exact sum (for comparing peers at equal measured error).

Most need packages of the test extra (shapely, scipy): :func:`need` imports one, and
under pytest a missing one skips the tests that use the oracle, with the reason.
"""

import importlib
import sys


def need(module, purpose):
    """Import ``module`` for ``purpose``; when it is missing, skip the calling test module
    under pytest (naming the module and the test extra), else raise ImportError."""
    try:
        return importlib.import_module(module)
    except ImportError:
        if "pytest" in sys.modules:
            import pytest

            pytest.skip("%s is not installed (%s; pip install -e '.[test]')"
                        % (module, purpose), allow_module_level=True)
        raise
