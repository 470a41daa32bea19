"""Recognizers sharing one sva.Engine, priors over objects and poses, sessions saved and restored, and reset: the
Python path against the C++ one (the CLI's results on the same map and sessions) and its errors."""

from __future__ import annotations

import numpy as np
import pytest

import sva
from conftest import reading_of
from test_recognition import assert_estimate_is


def fed(rec: sva.Recognizer, session: dict) -> sva.Recognizer:
    for r in session["readings"]:
        rec.add_reading(reading_of(r))
    return rec


def same_estimate(a: sva.Estimate, b: sva.Estimate) -> None:
    assert a.readings == b.readings and a.object == b.object
    assert a.object_probability.tolist() == b.object_probability.tolist()
    assert a.pose_valid == b.pose_valid
    assert np.array_equal(a.pose.R, b.pose.R) and np.array_equal(a.pose.T, b.pose.T)
    assert [h.probability for h in a.hypotheses] == [h.probability for h in b.hypotheses]
    for h, g in zip(a.hypotheses, b.hypotheses):
        assert np.array_equal(h.covariance, g.covariance)


def test_recognizers_sharing_an_engine_give_the_cli_estimates(tiny, tiny_map):
    engine = sva.Engine(tiny_map, backend="cpu")
    assert engine.backend == "cpu" and engine.fallback_reason == ""
    assert engine.map.entries == tiny_map.entries
    sessions, results = tiny.session_lines(), tiny.result_lines()
    a, b = sva.Recognizer(engine), sva.Recognizer(engine)
    for s, want in zip(sessions, results):
        a.reset()
        b.reset()
        fed(a, s)
        fed(b, s)
        assert_estimate_is(a.estimate(top_k=3), want, tiny_map.object_names)
        assert_estimate_is(b.estimate(top_k=3), want, tiny_map.object_names)


def test_engine_errors(tiny_map):
    engine = sva.Engine(tiny_map, backend="cpu")
    with pytest.raises(sva.Error, match="backend comes from the engine"):
        sva.Recognizer(engine, backend="cpu")
    with pytest.raises(sva.Error, match="map is empty"):
        sva.Engine(sva.Map())
    with pytest.raises(sva.Error, match="backend"):
        sva.Engine(tiny_map, backend="gpu")


def test_object_prior_changes_the_estimate_as_the_evidence_times_the_prior(tiny, tiny_map):
    s = tiny.session_lines()[0]
    prior = np.linspace(1.0, 3.0, tiny_map.objects)[::-1].copy()  # favours object 0
    prior[0], prior[-1] = prior[-1], prior[0]  # now the last object
    # One reading makes no pair: the evidence is flat and the prior decides.
    first = sva.Recognizer(tiny_map, backend="cpu")
    first.add_reading(reading_of(s["readings"][0]))
    assert first.estimate().object_probability == pytest.approx(np.full(tiny_map.objects, 1 / tiny_map.objects))
    first.set_prior(sva.Prior(prior))
    e = first.estimate()
    assert e.object == tiny_map.objects - 1
    assert e.object_probability == pytest.approx(prior / prior.sum(), rel=1e-12)
    # With evidence: the evidence times the prior, renormalised - exactly so before the calibration's top label,
    # which then recalibrates the product's top object (docs/api.md, "Priors").
    plain = fed(sva.Recognizer(tiny_map, backend="cpu", calibrate=False), s)
    camera = fed(sva.Recognizer(tiny_map, backend="cpu", calibrate=False), s)
    camera.set_prior(sva.Prior(list(prior)))
    p = plain.estimate().object_probability
    want = p * prior / prior.max()
    assert camera.estimate().object_probability == pytest.approx(want / want.sum(), rel=1e-9)
    camera.set_prior(sva.Prior())  # flat again: the evidence, bit for bit
    assert camera.estimate().object_probability.tolist() == p.tolist()
    # Calibrated, the prior still moves the posterior towards the object it favours, and a flat one changes nothing.
    plain = fed(sva.Recognizer(tiny_map, backend="cpu"), s)
    camera = fed(sva.Recognizer(tiny_map, backend="cpu"), s)
    camera.set_prior(sva.Prior(list(prior)))
    assert camera.estimate().object_probability[-1] > plain.estimate().object_probability[-1]
    camera.set_prior(sva.Prior())
    assert camera.estimate().object_probability.tolist() == plain.estimate().object_probability.tolist()


