"""The package as a wheel lays it out (the CMake install component "python" that `pip install .` packs): importable
from any directory, with its type stubs and the built-in scenes found inside the package."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import sva


def build_dir() -> Path:
    d = os.environ.get("SVA_TEST_BUILD_DIR")
    if not d:
        pytest.skip("SVA_TEST_BUILD_DIR is not set (ctest sets it): no build tree to install from")
    return Path(d)


def test_installed_package_is_complete_and_finds_its_assets(tmp_path):
    prefix = tmp_path / "site"
    r = subprocess.run(["cmake", "--install", str(build_dir()), "--component", "python", "--prefix", str(prefix)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    pkg = prefix / "sva"
    for f in ("__init__.py", "batch.py", "distributed.py", "py.typed", "_sva_core.pyi", "assets/scenes/tiny.json"):
        assert (pkg / f).is_file(), f
    stub = (pkg / "_sva_core.pyi").read_text()
    compile(stub, "_sva_core.pyi", "exec")  # valid Python (no duplicate arguments either)
    assert "class Recognizer:" in stub and "def add_reading(self, reading: Reading)" in stub
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "SVA_ASSETS")}
    env["PYTHONPATH"] = str(prefix)
    code = ("import sva; print(sva.__file__); print(sva.assets_dir()); "
            "s = sva.load_scene('tiny'); print(s.meshes[0])")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    module_file, assets, mesh = r.stdout.split("\n")[:3]
    assert Path(module_file).parent == pkg
    assert Path(assets) == pkg / "assets"
    assert Path(mesh).is_relative_to(pkg / "assets" / "objects")


def test_the_build_tree_package_uses_the_source_assets():
    assert (sva.assets_dir() / "scenes" / "tiny.json").is_file()


def test_import_sva_loads_the_engine_alone_and_the_tools_on_first_use():
    """`import sva` (all a robot's program needs) maps no cairo and no tools' module; sva.evaluate loads them."""
    code = ("import sys, sva\n"
            "def cairo(): return any('libcairo' in line for line in open('/proc/self/maps'))\n"
            "print(cairo(), 'sva._sva_eval' in sys.modules)\n"
            "sva.evaluate\n"
            "print(cairo(), 'sva._sva_eval' in sys.modules, 'evaluate' in dir(sva))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=os.environ)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split("\n")[:2] == ["False False", "True True True"]
