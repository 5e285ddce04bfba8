"""The README's library examples run as written (they are the documentation)."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_examples_run(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert blocks, "README has no python examples"
    monkeypatch.chdir(tmp_path)  # the examples write images
    scope = {}
    exec(compile("\n".join(blocks), str(README), "exec"), scope)
    assert scope["s"] and scope["stroke"] and len(scope["frames"]) == 10
    assert (tmp_path / "om.png").stat().st_size > 0
