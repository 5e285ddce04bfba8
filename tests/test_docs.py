"""docs/commands.md is the commands' ``--help`` as they are (docs/make_commands.py), and
the README's example commands name commands and options that exist."""

import re
import runpy
import shlex
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_command_reference_is_the_help():
    make = runpy.run_path(str(ROOT / "docs" / "make_commands.py"))
    text = (ROOT / "docs" / "commands.md").read_text(encoding="utf-8")
    assert text == make["commands_md"](), "docs/commands.md is stale: python docs/make_commands.py"


def test_readme_commands_parse():
    """Every `morph ...` example of the README names a command and only options it has."""
    from morph.cli import main

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    examples = set(re.findall(r"`(morph [a-z]+ [^`]*)`", readme))
    for block in re.findall(r"```sh\n(.*?)```", readme, re.S):
        examples |= set(re.findall(r"\b(morph [a-z]+ .*)$", block, re.M))
    assert len(examples) >= 8, examples
    for example in examples:
        words = shlex.split(example)
        cmd = main.commands.get(words[1])
        assert cmd is not None, example
        known = {o for p in cmd.params for o in getattr(p, "opts", [])}
        for w in words[2:]:
            if w.startswith("-") and not re.fullmatch(r"-\d.*", w):
                assert w in known, "%s: %s is not an option of morph %s" % (example, w, words[1])
