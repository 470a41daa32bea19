"""Bad inputs raise clear errors: wrong array shape or dtype (ValueError, TypeError), non-finite values and bad files
(sva.Error, a RuntimeError, with the engine's message naming the value or file)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import sva


def good(**kw) -> dict:
    a = dict(pressure=np.full((6, 6), 10.0, dtype=np.float32), position=[0.0, 0.0, 40.0], normal=[0.0, 0.0, 1.0])
    a.update(kw)
    return a


def test_error_is_a_runtime_error():
    assert issubclass(sva.Error, RuntimeError)


@pytest.mark.parametrize(
    "kw, exc, msg",
    [
        (dict(pressure=np.ones((6, 6), dtype=np.complex64)), TypeError, "Reading.pressure: expected an array of real numbers, got dtype complex64"),
        (dict(pressure=["a"] * 36), TypeError, "Reading.pressure: expected an array of real numbers, got dtype <U1"),
        (dict(pressure=np.ones((2, 3, 6))), ValueError, r"Reading.pressure: .* got shape \(2, 3, 6\)"),
        (dict(pressure=np.ones(0)), ValueError, "the pressure image is empty"),
        (dict(position=[1.0, 2.0]), ValueError, r"Reading.position: expected 3 numbers \(shape \(3,\)\), got shape \(2,\)"),
        (dict(normal=np.eye(3)), ValueError, r"Reading.normal: expected 3 numbers"),
        (dict(position="abc"), TypeError, "Reading.position: expected an array of real numbers"),
    ],
)
def test_bad_arrays(kw, exc, msg):
    with pytest.raises(exc, match=msg):
        sva.Reading(**good(**kw))


def test_pose_arrays():
    with pytest.raises(ValueError, match=r"RigidPose.R: expected a 3x3 matrix, got shape \(3,\)"):
        sva.RigidPose(np.ones(3), np.zeros(3))
    p = sva.RigidPose()
    with pytest.raises(ValueError, match="RigidPose.T"):
        p.T = np.zeros(4)
    r = sva.Reading(**good())
    with pytest.raises(ValueError, match="the reading's image has 36 values, the new one 25"):
        r.pressure = np.zeros((5, 5))


@pytest.mark.parametrize(
    "kw, msg",
    [
        (dict(pressure=np.full(36, math.nan, dtype=np.float32)), "the pressure image has a non-finite value"),
        (dict(pressure=np.full(36, np.inf)), "the pressure image has a non-finite value"),
        (dict(position=[math.nan, 0.0, 0.0]), "the sensor position is not finite"),
        (dict(normal=[0.0, 0.0, 0.0]), "the sensor normal has zero length"),
        (dict(pressure=np.full((5, 5), 10.0)), "25 pressure values, but the map's sensor has 36"),
        (dict(pressure=np.full((4, 9), 10.0)), "the pressure image is 4 x 9, but the map's sensor is 6 x 6"),
        (dict(status=sva.ControllerStatus.not_converged), "did not converge"),
    ],
)
def test_bad_readings_are_refused_by_the_engine(tiny_map, kw, msg):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    with pytest.raises(sva.Error, match=msg):
        rec.add_reading(sva.Reading(**good(**kw)))
    assert rec.reading_count() == 0  # nothing was added


def test_batch_recognizer_checks_its_arguments(tiny_map):
    b = sva.BatchRecognizer(tiny_map, 2, backend="cpu")
    with pytest.raises(sva.Error, match="2 sessions but 1 readings"):
        b.add_readings([0, 1], [sva.Reading(**good())])
    with pytest.raises(sva.Error, match="out of range"):
        b.add_readings([5], [sva.Reading(**good())])
    with pytest.raises(sva.Error, match="session 2 out of range"):
        b.belief_bytes(2)
    with pytest.raises(sva.Error, match="need at least one session"):
        sva.BatchRecognizer(tiny_map, 0)


def test_missing_and_bad_files(tmp_path):
    with pytest.raises(sva.Error, match="nope.svam"):
        sva.Map.load(tmp_path / "nope.svam")
    with pytest.raises(sva.Error, match="nope.svad"):
        sva.Dataset.load(str(tmp_path / "nope.svad"))
    junk = tmp_path / "junk.svam"
    junk.write_bytes(b"not a map at all")
    with pytest.raises(sva.Error, match="junk.svam"):
        sva.Map.load(junk)
    with pytest.raises(sva.Error, match="nope.svad"):
        sva.train(tmp_path / "nope.svad")
    with pytest.raises(sva.Error, match="nope.jsonl: cannot read the sessions file"):
        sva.recognize_batch(sva.Map(), tmp_path / "nope.jsonl")
    with pytest.raises(TypeError, match="expected a Dataset or the path"):
        sva.train(42)


def test_bad_workflow_options(tiny):
    with pytest.raises(sva.Error, match="descriptor"):
        sva.train(str(tiny.train), descriptor="xyz")
    with pytest.raises(sva.Error, match="sva.train: distance range 50"):
        sva.train(str(tiny.train), dist_range=(50.0, 10.0))
    with pytest.raises(sva.Error, match="clusters 0: expected 1 to 4096"):
        sva.train(str(tiny.train), clusters=0)
    with pytest.raises(sva.Error, match="sva.train: pair readings 1 per object"):
        sva.train(str(tiny.train), pair_readings=1)
    with pytest.raises(sva.Error, match="method"):
        sva.evaluate(str(tiny.map), str(tiny.test), method="magic")
    with pytest.raises(sva.Error, match="the map is empty"):
        sva.Recognizer(sva.Map())
