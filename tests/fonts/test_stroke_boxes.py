"""The skeletons' control boxes of the component separation, all glyphs boxed at
once (morph.fonts.stroke._control_boxes), against each glyph's control points
gathered and reduced alone."""

from pathlib import Path

import numpy as np

from morph import piece as pc
from morph.fonts.stroke import _control_boxes
from morph.parse.ufo import decomposed_paths, load_ufo

RELIEF = Path(__file__).parents[1] / "data" / "relief" / "Relief-SingleLine-subset.ufo"


def test_control_boxes_match_each_glyph_alone():
    font = load_ufo(RELIEF, lazy=False)
    names = ["a", "S", "g", "eight", "i", "O"]
    sets = [decomposed_paths(font, n) for n in names]
    sets.insert(2, [])                       # a glyph without contours: None
    got = _control_boxes(sets)
    assert got[2] is None
    worst, moved = 0.0, 0
    for paths, box in zip(sets, got):
        if not paths:
            continue
        xy = np.concatenate([pc.cartesian(p) for pieces, _ in paths for p in pieces])
        want = np.concatenate([xy.min(axis=0), xy.max(axis=0)])
        worst = max(worst, float(np.abs(np.array(box) - want).max()))
        # the box of the first piece alone is not the glyph's: a box that dropped
        # the rest would fail
        first = pc.cartesian(paths[0][0][0])
        moved += not np.allclose(np.concatenate([first.min(axis=0), first.max(axis=0)]), want)
    assert worst == 0.0
    assert moved >= 4
