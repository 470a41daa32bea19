"""Batch recognition sharded over a Dask LocalCluster of two worker processes gives the single-machine results file
byte for byte, with each worker holding one engine."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import sva
import sva.distributed as sd

distributed = pytest.importorskip("distributed")  # installed by scripts/setup.sh; the import must work


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_sharded_results_equal_the_single_machine_file(tiny, client, tmp_path):
    out = tmp_path / "results.jsonl"
    lines = sd.recognize_batch(tiny.map, tiny.sessions, out, client=client, backend="cpu", threads=1)
    assert out.read_bytes() == tiny.results.read_bytes()
    assert len(lines) == 6
    # 6 sessions on 2 workers: shards of one session, spread over both workers, one engine each
    assert sd.default_sessions_per_shard(6, 2, 64) == 1
    engines = client.run(lambda: len(sd._engines))
    assert sorted(engines.values()) == [1, 1]


def test_sharded_light_estimates_equal_the_single_machine_ones(tiny, client):
    lines = sd.recognize_batch(tiny.map, tiny.sessions, client=client, depth="light", backend="cpu", threads=1)
    assert lines == sva.recognize_batch(str(tiny.map), tiny.sessions, depth="light", backend="cpu")
    assert lines != tiny.results.read_text().splitlines()


def test_shard_sizes_do_not_change_the_results(tiny, client, tmp_path):
    for per_shard in (4, 100):
        out = tmp_path / f"r{per_shard}.jsonl"
        sd.recognize_batch(str(tiny.map), tiny.sessions, out, client=client, sessions_per_shard=per_shard,
                           sessions_per_submission=3, backend="cpu", threads=1)
        assert out.read_bytes() == tiny.results.read_bytes()


def test_the_earliest_bad_line_is_reported_and_nothing_written(tiny, client, tmp_path):
    lines = tiny.sessions.read_text().splitlines()
    lines[4] = lines[4].replace('"pressure":[', '"pressure":[1,', 1)
    lines[1] = lines[1].replace('"normal":[', '"normal":[null,', 1)
    bad = tmp_path / "bad.jsonl"
    bad.write_text("\n".join(lines) + "\n")
    out = tmp_path / "out.jsonl"
    with pytest.raises(sva.Error, match=r"bad\.jsonl:2: readings\[0\]\.normal"):
        sd.recognize_batch(tiny.map, bad, out, client=client, backend="cpu", threads=1)
    assert not out.exists()


def test_command_line_on_a_local_cluster(tiny, tmp_path, capfd):
    out = tmp_path / "cli.jsonl"
    rc = sd.main(["--local", "2", "--map", str(tiny.map), "--batch", str(tiny.sessions), "--out", str(out),
                  "--backend", "cpu", "--threads", "1"])
    assert rc == 0
    assert out.read_bytes() == tiny.results.read_bytes()
    assert "recognised 6 sessions on 2 workers" in capfd.readouterr().err


# The command line as docs/python.md shows it: `python -m sva.distributed`, in a process of its own (run as
# `__main__`, where pickling the worker function by value once failed on the module's lock).
def run_cli(*args: str, timeout: float = 240) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "sva.distributed", *args], capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))


def test_python_m_sva_distributed_local(tiny, tmp_path):
    out = tmp_path / "local.jsonl"
    r = run_cli("--local", "2", "--map", str(tiny.map), "--batch", str(tiny.sessions), "--out", str(out),
                "--backend", "cpu", "--threads", "1")
    assert r.returncode == 0, r.stderr
    assert out.read_bytes() == tiny.results.read_bytes()
    assert "recognised 6 sessions on 2 workers" in r.stderr


def start(*module_and_args: str, log: Path) -> subprocess.Popen:
    """A Dask command line of ours in its own process group (so that teardown ends its children too)."""
    return subprocess.Popen([sys.executable, "-m", *module_and_args], stdout=log.open("w"), stderr=subprocess.STDOUT,
                            start_new_session=True, env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))


def stop(p: subprocess.Popen) -> None:
    if p.poll() is None:
        os.killpg(p.pid, signal.SIGTERM)
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()


def scheduler_address(info: Path, scheduler: subprocess.Popen, log: Path, timeout: float = 60) -> str:
    """The address in the scheduler's file, once it is whole: the scheduler creates the file before it writes it, so
    a read in between finds it empty (a CI run failed so, with JSONDecodeError)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and scheduler.poll() is None:
        try:
            return json.loads(info.read_text())["address"]
        except (FileNotFoundError, json.JSONDecodeError, KeyError):
            time.sleep(0.2)
    pytest.fail(f"{info}: no scheduler address within {timeout} s\n{log.read_text()}")


def test_python_m_sva_distributed_scheduler(tiny, tmp_path):
    """`dask scheduler` and `dask worker` as a lab would start them, on the loopback address only."""
    info = tmp_path / "scheduler.json"
    procs = [start("distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                   "--scheduler-file", str(info), log=tmp_path / "scheduler.log")]
    try:
        address = scheduler_address(info, procs[0], tmp_path / "scheduler.log")
        assert address.startswith("tcp://127.0.0.1:"), address
        procs.append(start("distributed.cli.dask_worker", "--scheduler-file", str(info), "--host", "127.0.0.1",
                           "--nworkers", "1", "--nthreads", "1", "--no-dashboard", log=tmp_path / "worker.log"))
        out = tmp_path / "scheduler.jsonl"
        r = run_cli("--scheduler", address, "--map", str(tiny.map), "--batch", str(tiny.sessions), "--out", str(out),
                    "--backend", "cpu", "--threads", "1")
        assert r.returncode == 0, r.stderr + (tmp_path / "worker.log").read_text()
        assert out.read_bytes() == tiny.results.read_bytes()
    finally:
        for p in reversed(procs):
            stop(p)