def test_pose_prior_leaves_the_object_posterior_and_moves_the_pose(tiny, tiny_map):
    s = tiny.session_lines()[1]
    plain = fed(sva.Recognizer(tiny_map, backend="cpu", refine_pose=False), s)
    e = plain.estimate(top_k=3)
    assert e.pose_valid
    far = e.pose.T + np.array([30.0, 0.0, 0.0])
    rec = fed(sva.Recognizer(tiny_map, backend="cpu", refine_pose=False), s)
    poses = [None] * tiny_map.objects
    poses[e.object] = sva.PosePrior(far, 2.0)
    rec.set_prior(sva.Prior(object_pose=poses))
    w = rec.estimate(top_k=3)
    assert w.object_probability.tolist() == e.object_probability.tolist()
    # The best bin can only move towards the prior's mean (it has less evidence, so more prior).
    assert np.linalg.norm(w.bin_pose.T - far) <= np.linalg.norm(e.bin_pose.T - far) + 1e-9
    assert rec.estimate(top_k=3).pose.T.tolist() == w.pose.T.tolist()  # deterministic
    pp = sva.PosePrior([1, 2, 3], 4.0)
    assert pp.rotation is None and pp.position.tolist() == [1.0, 2.0, 3.0]
    pr = sva.PosePrior(far, 2.0, rotation=e.pose.R, rotation_sigma_rad=0.1)
    assert np.array_equal(pr.rotation, e.pose.R) and pr.rotation_sigma_rad == 0.1


def test_save_and_restore_give_the_same_estimate(tiny, tiny_map, tmp_path):
    engine = sva.Engine(tiny_map, backend="cpu")
    s = tiny.session_lines()[2]
    original = sva.Recognizer(engine)
    original.set_prior(sva.Prior(np.linspace(1.0, 2.0, tiny_map.objects)))
    fed(original, s)
    path = tmp_path / "robot.svas"
    original.save_session(path)
    resumed = sva.Recognizer(engine)
    resumed.restore_session(path)
    assert resumed.reading_count() == len(s["readings"])
    same_estimate(resumed.estimate(top_k=3), original.estimate(top_k=3))
    # and both go on alike
    more = reading_of(tiny.session_lines()[3]["readings"][0])
    original.add_reading(more)
    resumed.add_reading(more)
    same_estimate(resumed.estimate(top_k=3), original.estimate(top_k=3))


def test_reset_then_the_same_readings_give_the_same_estimate(tiny, tiny_map):
    s = tiny.session_lines()[4]
    rec = fed(sva.Recognizer(tiny_map, backend="cpu"), s)
    first = rec.estimate(top_k=3)
    rec.reset()
    assert rec.reading_count() == 0
    fed(rec, s)
    same_estimate(rec.estimate(top_k=3), first)


def test_bad_priors_and_session_files_raise_clear_errors(tiny_map, tmp_path):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    with pytest.raises(sva.Error, match="object probabilities, but the map has"):
        rec.set_prior(sva.Prior([0.5] * (tiny_map.objects + 1)))
    with pytest.raises(sva.Error, match="finite"):
        rec.set_prior(sva.Prior([float("nan")] * tiny_map.objects))
    with pytest.raises(TypeError, match="Prior.object_probability"):
        sva.Prior("abc")
    with pytest.raises(ValueError, match="PosePrior.position"):
        sva.PosePrior([1.0, 2.0], 3.0)
    with pytest.raises(sva.Error, match="position_sigma_mm"):
        rec.set_prior(sva.Prior(object_pose=[sva.PosePrior([0, 0, 0], 0.0)] * tiny_map.objects))
    with pytest.raises(sva.Error, match="object pose priors"):
        rec.set_prior(sva.Prior(object_pose=[None] * (tiny_map.objects + 2)))
    missing = tmp_path / "nowhere.svas"
    with pytest.raises(sva.Error, match="nowhere.svas"):
        rec.restore_session(missing)
    junk = tmp_path / "junk.svas"
    junk.write_bytes(b"not a session")
    with pytest.raises(sva.Error, match="junk.svas"):
        rec.restore_session(junk)


def test_pose_space_placed_in_the_workspace(tiny_map):
    grid = tiny_map.pose_space
    placed = sva.placed_pose_space(grid, [600.0, 0.0, 100.0], 150.0)
    assert placed.workspace.T.tolist() == [600.0, 0.0, 100.0]
    assert placed.translation_min_mm == -150.0 and placed.translation_max_mm == 150.0
    around = sva.pose_space_around(grid, sva.PosePrior([10.0, 20.0, 30.0], 5.0))
    assert around.workspace.T.tolist() == [10.0, 20.0, 30.0] and around.translation_max_mm == 15.0
    with pytest.raises(ValueError, match="placed_pose_space: centre"):
        sva.placed_pose_space(grid, [1.0, 2.0], 10.0)
