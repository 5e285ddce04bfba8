"""The environment of a timed subprocess: bytecode cached, as after a pip install.

This machine's shells set PYTHONDONTWRITEBYTECODE and the editable install has no
.pyc files, so a fresh process compiles every module it imports again (~0.2 s CPU
for the ~60 modules of `morph stroke`), a cost users who installed with pip do not
pay.  :func:`cached_env` gives subprocesses a private bytecode folder
(PYTHONPYCACHEPREFIX); the first run of a command fills it (a warm-up, not timed)
and the runs after it load the cached bytecode.
"""

import os
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def cached_env(prefix="bench-pycache-", **extra):
    """``os.environ`` with the repository on PYTHONPATH (unless one is set), bytecode
    written to and read from a new private folder, and ``extra`` set."""
    env = dict(os.environ, PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT),
               PYTHONPYCACHEPREFIX=tempfile.mkdtemp(prefix=prefix), **extra)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env
