"""ROS 2 messages from sva sessions, and MCAP bags of them (docs/ros.md).

Robot engineers inspect everything as ROS 2 bags in Foxglove or RViz. This module turns an estimate and its
session's readings into ROS 2 messages, publisher-agnostic: each function returns the message as a dict of its
fields (nested dicts and lists, as ``rosidl_runtime_py.set_message_fields`` takes them for an rclpy message, and as
mcap-ros2-support writes them), so a live node publishes them and :func:`export_session` writes them to an MCAP
file with no ROS installation:

- ``vision_msgs/msg/Detection3DArray``: the distinct hypotheses (object name, score, pose with covariance in metres,
  the object's bounding box at the best pose), as docs/api.md maps an Estimate onto Detection3D;
- ``geometry_msgs/msg/PoseWithCovarianceStamped``: the best hypothesis;
- ``visualization_msgs/msg/MarkerArray``: the touches (contact points, normals, their order) and the best
  object's mesh at its pose.

Command line: ``python -m sva.ros export --map MAP --sessions SESSIONS.jsonl --out BAG.mcap`` (``--help``).
"""

from __future__ import annotations

from typing import Iterable, Iterator, Optional, Sequence

import numpy as np

from .. import _sva_core as _core

# The exported topics and their types.
TOPICS = {
    "/sva/detections": "vision_msgs/msg/Detection3DArray",
    "/sva/pose": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "/sva/touches": "visualization_msgs/msg/MarkerArray",
    "/sva/object": "visualization_msgs/msg/MarkerArray",
    "/tf": "tf2_msgs/msg/TFMessage",
}

# The best hypothesis' frame: /tf places it at the best pose after every reading, and the object's mesh marker lives
# in it (frame-locked), so the mesh is sent only when the best object changes, not with every reading.
OBJECT_FRAME = "sva_object"

_MM = 1e-3  # sva works in millimetres, ROS in metres


