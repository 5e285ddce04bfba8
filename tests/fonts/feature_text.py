"""The feature text of a light UFO both ways, for the tests of morph's ports of
ufo2ft's feature writers (kern, mark): morph's (:func:`written`) and ufo2ft's
(:func:`ufo2fts`)."""

import ufoLib2

from morph.fonts import tables_static as T
from morph.fonts.stream import SkeletonSource


def written(path):
    """(reason, the feature text morph's tree gives) of the light font at ``path``:
    the reason it goes to ufo2ft and None, or None and the text after every writer
    morph runs has written (the last must write something)."""
    light = SkeletonSource(path, light=True).shell_font()
    tree = T.parse_features(light) if light.features.text else None
    compiler = T._Compiler(light, {}, True)
    reason, writers = T.left_to_ufo2ft(light, ".otf", tree, compiler.order, compiler.cmap)
    if reason is not None:
        return reason, None
    done = [w.write() for w in writers]
    assert writers and done[-1]
    return None, writers[0].tree.asFea()


def ufo2fts(path):
    """The feature text ufo2ft's feature compiler builds the layout tables from."""
    import ufo2ft
    from ufo2ft.featureCompiler import FeatureCompiler

    got = {}

    class Recorded(FeatureCompiler):
        def setupFeatures(self):
            super().setupFeatures()
            got["text"] = self.features

    ufo2ft.compileOTF(ufoLib2.Font.open(path), featureCompilerClass=Recorded, optimizeCFF=0)
    return got["text"]
