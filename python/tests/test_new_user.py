"""What a new Python user stumbled on (issue 20), each fixed and kept fixed: the package docstring's example runs,
images keep their shape and a wrong shape is refused, samples say whether they converged, an estimate before any
reading says it is none, saving a session refuses what loading would, a version, ROS units, names and docstrings,
and a truncated session file is called truncated."""

from __future__ import annotations

import contextlib
import io
import math
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import sva
from conftest import REPO, reading_of, run_sva


def docstring_example() -> str:
    """The indented block after the first "::" of the package docstring."""
    lines = sva.__doc__.splitlines()
    start = next(i for i, line in enumerate(lines) if line.rstrip().endswith("::")) + 1
    block = []
    for line in lines[start:]:
        if line.strip() and not line.startswith("    "):
            break
        block.append(line)
    return textwrap.dedent("\n".join(block))


def test_the_package_docstring_example_runs():
    code = docstring_example()
    assert "sva.Recognizer(engine)" in code and "sample.converged" in code
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "sva.__doc__", "exec"), {})
    lines = out.getvalue().splitlines()
    # One session per object, each recognised as itself (the tiny scene's two objects are far apart).
    assert [line.split()[:2] for line in lines] == [["die", "die"], ["brick", "brick"]], out.getvalue()


def test_images_keep_their_shape_and_the_map_says_its_sensor(tiny, tiny_map):
    assert (tiny_map.rows, tiny_map.cols) == (6, 6)
    assert (tiny_map.sensor.rows, tiny_map.sensor.cols) == (6, 6)
    r = sva.Reading(np.arange(36, dtype=np.float32).reshape(6, 6), [0, 0, 40], [0, 0, 1])
    assert r.pressure.shape == (6, 6) and (r.rows, r.cols) == (6, 6)
    assert r.pressure[1, 0] == 6.0
    flat = sva.Reading(np.arange(36, dtype=np.float32), [0, 0, 40], [0, 0, 1])
    assert flat.pressure.shape == (36,) and (flat.rows, flat.cols) == (0, 0)
    loaded = sva.Dataset.load(tiny.test)
    assert loaded[0].reading.pressure.shape == (6, 6)
    made, _ = sva.simulate("tiny", train=1, test=0, seed=1)
    assert made[0].reading.pressure.shape == (6, 6)


def test_a_wrongly_shaped_image_is_refused(tiny_map):
    odd = sva.Reading(np.full((4, 9), 10.0), [0, 0, 40], [0, 0, 1])
    assert odd.pressure.shape == (4, 9)
    rec = sva.Recognizer(tiny_map, backend="cpu")
    with pytest.raises(sva.Error, match=r"reading 1: the pressure image is 4 x 9, but the map's sensor is 6 x 6"):
        rec.add_reading(odd)
    assert rec.reading_count() == 0
    r = sva.Reading(np.full((6, 6), 1.0), [0, 0, 40], [0, 0, 1])
    with pytest.raises(ValueError, match=r"the reading's image is 6 x 6, the new one 4 x 9"):
        r.pressure = np.zeros((4, 9))
    r.pressure = np.zeros(36)  # flat: the values of the known shape
    assert r.pressure.shape == (6, 6)


def test_samples_say_whether_they_converged(tiny):
    d = sva.Dataset.load(tiny.test)
    flags = [s.converged for s in d]
    assert flags == d.converged().tolist()
    assert sum(flags) == d.count_converged()
    rec = sva.Recognizer(sva.Map.load(tiny.map), backend="cpu", refine_pose=False)
    for s in d:  # the documented loop: never raises on an unconverged sample
        if s.object == 1 and s.converged:
            rec.add_reading(s.reading)
    assert rec.reading_count() == sum(1 for s in d if s.object == 1 and s.converged)


def test_an_estimate_before_any_reading_is_not_an_answer(tiny, tiny_map):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    est = rec.estimate()
    assert not est.ready and est.readings == 0
    assert est.object is None and est.object_name is None
    assert not est.pose_valid and est.top == [] and est.hypotheses == [] and est.object_hypotheses == []
    assert est.object_probability.tolist() == [0.5, 0.5]  # the (flat) prior, not evidence
    rec.set_prior(sva.Prior([1.0, 3.0]))
    assert rec.estimate().object_probability.tolist() == [0.25, 0.75]
    assert rec.estimate().object is None
    rec.add_reading(reading_of(tiny.session_lines()[0]["readings"][0]))
    est = rec.estimate()
    assert est.ready and est.object in (0, 1) and est.object_name in tiny_map.object_names
    rec.reset()
    assert not rec.estimate().ready


