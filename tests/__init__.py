"""morph's test suite (a package, so test files in subfolders may share base names and
``from tests.reference import ...`` works under plain ``pytest`` too).  See README.md."""
