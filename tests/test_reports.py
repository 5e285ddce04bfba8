"""The committed reports under bench/ still say what their scripts compute: ``python -m
bench.reports --check`` recomputes a few headline numbers of each report on small, fast
cases (the methods comparison's QAC counts, the copies' loops and areas, the arc's cubic
counts) and checks that docs/performance.md is what the reports make of it.

It runs as a subprocess: the test suite does not import bench/ (bench imports the
oracles of tests/, never the other way)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_reports_match_their_scripts():
    pytest.importorskip("kurbopy", reason="bench/export.py's check needs kurbopy")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    res = subprocess.run([sys.executable, "-m", "bench.reports", "--check"], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "skipped" not in res.stdout, res.stdout
    assert res.stdout.count("ok ") >= 10, res.stdout
