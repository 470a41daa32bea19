"""sva.ros: ROS 2 messages of a session and the MCAP bag written from them, read back and checked against the
estimates `sva recognize` wrote for the same sessions (docs/ros.md)."""

import math
import os
import stat

import numpy as np
import pytest

import sva
import sva.ros
from conftest import reading_of


def quaternion_xyzw(R) -> np.ndarray:
    """The unit quaternion of a rotation matrix, w >= 0 (as sva.to_ros gives it)."""
    R = np.asarray(R, dtype=np.float64)
    w = math.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return np.array([x, y, z, w])


@pytest.fixture(scope="module")
def bag(tiny, tiny_map, tmp_path_factory):
    out = tmp_path_factory.mktemp("ros") / "session2.mcap"
    sessions = sva.read_sessions(tiny.sessions, tiny_map)
    rec = sva.Recognizer(tiny_map, backend="cpu")
    meshes = sva.ros.scene_meshes(sva.load_scene(tiny_map.scene_name))
    summary = sva.ros.export_session(rec, sessions[2].readings, out, frame_id="base_link", start_ns=5_000_000_000,
                                     period_ns=250_000_000, top_k=3, detection_id=sessions[2].id, meshes=meshes)
    return out, summary, sessions[2]


def test_the_bag_decodes_and_holds_every_reading_on_its_stamp(bag):
    out, summary, session = bag
    msgs = sva.ros.read_bag(out)
    n = len(session.readings)
    assert summary["readings"] == n and summary["bytes"] == out.stat().st_size
    by_topic = {}
    for topic, t, m in msgs:
        by_topic.setdefault(topic, []).append((t, m))
        if topic in ("/sva/detections", "/sva/pose"):
            assert m.header.frame_id == "base_link"
        elif topic == "/tf":
            assert m.transforms[0].header.frame_id == "base_link"
            assert m.transforms[0].child_frame_id == sva.ros.OBJECT_FRAME
        else:
            assert {mk.header.frame_id for mk in m.markers} == {"base_link" if topic == "/sva/touches"
                                                                 else sva.ros.OBJECT_FRAME}
    for topic in ("/sva/detections", "/sva/touches"):
        stamps = [t for t, _ in by_topic[topic]]
        assert stamps == [5_000_000_000 + i * 250_000_000 for i in range(n)], topic
    # /tf moves the best object's frame with every pose; its mesh is sent when the best object changes.
    assert [t for t, _ in by_topic["/tf"]] == [t for t, _ in by_topic["/sva/pose"]]
    for (_, tf), (_, pose) in zip(by_topic["/tf"], by_topic["/sva/pose"]):
        tr, p = tf.transforms[0].transform, pose.pose.pose
        assert (tr.translation.x, tr.translation.y, tr.translation.z) == (p.position.x, p.position.y, p.position.z)
        assert (tr.rotation.w, tr.rotation.z) == (p.orientation.w, p.orientation.z)
    objects = by_topic["/sva/object"]
    assert 1 <= len(objects) <= len(by_topic["/sva/pose"]) + 1
    assert objects[-1][1].markers[0].frame_locked and len(objects[-1][1].markers[0].points) % 3 == 0
    for t, m in by_topic["/sva/detections"]:
        assert m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec == t
    # The touches so far at each reading: points, normals (two ends each) and a number each.
    for i, (_, m) in enumerate(by_topic["/sva/touches"]):
        assert len(m.markers) == 2 + i + 1
        assert len(m.markers[0].points) == i + 1 and len(m.markers[1].points) == 2 * (i + 1)
        assert [mk.text for mk in m.markers[2:]] == [str(k + 1) for k in range(i + 1)]
        p = np.asarray(session.readings[i].position) / 1000
        last = m.markers[0].points[i]
        assert (last.x, last.y, last.z) == pytest.approx(tuple(p), abs=1e-12)
    assert summary["messages"] == {t: len(v) for t, v in by_topic.items()}


