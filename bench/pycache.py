"""The environment of a timed subprocess: bytecode cached and a site as after a pip
install.

This machine's shells set PYTHONDONTWRITEBYTECODE and the editable install has no
.pyc files, so a fresh process compiles every module it imports again (~0.2 s CPU
for the ~60 modules of `morph stroke`), a cost users who installed with pip do not
pay.  :func:`cached_env` gives subprocesses a private bytecode folder
(PYTHONPYCACHEPREFIX); the first run of a command fills it (a warm-up, not timed)
and the runs after it load the cached bytecode.

This interpreter's site-packages also run .pth files at every start that a user's
environment does not have: the editable install's finder (which imports pathlib,
importlib.resources and zipfile) and the machine's own hooks, ~45 ms of CPU per
process against ~3 ms for a virtual environment's site.  :func:`installed_python`
gives the timed commands an interpreter as a user's virtual environment has it: a
venv whose only .pth file puts this interpreter's site-packages and the repository
on sys.path (a path line of a .pth file is appended to sys.path; the .pth files in
that folder are not run).
"""

import atexit
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_INSTALLED = []


def cached_env(prefix="bench-pycache-", **extra):
    """``os.environ`` with the repository on PYTHONPATH (unless one is set), bytecode
    written to and read from a new private folder, and ``extra`` set."""
    env = dict(os.environ, PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT),
               PYTHONPYCACHEPREFIX=tempfile.mkdtemp(prefix=prefix), **extra)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def installed_python():
    """The path of a Python whose site is a fresh virtual environment's, with this
    interpreter's packages and the repository importable (see the module docstring):
    made once per bench process, removed at its exit."""
    if not _INSTALLED:
        venv = Path(tempfile.mkdtemp(prefix="bench-venv-"))
        atexit.register(shutil.rmtree, venv, True)
        subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
        python = venv / "bin" / "python"
        purelib = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig."
                                  "get_paths()['purelib'])"], capture_output=True, text=True,
                                 check=True).stdout.strip()
        paths = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
        Path(purelib, "morph-bench.pth").write_text(
            "".join(p + "\n" for p in sorted(paths) + [str(ROOT)]))
        _INSTALLED.append(str(python))
    return _INSTALLED[0]


def site_pth(python):
    """The .pth files that ``python``'s site runs at its start."""
    out = subprocess.run([python, "-c", "import site, glob, os; print('\\n'.join(sorted("
                          "os.path.basename(p) for d in site.getsitepackages() for p in "
                          "glob.glob(os.path.join(d, '*.pth')))))"],
                         capture_output=True, text=True, check=True).stdout
    return out.split()