def time_msg(stamp_ns: int) -> dict:
    """builtin_interfaces/Time of a stamp in nanoseconds."""
    if stamp_ns < 0:
        raise ValueError(f"sva.ros: stamp {stamp_ns} ns is negative")
    return {"sec": int(stamp_ns // 1_000_000_000), "nanosec": int(stamp_ns % 1_000_000_000)}


def header(stamp_ns: int, frame_id: str) -> dict:
    """std_msgs/Header."""
    return {"stamp": time_msg(stamp_ns), "frame_id": frame_id}


def _point(p: Sequence[float]) -> dict:
    return {"x": float(p[0]), "y": float(p[1]), "z": float(p[2])}


def _pose(position_m: Sequence[float], quaternion_xyzw: Sequence[float]) -> dict:
    q = quaternion_xyzw
    return {"position": _point(position_m), "orientation": {"x": float(q[0]), "y": float(q[1]), "z": float(q[2]),
                                                            "w": float(q[3])}}


def _color(r: float, g: float, b: float, a: float = 1.0) -> dict:
    return {"r": float(r), "g": float(g), "b": float(b), "a": float(a)}


def pose_with_covariance(hypothesis: "_core.PoseHypothesis") -> dict:
    """geometry_msgs/PoseWithCovariance of a hypothesis (``PoseHypothesis.to_ros``: metres, x y z w, ROS order)."""
    position, orientation, covariance = hypothesis.to_ros()
    return {"pose": _pose(position, orientation), "covariance": [float(c) for c in np.asarray(covariance).ravel()]}


class ObjectBox:
    """An object's bounding box in its own frame (mm), from its mesh: where Detection3D's ``bbox`` comes from."""

    def __init__(self, vertices_mm: np.ndarray):
        v = np.asarray(vertices_mm, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
            raise ValueError("sva.ros: a bounding box needs an (n, 3) array of vertices")
        self.low, self.high = v.min(axis=0), v.max(axis=0)

    def at(self, pose: "_core.RigidPose", orientation_xyzw: Sequence[float]) -> dict:
        """vision_msgs/BoundingBox3D of the box at ``pose`` (its centre moved by the pose, its axes the object's)."""
        centre = np.asarray(pose.R) @ (0.5 * (self.low + self.high)) + np.asarray(pose.T)
        return {"center": _pose(centre * _MM, orientation_xyzw), "size": _point((self.high - self.low) * _MM)}


def detection_array(estimate: "_core.Estimate", stamp_ns: int, frame_id: str, *, detection_id: str = "",
                    boxes: Optional[Sequence[Optional[ObjectBox]]] = None) -> dict:
    """vision_msgs/Detection3DArray: one Detection3D for the touched object, its results the estimate's distinct
    hypotheses, strongest first (docs/api.md, "Mapping an Estimate onto vision_msgs/Detection3D"); the bbox is the
    best object's box at the best pose where ``boxes[object]`` is known, else of size 0 at the best pose. No
    detection before the estimate has a pose."""
    detections = []
    if estimate.ready and estimate.hypotheses:
        results = [{"hypothesis": {"class_id": h.object_name, "score": float(h.probability)},
                    "pose": pose_with_covariance(h)} for h in estimate.hypotheses]
        best = estimate.hypotheses[0]
        box = boxes[best.object] if boxes is not None and best.object < len(boxes) else None
        centre = results[0]["pose"]["pose"]
        q = centre["orientation"]
        bbox = (box.at(best.pose, (q["x"], q["y"], q["z"], q["w"])) if box is not None
                else {"center": centre, "size": _point((0.0, 0.0, 0.0))})
        detections.append({"header": header(stamp_ns, frame_id), "results": results, "bbox": bbox,
                           "id": detection_id})
    return {"header": header(stamp_ns, frame_id), "detections": detections}


def best_pose(estimate: "_core.Estimate", stamp_ns: int, frame_id: str) -> Optional[dict]:
    """geometry_msgs/PoseWithCovarianceStamped of the best hypothesis (the estimate's pose), or None before the
    estimate has one."""
    if not (estimate.ready and estimate.hypotheses):
        return None
    return {"header": header(stamp_ns, frame_id), "pose": pose_with_covariance(estimate.hypotheses[0])}


def _marker(stamp_ns: int, frame_id: str, ns: str, marker_id: int, kind: int) -> dict:
    return {
        "header": header(stamp_ns, frame_id), "ns": ns, "id": marker_id, "type": kind, "action": 0,
        "pose": _pose((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)), "scale": _point((1.0, 1.0, 1.0)),
        "color": _color(1.0, 1.0, 1.0), "lifetime": {"sec": 0, "nanosec": 0}, "frame_locked": False, "points": [],
        "colors": [], "texture_resource": "", "texture": {"header": header(0, ""), "format": "", "data": b""},
        "uv_coordinates": [], "text": "", "mesh_resource": "", "mesh_file": {"filename": "", "data": b""},
        "mesh_use_embedded_materials": False,
    }


SPHERE_LIST, LINE_LIST, TEXT_VIEW_FACING, TRIANGLE_LIST = 7, 5, 9, 11


def touch_markers(readings: Sequence["_core.Reading"], stamp_ns: int, frame_id: str, *,
                  normal_length_mm: float = 10.0) -> dict:
    """visualization_msgs/MarkerArray of the touches so far: their contact points (one sphere list, the latest
    touch orange), their outward normals (a line list) and their numbers in order (a text each, 1 first)."""
    points = _marker(stamp_ns, frame_id, "sva_touches", 0, SPHERE_LIST)
    points["scale"] = _point((0.003, 0.003, 0.003))
    normals = _marker(stamp_ns, frame_id, "sva_normals", 0, LINE_LIST)
    normals["scale"] = _point((0.0006, 0.0, 0.0))
    normals["color"] = _color(0.2, 0.6, 1.0)
    markers = [points, normals]
    for i, r in enumerate(readings):
        p = np.asarray(r.position, dtype=np.float64)
        n = np.asarray(r.normal, dtype=np.float64)
        latest = i + 1 == len(readings)
        points["points"].append(_point(p * _MM))
        points["colors"].append(_color(1.0, 0.5, 0.0) if latest else _color(0.9, 0.9, 0.9))
        normals["points"] += [_point(p * _MM), _point((p + normal_length_mm * n) * _MM)]
        label = _marker(stamp_ns, frame_id, "sva_touch_numbers", i, TEXT_VIEW_FACING)
        label["pose"] = _pose((p + 4.0 * n) * _MM, (0.0, 0.0, 0.0, 1.0))
        label["scale"] = _point((0.0, 0.0, 0.006))
        label["text"] = str(i + 1)
        markers.append(label)
    return {"markers": markers}


class ObjectMesh:
    """An object's triangles in its own frame, ready for a TRIANGLE_LIST marker (metres)."""

    def __init__(self, vertices_mm: np.ndarray, triangles: np.ndarray):
        v = np.asarray(vertices_mm, dtype=np.float64) * _MM
        t = np.asarray(triangles, dtype=np.int64)
        if t.size and (t.min() < 0 or t.max() >= len(v)):
            raise ValueError("sva.ros: a triangle names a vertex the mesh does not have")
        self.points = [_point(p) for p in v[t.ravel()]]
        self.box = ObjectBox(vertices_mm)


def object_transform(estimate: "_core.Estimate", stamp_ns: int, frame_id: str) -> Optional[dict]:
    """tf2_msgs/TFMessage placing OBJECT_FRAME at the best hypothesis' pose in ``frame_id`` (None before a pose)."""
    if not (estimate.ready and estimate.hypotheses):
        return None
    pose = pose_with_covariance(estimate.hypotheses[0])["pose"]
    return {"transforms": [{"header": header(stamp_ns, frame_id), "child_frame_id": OBJECT_FRAME,
                            "transform": {"translation": pose["position"], "rotation": pose["orientation"]}}]}


def object_marker(estimate: "_core.Estimate", mesh: Optional[ObjectMesh], stamp_ns: int) -> dict:
    """visualization_msgs/MarkerArray with the best object's mesh in OBJECT_FRAME (frame-locked: /tf moves it),
    coloured by the object's probability when sent (grey to green), or a DELETEALL before the estimate has a pose or
    without a mesh."""
    if mesh is None or not (estimate.ready and estimate.hypotheses):
        clear = _marker(stamp_ns, OBJECT_FRAME, "sva_object", 0, TRIANGLE_LIST)
        clear["action"] = 3
        return {"markers": [clear]}
    best = estimate.hypotheses[0]
    m = _marker(stamp_ns, OBJECT_FRAME, "sva_object", 0, TRIANGLE_LIST)
    m["frame_locked"] = True
    p = float(estimate.object_probability[best.object]) * (1.0 - float(estimate.p_unknown))
    m["color"] = _color(0.6 - 0.4 * p, 0.6 + 0.3 * p, 0.6 - 0.4 * p, 0.7)
    m["points"] = mesh.points
    m["text"] = best.object_name
    return {"markers": [m]}


def session_messages(recognizer: "_core.Recognizer", readings: Iterable["_core.Reading"], *, frame_id: str = "world",
                     start_ns: int = 0, period_ns: int = 500_000_000, top_k: int = 5, detection_id: str = "",
                     meshes: Optional[Sequence[Optional[ObjectMesh]]] = None,
                     stamps_ns: Optional[Sequence[int]] = None,
                     depth: str = "full") -> Iterator[tuple[str, int, dict]]:
    """Adds the readings to ``recognizer`` one by one and yields ``(topic, stamp_ns, message)`` after each: the
    detections, the best pose and its /tf frame (once there is one), the touches, and the best object's mesh
    (when the best object changes: /tf moves it), reading i at
    ``stamps_ns[i]`` when given (a recording's times: non-decreasing, one per reading), else at
    ``start_ns + i * period_ns``. ``depth="light"``: each update's estimate without the host's fits, the histogram's
    pose (Recognizer.estimate; docs/recognition.md, "Light and full estimates"), for a node that answers every touch
    fast."""
    if period_ns <= 0:
        raise ValueError(f"sva.ros: the period between readings must be positive, got {period_ns} ns")
    if stamps_ns is not None:
        readings = list(readings)
        if len(stamps_ns) != len(readings):
            raise ValueError(f"sva.ros: {len(stamps_ns)} stamps for {len(readings)} readings")
        if any(b < a for a, b in zip(stamps_ns, stamps_ns[1:])) or (stamps_ns and stamps_ns[0] < 0):
            raise ValueError("sva.ros: the stamps must be non-negative and in order")
    boxes = [m.box if m is not None else None for m in meshes] if meshes is not None else None
    taken: list = []
    shown = None  # the object whose mesh was sent last (-1: a DELETEALL)
    for i, reading in enumerate(readings):
        recognizer.add_reading(reading)
        taken.append(reading)
        est = recognizer.estimate(top_k, depth=depth)
        stamp = stamps_ns[i] if stamps_ns is not None else start_ns + i * period_ns
        yield "/sva/detections", stamp, detection_array(est, stamp, frame_id, detection_id=detection_id, boxes=boxes)
        pose = best_pose(est, stamp, frame_id)
        if pose is not None:
            yield "/sva/pose", stamp, pose
            yield "/tf", stamp, object_transform(est, stamp, frame_id)
        yield "/sva/touches", stamp, touch_markers(taken, stamp, frame_id)
        if meshes is not None:
            best = est.hypotheses[0].object if est.ready and est.hypotheses else -1
            mesh = meshes[best] if 0 <= best < len(meshes) else None
            if (best if mesh is not None else -1) != shown:
                yield "/sva/object", stamp, object_marker(est, mesh, stamp)
                shown = best if mesh is not None else -1


def scene_meshes(scene: "_core.Scene") -> list[ObjectMesh]:
    """Every object's mesh of a scene (sva.load_scene), as the simulator places it."""
    return [ObjectMesh(*scene.object_mesh(i)) for i in range(len(scene.object_names))]


from .bag import export_session, read_bag  # noqa: E402  (the writer needs the converters above)

__all__ = [
    "OBJECT_FRAME", "TOPICS", "ObjectBox", "ObjectMesh", "best_pose", "detection_array", "export_session", "header",
    "object_marker", "object_transform", "pose_with_covariance", "read_bag", "scene_meshes", "session_messages",
    "time_msg",
    "touch_markers",
]