def test_poses_and_covariances_are_the_recognizers(bag, tiny, tiny_map):
    out, _, session = bag
    msgs = sva.ros.read_bag(out, topics=["/sva/pose", "/sva/detections"])
    # The same readings through a recognizer here: every hypothesis, pose and covariance, reading by reading.
    rec = sva.Recognizer(tiny_map, backend="cpu")
    expected = []
    for r in session.readings:
        rec.add_reading(r)
        expected.append(rec.estimate(3))
    poses = [m for topic, _, m in msgs if topic == "/sva/pose"]
    dets = [m for topic, _, m in msgs if topic == "/sva/detections"]
    with_pose = [e for e in expected if e.hypotheses]
    assert len(poses) == len(with_pose) >= 1
    for m, e in zip(poses, with_pose):
        position, q, cov = e.hypotheses[0].to_ros()
        p = m.pose.pose
        assert [p.position.x, p.position.y, p.position.z] == list(position)
        assert [p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w] == list(q)
        assert list(m.pose.covariance) == list(np.asarray(cov).ravel())
    for m, e in zip(dets, expected):
        assert len(m.detections) == (1 if e.hypotheses else 0)
        if e.hypotheses:
            d = m.detections[0]
            assert d.id == session.id
            assert [r.hypothesis.class_id for r in d.results] == [h.object_name for h in e.hypotheses]
            assert [r.hypothesis.score for r in d.results] == [h.probability for h in e.hypotheses]
            assert d.bbox.size.x > 0.05  # the tiny scene's objects are 80 mm: the box is the mesh's, in metres
    # The last pose is the one `sva recognize` wrote for this session (the batch result, mm and a rotation matrix).
    want = tiny.result_lines()[2]
    assert want["id"] == session.id and want["readings"] == len(session.readings)
    last = poses[-1].pose.pose
    assert [last.position.x, last.position.y, last.position.z] == pytest.approx(
        [t / 1000 for t in want["pose"]["T"]], abs=1e-9)
    assert [last.orientation.x, last.orientation.y, last.orientation.z, last.orientation.w] == pytest.approx(
        list(quaternion_xyzw(want["pose"]["R"])), abs=1e-6)
    assert dets[-1].detections[0].results[0].hypothesis.class_id == want["object"]


def test_the_command_line_writes_the_same_bag_and_refuses_bad_input(tiny, tmp_path, capsys):
    from sva.ros.__main__ import main

    out = tmp_path / "cli.mcap"
    assert main(["export", "--map", str(tiny.map), "--sessions", str(tiny.sessions), "--out", str(out),
                 "--session", "2", "--frame", "base_link", "--start", "5", "--period", "0.25", "--top", "3",
                 "--backend", "cpu"]) == 0
    assert "6 readings" in capsys.readouterr().out
    topics = [t for t, _, _ in sva.ros.read_bag(out)]
    assert topics.count("/sva/detections") == 6 and topics.count("/tf") == topics.count("/sva/pose") >= 1
    assert 1 <= topics.count("/sva/object") < 6  # sent when the best object changes, not with every reading
    for args, message in [
        (["--session", "9"], "session 9 out of range (6 sessions)"),
        (["--id", "nope"], "no session with id 'nope'"),
        (["--period", "0"], "--period must be > 0"),
    ]:
        assert main(["export", "--map", str(tiny.map), "--sessions", str(tiny.sessions), "--out",
                     str(tmp_path / "bad.mcap"), *args]) == 1
        assert message in capsys.readouterr().err
        assert not (tmp_path / "bad.mcap").exists()
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"readings": [{"position": [0, 0], "normal": [0, 0, 1], "pressure": []}]}\n')
    assert main(["export", "--map", str(tiny.map), "--sessions", str(bad), "--out", str(tmp_path / "x.mcap")]) == 1
    assert "bad.jsonl:1" in capsys.readouterr().err
    with pytest.raises(sva.Error, match="does not exist"):
        sva.ros.export_session(sva.Recognizer(sva.Map.load(tiny.map), backend="cpu"), [], tmp_path / "no" / "x.mcap")


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600)])
def test_the_bag_takes_the_users_umask(tiny, tmp_path, umask, mode):
    """A bag is meant to be shared: its mode is what the user's umask gives any new file (the engine's files too),
    not the 0600 of the temporary file it is written to."""
    from sva.ros.__main__ import main

    out = tmp_path / "shared.mcap"
    old = os.umask(umask)
    try:
        assert main(["export", "--map", str(tiny.map), "--sessions", str(tiny.sessions), "--out", str(out),
                     "--session", "0", "--backend", "cpu", "--mesh", "off"]) == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE(out.stat().st_mode) == mode
    assert [p.name for p in tmp_path.iterdir()] == ["shared.mcap"]


def test_converters_need_no_bag(tiny, tiny_map):
    """The message dicts alone, for a live node: before any reading no detection and no pose."""
    rec = sva.Recognizer(tiny_map, backend="cpu")
    est = rec.estimate(3)
    assert sva.ros.detection_array(est, 0, "world")["detections"] == []
    assert sva.ros.best_pose(est, 0, "world") is None
    first = reading_of(tiny.session_lines()[0]["readings"][0])
    msgs = list(sva.ros.session_messages(rec, [first], frame_id="world"))
    assert [t for t, _, _ in msgs] == ["/sva/detections", "/sva/touches"]
    with pytest.raises(ValueError, match="negative"):
        sva.ros.time_msg(-1)


def test_a_light_node_publishes_the_light_estimates(tiny, tiny_map):
    """depth="light": every /sva/pose is the light estimate's, never the fine pose; a bad depth names itself."""
    readings = [reading_of(r) for r in tiny.session_lines()[0]["readings"]]
    rec, ref = sva.Recognizer(tiny_map, backend="cpu"), sva.Recognizer(tiny_map, backend="cpu")
    poses = [m for t, _, m in sva.ros.session_messages(rec, readings, depth="light") if t == "/sva/pose"]
    want = []
    for r in readings:
        ref.add_reading(r)
        est = ref.estimate(5, depth="light")
        assert not est.pose_refined
        if est.ready and est.hypotheses:
            want.append(sva.ros.pose_with_covariance(est.hypotheses[0]))
    assert [p["pose"] for p in poses] == want and len(want) >= 4
    with pytest.raises(sva.Error, match="depth"):
        list(sva.ros.session_messages(sva.Recognizer(tiny_map, backend="cpu"), readings[:1], depth="fine"))