def test_save_session_refuses_what_restore_would(tiny, tiny_map, tmp_path):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    rec.add_reading(reading_of(tiny.session_lines()[0]["readings"][0]))
    missing = tmp_path / "no" / "such" / "s.svas"
    with pytest.raises(sva.Error, match=re.escape(f"the folder {missing.parent} does not exist")):
        rec.save_session(missing)
    assert not (tmp_path / "no").exists()  # no folder made
    with pytest.raises(sva.Error, match=re.escape(f"{tmp_path}: is a folder, expected a session file name")):
        rec.save_session(tmp_path)
    with pytest.raises(sva.Error, match="the file name is empty"):
        rec.save_session("")
    (tmp_path / "plain").write_text("x")
    with pytest.raises(sva.Error, match="the folder .*plain is not a folder"):
        rec.save_session(tmp_path / "plain" / "s.svas")
    rec.save_session(tmp_path / "s.svas")  # and a good path still works
    assert (tmp_path / "s.svas").is_file()


def test_a_truncated_session_file_is_called_truncated(tiny, tiny_map, tmp_path):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    for r in tiny.session_lines()[0]["readings"][:2]:
        rec.add_reading(reading_of(r))
    good = tmp_path / "s.svas"
    rec.save_session(good)
    data = good.read_bytes()
    head = tmp_path / "head.svas"
    head.write_bytes(data[:20])  # the magic intact, the header cut
    with pytest.raises(sva.Error, match=re.escape(f"{head}: truncated session file: 20 bytes, its header alone is 32")):
        sva.Recognizer(tiny_map, backend="cpu").restore_session(head)
    body = tmp_path / "body.svas"
    body.write_bytes(data[:-10])
    with pytest.raises(sva.Error, match=re.escape(f"{body}: truncated session file: expected {len(data)} bytes") +
                       ".*" + re.escape(f"the file has {len(data) - 10}")):
        sva.Recognizer(tiny_map, backend="cpu").restore_session(body)


def test_version_is_the_projects():
    m = re.search(r'^version = "([^"]+)"', (REPO / "pyproject.toml").read_text(), re.M)
    assert sva.__version__ == m.group(1)
    assert run_sva("--version").split() == ["sva", sva.__version__]


def rotation_of_quaternion(x, y, z, w) -> np.ndarray:
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def test_to_ros_follows_the_documented_mapping(tiny, tiny_map):
    doc = (REPO / "docs" / "api.md").read_text()
    # The mapping the test checks, as docs/api.md states it.
    assert "`hypotheses[i].pose.T` / 1000 (ROS uses metres)" in doc
    assert "the x, y, z block by 1e-6, the mixed blocks by 1e-3" in doc
    assert "to_ros" in doc
    rec = sva.Recognizer(tiny_map, backend="cpu")
    for r in tiny.session_lines()[0]["readings"]:
        rec.add_reading(reading_of(r))
    hyps = rec.estimate(top_k=3).hypotheses
    assert hyps
    for h in hyps:
        position, q, cov = h.to_ros()
        assert position.shape == (3,) and q.shape == (4,) and cov.shape == (6, 6)
        assert position == pytest.approx(h.pose.T / 1000, abs=1e-15)
        assert math.isclose(np.linalg.norm(q), 1.0, abs_tol=1e-12) and q[3] >= 0
        assert rotation_of_quaternion(*q) == pytest.approx(h.pose.R, abs=1e-9)
        scale = np.array([1e-3] * 3 + [1.0] * 3)
        assert cov == pytest.approx(h.covariance * np.outer(scale, scale), rel=1e-12, abs=0)


def test_names_and_docstrings():
    for f in (sva.Recognizer.estimate, sva.Recognizer.reading_count, sva.PoseHypothesis.to_ros):
        assert f.__doc__ and len(f.__doc__.strip()) > 20, f
    for prop in (sva.Estimate.object_name, sva.Estimate.bin_pose, sva.Estimate.ready, sva.Hypothesis.probability,
                 sva.Hypothesis.object_name, sva.PoseHypothesis.probability, sva.Hypothesis.pose):
        assert prop.__doc__ and prop.__doc__.strip(), prop


def test_reading_count_and_the_deprecated_name(tiny, tiny_map):
    rec = sva.Recognizer(tiny_map, backend="cpu")
    assert rec.reading_count() == 0
    rec.add_reading(reading_of(tiny.session_lines()[0]["readings"][0]))
    assert rec.reading_count() == 1
    with pytest.warns(DeprecationWarning, match="reading_count"):
        assert rec.readings() == 1


def test_help_runs_without_error():
    r = subprocess.run([sys.executable, "-c", "import sva, pydoc; pydoc.render_doc(sva)"], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
