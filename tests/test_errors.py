"""morph.errors: one base class; each error keeps the data it is about."""

import numpy as np
import pytest

from morph import errors


def test_errors_keep_their_data():
    piece = np.zeros((3, 3))
    loops = [[piece]]
    cases = [
        (errors.ParseError("bad", "f.svg"), {"source": "f.svg"}),
        (errors.DegenerateCurveError("flat", piece), {"piece": piece}),
        (errors.ToleranceNotMetError("far", piece, 0.5), {"piece": piece, "achieved": 0.5}),
        (errors.TopologyError("open", loops, (1.0, 2.0)), {"loops": loops, "point": (1.0, 2.0)}),
        (errors.NibError("concave", loops), {"nib": loops}),
        (errors.LimitError("too fine", 1e-3), {"suggestion": 1e-3}),
    ]
    for exc, data in cases:
        assert isinstance(exc, errors.MorphError) and str(exc)
        for name, value in data.items():
            assert getattr(exc, name) is value
    # bad arguments are ValueErrors too; the data is optional for the raiser
    assert isinstance(errors.NibError("x"), ValueError)
    assert isinstance(errors.LimitError("x"), ValueError)
    assert errors.TopologyError("open").loops is None


def test_one_line():
    assert errors.one_line(ValueError("a\n  b\tc ")) == "a b c"
    assert errors.one_line(KeyError()) == "KeyError"
    with pytest.raises(errors.MorphError):
        raise errors.TopologyError("loops do not close")
