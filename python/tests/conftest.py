"""Fixtures of the Python suite: the tiny built-in scene simulated, trained and recognised once per session by the
C++ command line (`sva`), so that every test compares the Python path with the C++ one on the same files."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

import sva

REPO = Path(__file__).resolve().parents[2]


def sva_bin() -> Path:
    """The C++ command line: SVA_TEST_SVA_BIN (set by ctest), else the default preset's build."""
    p = Path(os.environ.get("SVA_TEST_SVA_BIN", REPO / "build" / "sva"))
    if not p.is_file():
        pytest.fail(f"{p}: the sva command line is missing (build it, or set SVA_TEST_SVA_BIN)")
    return p


def run_sva(*args: str) -> str:
    # The package's assets for the command line too: the scene's mesh paths are written into the datasets and maps,
    # so both sides must read the same files (an installed package carries its own copy).
    env = dict(os.environ, SVA_ASSETS=str(sva.assets_dir()))
    r = subprocess.run([str(sva_bin()), *args], capture_output=True, text=True, env=env)
    assert r.returncode == 0, f"sva {' '.join(args)} failed:\n{r.stderr}"
    return r.stdout


class Tiny:
    """Files of the tiny scene made by the C++ command line."""

    def __init__(self, d: Path):
        self.dir = d
        self.train = d / "train.svad"
        self.test = d / "test.svad"
        self.map = d / "map.svam"
        self.sessions = d / "sessions.jsonl"
        self.results = d / "results.jsonl"  # sva recognize --backend cpu --top 3
        self.eval_json = d / "eval.json"

    def session_lines(self) -> list[dict]:
        return [json.loads(line) for line in self.sessions.read_text().splitlines() if line.strip()]

    def result_lines(self) -> list[dict]:
        return [json.loads(line) for line in self.results.read_text().splitlines()]


# Small counts: the whole suite stays within a minute on 2 cores.
SIM_ARGS = ("--scene", "tiny", "--seed", "3", "--train", "12", "--test", "5")
EVAL = dict(trials=4, max_readings=5, seed=2)


@pytest.fixture(scope="session")
def tiny(tmp_path_factory) -> Tiny:
    t = Tiny(tmp_path_factory.mktemp("tiny"))
    run_sva("simulate", *SIM_ARGS, "--out", str(t.dir))
    run_sva("train", "--data", str(t.train), "--out", str(t.map))
    run_sva("recognize", "--write-sessions", str(t.sessions), "--map", str(t.map), "--data", str(t.test),
            "--trials", "6", "--max-readings", "6", "--seed", "5")
    run_sva("recognize", "--map", str(t.map), "--batch", str(t.sessions), "--out", str(t.results), "--backend", "cpu",
            "--top", "3")
    run_sva("eval", "--map", str(t.map), "--data", str(t.test), "--trials", str(EVAL["trials"]), "--max-readings",
            str(EVAL["max_readings"]), "--seed", str(EVAL["seed"]), "--backend", "cpu", "--json", str(t.eval_json))
    return t


@pytest.fixture(scope="session")
def tiny_map(tiny) -> sva.Map:
    return sva.Map.load(tiny.map)


def reading_of(r: dict) -> sva.Reading:
    """A sessions-file reading (docs/batch-format.md) as an sva.Reading built from NumPy arrays, with the normal
    normalised as the engine's reader does (glm::normalize: v * (1 / sqrt(v . v)), in this order)."""
    import math

    import numpy as np

    x, y, z = (float(v) for v in r["normal"])
    k = 1.0 / math.sqrt(x * x + y * y + z * z)
    return sva.Reading(np.asarray(r["pressure"], dtype=np.float32).reshape(6, 6), np.array(r["position"]),
                       np.array([x * k, y * k, z * k]), r.get("x_axis", (1.0, 0.0, 0.0)))
