"""``python -m morph``: the ``morph`` command (:func:`morph.cli.run`), for an
environment whose scripts folder is not on PATH."""

from .cli import run

run()
