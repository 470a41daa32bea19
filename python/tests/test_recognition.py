"""The Python path gives the C++ path's estimates: the Recognizer, the BatchRecognizer and batch recognition of a
sessions file against `sva recognize` on the same map and sessions."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

import sva
from conftest import reading_of, run_sva


def pose_of(j: dict) -> tuple[np.ndarray, np.ndarray]:
    return np.array(j["R"]), np.array(j["T"])


def assert_estimate_is(est: sva.Estimate, want: dict, names: list[str]) -> None:
    """An Estimate equals a line of the C++ results file (numbers as written: round-trip precision); `names` are
    the map's objects in id order."""
    assert est.readings == want["readings"]
    assert est.object_name == want["object"]
    assert est.pose_valid == want["pose_valid"]
    assert est.object_probability.tolist() == [want["object_probability"][n] for n in names]
    assert est.p_unknown == want["p_unknown"]
    if est.pose_valid:
        R, T = pose_of(want["pose"])
        assert np.array_equal(est.pose.R, R) and np.array_equal(est.pose.T, T)
    assert len(est.top) == len(want["top"])
    for h, w in zip(est.top, want["top"]):
        assert h.object_name == w["object"] and h.probability == w["probability"]
        R, T = pose_of(w)
        assert np.array_equal(h.pose.R, R) and np.array_equal(h.pose.T, T)


def test_recognizer_gives_the_cli_estimates(tiny, tiny_map):
    results = tiny.result_lines()
    sessions = tiny.session_lines()
    assert len(sessions) == len(results) == 6
    rec = sva.Recognizer(tiny_map, backend="cpu")
    for s, want in zip(sessions, results):
        rec.reset()
        for r in s["readings"]:
            rec.add_reading(reading_of(r))
        assert rec.reading_count() == len(s["readings"])
        assert_estimate_is(rec.estimate(top_k=3), want, tiny_map.object_names)
    # and the estimates are not trivial: most trials find the object (6 readings on the tiny scene)
    right = sum(w["object"] == s["truth"]["object"] for s, w in zip(sessions, results))
    assert right >= 4


def test_estimate_arrays(tiny, tiny_map):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    for r in tiny.session_lines()[0]["readings"]:
        rec.add_reading(reading_of(r))
    est = rec.estimate()
    assert est.pose.R.shape == (3, 3) and est.pose.R.dtype == np.float64
    assert est.pose.T.shape == (3,)
    assert np.allclose(est.pose.R @ est.pose.R.T, np.eye(3), atol=1e-9)
    assert est.object_probability.shape == (tiny_map.objects,)
    assert est.object_probability.sum() == pytest.approx(1.0)
    assert len(est.top) == 5 and est.top[0].probability >= est.top[-1].probability
    # the 4x4 matrix and apply() agree with R and T
    M = est.pose.matrix()
    x = np.array([10.0, -5.0, 3.0])
    assert np.allclose(M[:3, :3] @ x + M[:3, 3], est.pose.apply(x))
    assert np.allclose(est.pose.apply(x), est.pose.R @ x + est.pose.T)


def test_estimate_evidence_weighs_into_its_object(tiny, tiny_map):
    """Estimate.evidence: what the object posterior is made of, as arrays per object id; weighed as the calibration
    weighs it, it ranks the estimate's object first (docs/recognition.md, "What the posterior is made of")."""
    rec = sva.Recognizer(tiny_map, backend="cpu")
    assert rec.estimate().evidence.pairs_log2_mass.shape == (0,)  # not ready: nothing yet
    for r in tiny.session_lines()[0]["readings"]:
        rec.add_reading(reading_of(r))
    est = rec.estimate()
    ev = est.evidence
    assert isinstance(ev, sva.ObjectEvidence)
    assert ev.pairs_log2_mass.shape == (tiny_map.objects,) and ev.pairs_log2_mass.dtype == np.float64
    assert ev.surface_log2_fit.shape in ((0,), (tiny_map.objects,))
    q = ev.temperature * ev.pairs_log2_mass
    if ev.surface_log2_fit.size:
        q = q + ev.surface_weight * ev.surface_log2_fit
    assert int(np.argmax(q)) == est.object


