"""docs/commands.md is the commands' ``--help`` as they are (docs/make_commands.py), and
the README's example commands name commands and options that exist."""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_command_reference_is_the_help():
    """In a fresh process: the help as a user sees it, whatever other tests patched."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    res = subprocess.run([sys.executable, str(ROOT / "docs" / "make_commands.py"), "--check"],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stdout + res.stderr


def test_readme_commands_parse():
    """Every `morph ...` example of the README names a command and only options it has."""
    from morph.cli import main

    examples = _readme_examples()
    assert len(examples) >= 8, examples
    for example in examples:
        words = shlex.split(example)
        cmd = main.get_command(None, words[1])
        assert cmd is not None, example
        known = {o for p in cmd.params for o in getattr(p, "opts", [])}
        for w in words[2:]:
            if w.startswith("-") and not re.fullmatch(r"-\d.*", w):
                assert w in known, "%s: %s is not an option of morph %s" % (example, w, words[1])


def _readme_examples():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    examples = set(re.findall(r"`(morph [a-z]+ [^`]*)`", readme))
    for block in re.findall(r"```sh\n(.*?)```", readme, re.S):
        examples |= set(re.findall(r"\b(morph [a-z]+ .*)$", block, re.M))
    return sorted(examples)


@pytest.mark.slow
@pytest.mark.parametrize("example", _readme_examples())
def test_readme_commands_run(example, tmp_path, monkeypatch):
    """Each `morph ...` example of the README runs as written (inputs named relative to
    the repository), exit 0, and writes what it names."""
    from click.testing import CliRunner

    from morph.cli import main

    words = shlex.split(example)[1:]
    args = [str(ROOT / w) if (ROOT / w).exists() and "/" in w else w for w in words]
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, (example, res.output)
    if "-o" in words:
        assert (tmp_path / words[words.index("-o") + 1]).exists(), example