def test_a_replayed_recording_becomes_a_bag_on_its_recorded_stamps(tiny, tmp_path):
    """A sensor recording (here a simulated one, `sva export --recording`) replayed through the live pipeline into
    a sessions file (`sva replay --write-session`), then into a bag on the readings' recorded times."""
    from conftest import run_sva
    from sva.ros.__main__ import main

    rec, sessions, out = tmp_path / "r.svar", tmp_path / "r.jsonl", tmp_path / "r.mcap"
    run_sva("export", "--data", str(tiny.test), "--recording", str(rec), "--touch-rate", "10", "--frame-rate", "100")
    run_sva("replay", str(rec), "--speed", "0", "--write-session", str(sessions))
    session = sva.read_sessions(sessions, sva.Map.load(tiny.map))[0]
    stamps = session.truth["stamps_s"]
    assert len(stamps) == len(session.readings) >= 3 and session.truth["recording"] == str(rec)
    assert main(["export", "--map", str(tiny.map), "--sessions", str(sessions), "--out", str(out), "--mesh", "off",
                 "--backend", "cpu"]) == 0
    got = [t for _, t, _ in sva.ros.read_bag(out, topics=["/sva/touches"])]
    assert got == [round(s * 1e9) for s in stamps]
    assert main(["export", "--map", str(tiny.map), "--sessions", str(tiny.sessions), "--out", str(out),
                 "--stamps", "recorded"]) == 1  # trials have no recorded times


def test_an_evaluation_trial_is_the_trial_sva_writes(tiny, tiny_map, tmp_path):
    """sva.trial_session makes trial K as sva eval and sva recognize --write-sessions do (the same generator)."""
    from sva.ros.__main__ import main

    written = sva.read_sessions(tiny.sessions, tiny_map)[1]  # --trials 6 --max-readings 6 --seed 5
    made = sva.trial_session(tiny.test, tiny_map, 1, seed=5, max_readings=6)
    assert made.id == written.id == "trial-1"
    assert made.truth["object"] == written.truth["object"]
    assert np.allclose(made.truth["T"], written.truth["T"], atol=1e-9)
    assert len(made.readings) == len(written.readings) == 6
    for a, b in zip(made.readings, written.readings):  # the file holds them as printed JSON numbers
        assert np.allclose(a.position, b.position, atol=1e-9)
        assert np.allclose(np.ravel(a.pressure), np.ravel(b.pressure))
    out = tmp_path / "trial.mcap"
    assert main(["export", "--map", str(tiny.map), "--data", str(tiny.test), "--trial", "1", "--seed", "5",
                 "--max-readings", "6", "--out", str(out), "--mesh", "off", "--backend", "cpu"]) == 0
    msgs = sva.ros.read_bag(out)
    assert [t for t, _, _ in msgs].count("/sva/detections") == 6
    # Against the evaluation of the same trials: at every reading with a pose, the bag's pose and the top object's
    # score are what `sva eval --csv` wrote (mm and rotation vector there; metres and a quaternion here).
    import csv

    from conftest import run_sva

    run_sva("eval", "--map", str(tiny.map), "--data", str(tiny.test), "--trials", "2", "--max-readings", "6",
            "--seed", "5", "--backend", "cpu", "--csv", str(tmp_path / "e.csv"))
    rows = [r for r in csv.DictReader(open(tmp_path / "e.csv")) if r["trial"] == "1"]
    poses = {t: m for topic, t, m in msgs if topic == "/sva/pose"}
    stamps = sorted({t for topic, t, _ in msgs if topic == "/sva/detections"})
    checked = 0
    for row, t in zip(rows, stamps):
        assert (row["pose_valid"] == "1") == (t in poses), row
        if t not in poses:
            continue
        p = poses[t].pose.pose
        assert [p.position.x, p.position.y, p.position.z] == pytest.approx(
            [float(row[k]) / 1000 for k in ("est_tx", "est_ty", "est_tz")], abs=1e-8)
        r = np.array([float(row[k]) for k in ("est_rx", "est_ry", "est_rz")])
        angle = np.linalg.norm(r)
        want = np.concatenate([np.sin(angle / 2) * r / angle, [np.cos(angle / 2)]]) if angle > 0 else [0, 0, 0, 1]
        got = np.array([p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w])
        assert min(np.abs(got - want).max(), np.abs(got + want).max()) < 1e-6, (got, want)
        checked += 1
    assert checked >= 1
    with pytest.raises(sva.Error, match="must be"):
        sva.trial_session(tiny.test, tiny_map, -1)