def test_light_estimates_read_their_own_calibration(tiny, tiny_map):
    """A map of this build carries light estimates' calibration from its fine pose's first reading (tests/calibration
    show what it changes); before that reading a light estimate's probabilities are the full estimate's."""
    assert tiny_map.light_calibration_from == tiny_map.fine_pose_from == 6
    rec = sva.Recognizer(tiny_map, backend="cpu")
    compared = 0
    for s in tiny.session_lines():
        rec.reset()
        for reading in s["readings"][:5]:
            rec.add_reading(reading_of(reading))
            light, full = rec.estimate(top_k=0, depth="light"), rec.estimate(top_k=0)
            assert light.object_probability.tolist() == full.object_probability.tolist()
            assert light.p_unknown == full.p_unknown
            compared += 1
    assert compared > 0


def test_light_estimate_is_the_beliefs_answer(tiny, tiny_map):
    """depth="light": the parabolic pose, no fit; what a recognizer built without fits says (calibration off on both,
    so that neither fits for "none of these"); a full estimate after it is the full estimate alone."""
    sessions = tiny.session_lines()
    rec = sva.Recognizer(tiny_map, backend="cpu", calibrate=False)
    bare = sva.Recognizer(tiny_map, backend="cpu", calibrate=False, refine_pose=False, surface_check=False)
    alone = sva.Recognizer(tiny_map, backend="cpu", calibrate=False)
    refined = 0
    for s in sessions:
        for r in (rec, bare, alone):
            r.reset()
        for reading in s["readings"]:
            for r in (rec, bare, alone):
                r.add_reading(reading_of(reading))
        light = rec.estimate(top_k=3, depth="light")
        assert not light.pose_refined
        assert np.array_equal(light.pose.R, light.parabolic_pose.R)
        assert np.array_equal(light.pose.T, light.parabolic_pose.T)
        want = bare.estimate(top_k=3)
        assert light.object_probability.tolist() == want.object_probability.tolist()
        assert [h.probability for h in light.top] == [h.probability for h in want.top]
        full, full_alone = rec.estimate(top_k=3), alone.estimate(top_k=3)
        assert full.object_probability.tolist() == full_alone.object_probability.tolist()
        assert np.array_equal(full.pose.T, full_alone.pose.T)
        refined += full.pose_refined
    assert refined > 0  # not vacuous: 6 readings, the full estimates fitted
    b = sva.BatchRecognizer(tiny_map, 2, backend="cpu", calibrate=False)
    b.add_readings([0, 1], [reading_of(sessions[0]["readings"][0])] * 2)
    b.add_readings([0, 1], [reading_of(sessions[0]["readings"][1])] * 2)
    both = b.estimates([0, 1], top_k=3, depth="light")
    assert both[0].object_probability.tolist() == b.estimate(1, top_k=3, depth="light").object_probability.tolist()
    with pytest.raises(sva.Error, match='depth expects full or light, got "fine"'):
        rec.estimate(depth="fine")
    with pytest.raises(sva.Error, match="depth"):
        b.estimates([0], depth="")


def test_batch_recognizer_gives_the_cli_estimates(tiny, tiny_map):
    sessions = tiny.session_lines()
    results = tiny.result_lines()
    b = sva.BatchRecognizer(tiny_map, len(sessions), backend="cpu")
    assert b.backend == "cpu" and b.sessions() == len(sessions)
    for step in range(max(len(s["readings"]) for s in sessions)):
        ids = [i for i, s in enumerate(sessions) if step < len(s["readings"])]
        b.add_readings(ids, [reading_of(sessions[i]["readings"][step]) for i in ids])
    at_once = b.estimates(list(range(len(sessions))), top_k=3)
    assert len(at_once) == len(sessions)
    for i, want in enumerate(results):
        assert b.readings(i) == len(sessions[i]["readings"])
        assert_estimate_is(b.estimate(i, top_k=3), want, tiny_map.object_names)
        assert_estimate_is(at_once[i], want, tiny_map.object_names)
        assert b.belief_bytes(i) > 0  # a live session's memory: its belief's tables
    kept = b.belief_bytes(0)
    b.reset(0)
    assert b.belief_bytes(0) == kept  # a reset keeps the table's allocation for the next session
    assert b.readings(0) == 0 and b.readings(1) > 0
    with pytest.raises(sva.Error, match="out of range"):
        b.reset([1, len(sessions)])  # every id checked first: session 1 keeps its readings
    assert b.readings(1) > 0
    b.reset(list(range(len(sessions))))  # a group's start, all at once
    assert all(b.readings(i) == 0 for i in range(len(sessions)))


