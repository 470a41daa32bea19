"""Batch recognition sharded over a Dask LocalCluster of two worker processes gives the single-machine results file
byte for byte, with each worker holding one engine."""

from __future__ import annotations

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
