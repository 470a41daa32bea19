"""The examples run: python_quickstart.py writes its figure, python_active_touch.py plans its touches."""

from __future__ import annotations

import os
import subprocess
import sys

from conftest import REPO


def test_quickstart_runs(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, str(REPO / "examples" / "python_quickstart.py"), "--out", str(tmp_path)],
                       capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    png = tmp_path / "quickstart.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    assert (tmp_path / "map.svam").is_file() and (tmp_path / "train.svad").is_file()
    last = r.stdout.strip().splitlines()[-1]
    assert last.startswith("final: brick"), r.stdout


def test_active_touch_example_runs(tmp_path):
    r = subprocess.run([sys.executable, str(REPO / "examples" / "python_active_touch.py"), "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.strip().splitlines()
    assert lines[-2].startswith("touches until one object holds 95%: "), r.stdout
    assert lines[-1].startswith("final: brick"), r.stdout
