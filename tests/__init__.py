"""morph's test suite (a package, so test files in subfolders may share base names and
``from tests.oracles.reference import ...`` works under plain ``pytest`` too).  See README.md."""

from pathlib import Path

DATA = Path(__file__).resolve().parent / "data"
#: the Relief SingleLine subset: a UFO of open skeleton contours (licence in its folder)
RELIEF_SUBSET = DATA / "relief" / "Relief-SingleLine-subset.ufo"
