"""The interpreter the comparison reports time morph's commands with (bench/pycache.py).

``installed_python`` stands for a user's virtual environment: its site runs only the
bench's own .pth file (not this machine's editable finder or other hooks), and
morph, numpy and fontTools import from where this interpreter has them.  It runs as a
subprocess: the test suite does not import bench/.
"""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHECK = """
import subprocess
from bench.pycache import installed_python, site_pth
python = installed_python()
print(site_pth(python))
print(subprocess.run([python, "-c", "import sys, morph, numpy, fontTools; "
                      "print(morph.__file__); print(sys.prefix != sys.base_prefix)"],
                     capture_output=True, text=True, check=True).stdout)
"""


def test_installed_python_runs_only_its_own_site():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", CHECK], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    pth, morph_file, in_venv = res.stdout.split("\n")[:3]
    assert pth == "['morph-bench.pth']", pth
    assert Path(morph_file).resolve() == (ROOT / "morph" / "__init__.py").resolve()
    assert in_venv == "True"
