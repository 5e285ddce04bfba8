"""The bench cache of peer figures (bench/peer_cache.py) misses when its input changes.

The comparison reports take the Clipper references and FontForge's results from the
cache when the same skeletons were measured before; a glyph edited by one point must
be measured again, and the others must not.  ``python -m bench.peer_cache --check``
checks that in a fresh cache (FontForge's part where it is installed); it runs as a
subprocess: the test suite does not import bench/.
"""

import os
import subprocess
import sys
from pathlib import Path


ROOT = Path(__file__).resolve().parents[1]


def test_bench_cache_misses_an_edited_glyph():
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    res = subprocess.run([sys.executable, "-m", "bench.peer_cache", "--check"], cwd=ROOT,
                         env=env, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    assert res.stdout.count("ok ") >= 5 and "FAIL" not in res.stdout, res.stdout