# Groups of 2 on 3 recognizers in flight at once: the same bytes (on a GPU, the host works while the device runs).
@pytest.mark.parametrize("per_submission, in_flight, umask, mode",
                         [(64, None, 0o022, 0o644), (4, None, 0o077, 0o600), (2, 3, 0o022, 0o644)])
def test_recognize_batch_writes_the_cli_file(tiny, tiny_map, tmp_path, per_submission, in_flight, umask, mode):
    out = tmp_path / "results.jsonl"
    old = os.umask(umask)
    try:
        lines = sva.recognize_batch(tiny_map, tiny.sessions, out, sessions_per_submission=per_submission,
                                    in_flight=in_flight, backend="cpu")
    finally:
        os.umask(old)
    assert out.read_bytes() == tiny.results.read_bytes()
    assert lines == tiny.results.read_text().splitlines()
    # A results file is meant to be shared: the user's umask decides its mode, not the temporary file's 0600.
    assert stat.S_IMODE(out.stat().st_mode) == mode
    assert [p.name for p in tmp_path.iterdir()] == ["results.jsonl"]  # no temporary file left behind


def test_recognize_batch_light_estimates_are_the_cli_files(tiny, tiny_map, tmp_path):
    """depth="light": each session's estimate at its end without the host's fits, as `sva recognize --estimate
    light` writes them; the tiny sessions' 6 readings reach the fine pose, so the full file differs."""
    cli = tmp_path / "cli.jsonl"
    run_sva("recognize", "--map", str(tiny.map), "--batch", str(tiny.sessions), "--out", str(cli), "--backend", "cpu",
            "--top", "3", "--estimate", "light")
    out = tmp_path / "light.jsonl"
    lines = sva.recognize_batch(tiny_map, tiny.sessions, out, backend="cpu", depth="light")
    assert out.read_bytes() == cli.read_bytes()
    assert lines == cli.read_text().splitlines()
    assert out.read_bytes() != tiny.results.read_bytes()
    with pytest.raises(sva.Error, match='depth expects full or light, got "fine"'):
        sva.recognize_batch(tiny_map, tiny.sessions, backend="cpu", depth="fine")


def test_recognize_batch_reports_the_bad_line(tiny, tmp_path):
    lines = tiny.sessions.read_text().splitlines()
    bad = lines[:3] + [lines[3].replace('"position":[', '"position":["x",', 1)] + lines[4:]
    f = tmp_path / "bad.jsonl"
    f.write_text("\n".join(bad) + "\n")
    out = tmp_path / "out.jsonl"
    with pytest.raises(sva.Error, match=r"bad\.jsonl:4: readings\[0\]\.position: expected an array of 3 numbers"):
        sva.recognize_batch(str(tiny.map), f, out, backend="cpu")
    assert not out.exists()
    with pytest.raises(sva.Error, match="no-such-dir/out.jsonl: cannot write"):
        sva.recognize_batch(str(tiny.map), tiny.sessions, tmp_path / "no-such-dir" / "out.jsonl", backend="cpu")
    empty = tmp_path / "empty.jsonl"
    empty.write_text("\n  \n")
    with pytest.raises(sva.Error, match="no sessions"):
        sva.recognize_batch(str(tiny.map), empty, backend="cpu")


def test_pose_space_and_options(tiny_map):
    ps = tiny_map.pose_space
    assert ps.kind == sva.PoseSpaceKind.spatial and ps.translation_bins > 0
    wide = sva.PoseSpaceSpec(translation_bins=10, translation_min_mm=-300, translation_max_mm=300)
    rec = sva.Recognizer(tiny_map, wide, backend="cpu", refine_pose=False, threads=1)
    assert rec.reading_count() == 0
    with pytest.raises(sva.Error, match="backend"):
        sva.Recognizer(tiny_map, backend="gpu")
    with pytest.raises(TypeError, match="unknown option \"backnd\""):
        sva.Recognizer(tiny_map, backnd="cpu")
    with pytest.raises(sva.Error, match="likelihood_cutoff"):
        sva.Recognizer(tiny_map, backend="cpu", likelihood_cutoff=-1.0)
    # The surface check (docs/recognition.md) is on by default and can be turned off; a wrong type is named.
    assert sva.Recognizer(tiny_map, backend="cpu", surface_check=False).reading_count() == 0
    with pytest.raises(TypeError, match="surface_check"):
        sva.Recognizer(tiny_map, backend="cpu", surface_check="yes")



