"""Write docs/commands.md, the command reference, from the commands' own ``--help``.

    python docs/make_commands.py            # rewrite docs/commands.md
    python docs/make_commands.py --check    # exit 1 when docs/commands.md is stale

The help is rendered by click at a fixed width (88 columns), so the file does not
depend on the terminal; ``tests/test_docs.py`` fails when a command's help changed and
the file was not remade.
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "commands.md"
WIDTH = 88
# font commands first (what a type designer came for), then the shape commands
ORDER = ("stroke", "brush", "glyph", "svg", "sum", "offset", "cspace", "outline")


def help_text(command, name, parent=None):
    import click

    ctx = click.Context(command, info_name=name, parent=parent, terminal_width=WIDTH,
                        max_content_width=WIDTH, help_option_names=["-h", "--help"])
    return ctx, command.get_help(ctx)


def commands_md():
    """The text of docs/commands.md."""
    from morph.cli import main

    root, top = help_text(main, "morph")
    names = [n for n in ORDER if n in main.commands]
    names += sorted(set(main.commands) - set(names))
    out = ["# Command reference", "",
           "Made by `python docs/make_commands.py` from each command's `--help` (font "
           "commands first, then shape commands); `morph COMMAND --help` prints the same.",
           "", "```", top, "```", ""]
    for name in names:
        _, text = help_text(main.commands[name], name, root)
        out += ["## morph %s" % name, "", "```", text, "```", ""]
    return "\n".join(out).rstrip("\n") + "\n"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    text = commands_md()
    if "--check" in argv:
        current = OUT.read_text(encoding="utf-8") if OUT.exists() else ""
        if current != text:
            print("docs/commands.md is stale: run python docs/make_commands.py")
            return 1
        return 0
    OUT.write_text(text, encoding="utf-8")
    print("wrote", OUT.relative_to(ROOT))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main())
