"""sva.simulate, sva.train and sva.evaluate give what `sva simulate`, `sva train` and `sva eval` give."""

from __future__ import annotations

import json

import numpy as np
import pytest

import sva
from conftest import EVAL, SIM_ARGS


def sim_kwargs() -> dict:
    a = dict(zip(SIM_ARGS[::2], SIM_ARGS[1::2]))
    return dict(train=int(a["--train"]), test=int(a["--test"]), seed=int(a["--seed"]))


def test_simulate_writes_the_cli_datasets(tiny, tmp_path):
    train, test = sva.simulate("tiny", out=tmp_path, threads=1, **sim_kwargs())
    assert (tmp_path / "train.svad").read_bytes() == tiny.train.read_bytes()
    assert (tmp_path / "test.svad").read_bytes() == tiny.test.read_bytes()
    assert len(train) == 2 * 12 and len(test) == 2 * 5
    assert train.split == "train" and test.scene.name == "tiny"
    # the in-memory datasets are the files' contents
    loaded = sva.Dataset.load(tiny.train)
    assert np.array_equal(loaded.pressures(), train.pressures())
    assert np.array_equal(loaded.positions(), train.positions())


def test_train_builds_the_cli_map(tiny, tmp_path):
    report = sva.TrainReport()
    m = sva.train(str(tiny.train), out=tmp_path / "map.svam", report=report)
    assert (tmp_path / "map.svam").read_bytes() == tiny.map.read_bytes()
    assert report.readings_used > 0 and report.readings_used <= 24
    assert m.objects == 2 and m.object_names == ["die", "brick"] and m.scene_name == "tiny"
    assert m.entries > 0 and m.bytes > 0
    # from a Dataset object too, with an option changed: another map
    other = sva.train(sva.Dataset.load(tiny.train), clusters=4)
    assert other.classes == 4
    # fewer readings paired: every reading kept as surface, fewer entries
    assert report.readings_paired == report.readings_used
    paired = sva.TrainReport()
    few = sva.train(str(tiny.train), pair_readings=4, report=paired, calibrate=False)
    assert paired.readings_paired == 8 and paired.readings_used == report.readings_used
    assert few.readings == m.readings and 0 < few.entries < m.entries
    # the fine pose's start: the scene's default, or the one asked for, kept in the saved map
    assert m.fine_pose_from == 6
    early = sva.train(str(tiny.train), fine_pose_from=4, calibrate=False, out=tmp_path / "early.svam")
    assert early.fine_pose_from == 4 and sva.Map.load(tmp_path / "early.svam").fine_pose_from == 4
    with pytest.raises(sva.Error, match="fine pose from 2 readings: expected 3 to 1000"):
        sva.train(str(tiny.train), fine_pose_from=2)
    # the objects' meshes: in the map by default (the verify stage's measurement model), left out on request
    assert m.surface_objects == m.objects and m.surface_bytes > 0
    bare = sva.train(str(tiny.train), calibrate=False, surfaces=False)
    assert bare.surface_objects == 0 and bare.surface_bytes == 0 and bare.bytes == early.bytes


def test_evaluate_gives_the_cli_summary(tiny, tiny_map, tmp_path):
    got = sva.evaluate(tiny_map, str(tiny.test), backend="cpu", threads=1, json=tmp_path / "e.json", **EVAL)
    want = json.loads(tiny.eval_json.read_text())

    def timeless(summary: dict) -> dict:  # update times vary run to run
        s = dict(summary)
        s["curve"] = [{k: v for k, v in p.items() if not k.startswith("update_ms")} for p in s["curve"]]
        return s

    assert timeless(got) == timeless(want)
    assert timeless(json.loads((tmp_path / "e.json").read_text())) == timeless(want)
    assert len(got["curve"]) == EVAL["max_readings"] and got["trials"] == EVAL["trials"]
    assert got["curve"][-1]["accuracy"] >= 0.5


def test_dataset_views(tiny):
    d = sva.Dataset.load(tiny.test)
    n = len(d)
    P = d.pressures()
    assert P.shape == (n, 6, 6) and P.dtype == np.float32
    assert d.positions().shape == (n, 3) and d.normals().shape == (n, 3)
    assert set(d.objects().tolist()) == {0, 1}
    assert d.converged().dtype == bool and d.converged().sum() == d.count_converged()
    s = d[-1]
    assert s.reading.pressure.shape == (6, 6) and np.array_equal(s.reading.pressure, P[-1])  # the sensor's shape
    assert np.array_equal(s.object_pose.R, np.eye(3))
    assert s.object == d.objects()[-1]
    assert sum(1 for _ in d) == n
    with pytest.raises(IndexError):
        d[n]


def test_zero_copy_views():
    r = sva.Reading(np.arange(36, dtype=np.float32), [1.0, 2.0, 3.0], [0.0, 0.0, 1.0])
    view = r.pressure
    view[0] = 99.0  # the view is the reading's image
    assert r.pressure[0] == 99.0
    assert np.shares_memory(view, r.pressure)
    r.pressure = np.full((6, 6), 2.0)  # assigned in place: the old view sees the new values
    assert view[5] == 2.0
    p = sva.RigidPose()
    R = p.R
    R[0, 1] = 5.0
    assert p.R[0, 1] == 5.0 and p.matrix()[0, 1] == 5.0
    p.T = [1, 2, 3]
    assert p.apply([0, 0, 0]).tolist() == [1.0, 2.0, 3.0]


def test_scenes_and_assets():
    assert (sva.assets_dir() / "scenes" / "tiny.json").is_file()
    s = sva.load_scene("tiny")
    assert s.object_names == ["die", "brick"] and s.sensor.elements == 36
    assert all(m.is_file() for m in s.meshes)
    with pytest.raises(sva.Error, match="no built-in scene"):
        sva.load_scene("nonesuch")