def test_hypotheses_with_covariance(tiny, tiny_map):
    """Distinct modes carry a 6x6 covariance in ROS PoseWithCovariance order as a NumPy array."""
    rec = sva.Recognizer(tiny_map, backend="cpu")
    for r in tiny.session_lines()[0]["readings"]:
        rec.add_reading(reading_of(r))
    est = rec.estimate()
    assert len(est.hypotheses) >= 1
    h = est.hypotheses[0]
    assert h.object == est.object and 0.0 < h.probability <= 1.0
    cov = h.covariance
    assert cov.shape == (6, 6) and cov.dtype == np.float64
    assert np.allclose(cov, cov.T)
    assert np.all(np.diag(cov)[:3] > 0)  # the bin quantisation alone gives every translation axis a variance
    assert len(est.object_hypotheses) == tiny_map.objects
    assert est.object_hypotheses[est.object].valid


def test_sessions_per_submission_defaults_to_the_engines(tiny_map, tiny, tmp_path):
    # On the CPU reference (and lavapipe) the engine steps 64 sessions together; the default gives the same file as
    # asking for it.
    engine = sva.Engine(tiny_map, backend="cpu")
    assert engine.sessions_per_submission() == 64
    assert engine.submissions_in_flight() == 1  # the CPU's cores are busy with one group
    with pytest.raises(sva.Error, match="in_flight must be >= 1"):
        sva.recognize_batch(tiny_map, tiny.sessions, in_flight=0, backend="cpu")
    assert engine.sessions_per_submission(belief_budget_bins=0) == 64
    with pytest.raises(TypeError):
        engine.sessions_per_submission(no_such_option=1)
    default = sva.recognize_batch(tiny_map, tiny.sessions, tmp_path / "a.jsonl", backend="cpu", threads=1)
    asked = sva.recognize_batch(tiny_map, tiny.sessions, tmp_path / "b.jsonl", sessions_per_submission=64,
                                backend="cpu", threads=1)
    assert default == asked
    assert (tmp_path / "a.jsonl").read_bytes() == (tmp_path / "b.jsonl").read_bytes()


def test_belief_budget_bins_is_an_option(tiny, tiny_map):
    # RecognizerOptions.belief_budget_bins from Python (docs/recognition.md, "Bounded memory"): accepted by the
    # recognizers and the engine, a negative count refused by name.
    session = tiny.session_lines()[0]
    bounded = sva.BatchRecognizer(tiny_map, 1, backend="cpu", belief_budget_bins=256)
    free = sva.BatchRecognizer(tiny_map, 1, backend="cpu", belief_budget_bins=0)
    for r in session["readings"]:
        bounded.add_readings([0], [reading_of(r)])
        free.add_readings([0], [reading_of(r)])
    assert bounded.estimate(0).object == free.estimate(0).object
    assert sva.Engine(tiny_map, backend="cpu").sessions_per_submission(belief_budget_bins=256) == 64
    with pytest.raises(TypeError, match="belief_budget_bins"):
        sva.BatchRecognizer(tiny_map, 1, backend="cpu", belief_budget_bins=-1)


def test_sva_recognize_groups_in_flight_give_the_same_file(tiny, tmp_path):
    # The command line's --in-flight: three groups of 2 sessions at once on three recognizers, the file's bytes as one
    # group of all (the GPU's double buffering, here on the CPU reference).
    out = tmp_path / "in-flight.jsonl"
    run_sva("recognize", "--map", str(tiny.map), "--batch", str(tiny.sessions), "--out", str(out),
            "--backend", "cpu", "--top", "3", "--sessions-per-submission", "2", "--in-flight", "3")
    assert out.read_bytes() == tiny.results.read_bytes()
