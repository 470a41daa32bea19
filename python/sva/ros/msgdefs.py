"""ROS 2 message definitions (Humble), as MCAP's ``ros2msg`` schemas carry them: the message's own text, then each
dependency after a line of ``=`` and ``MSG: package/Type``. Readers (Foxglove, ``ros2 bag``, mcap-ros2-support)
decode the bag from these texts alone, so no ROS installation is needed to write or read it.
"""

from __future__ import annotations

_SEP = "=" * 80

# Every type the exported topics use, by full name, without its dependencies.
_TEXT = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec",
    "builtin_interfaces/Duration": "int32 sec\nuint32 nanosec",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id",
    "std_msgs/ColorRGBA": "float32 r\nfloat32 g\nfloat32 b\nfloat32 a",
    "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/Quaternion": "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1",
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z",
    "geometry_msgs/Pose": "Point position\nQuaternion orientation",
    "geometry_msgs/PoseWithCovariance": "Pose pose\nfloat64[36] covariance",
    "geometry_msgs/PoseWithCovarianceStamped": "std_msgs/Header header\nPoseWithCovariance pose",
    "geometry_msgs/Transform": "Vector3 translation\nQuaternion rotation",
    "geometry_msgs/TransformStamped": "std_msgs/Header header\nstring child_frame_id\nTransform transform",
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms",
    "vision_msgs/ObjectHypothesis": "string class_id\nfloat64 score",
    "vision_msgs/ObjectHypothesisWithPose": "ObjectHypothesis hypothesis\ngeometry_msgs/PoseWithCovariance pose",
    "vision_msgs/BoundingBox3D": "geometry_msgs/Pose center\ngeometry_msgs/Vector3 size",
    "vision_msgs/Detection3D": (
        "std_msgs/Header header\nObjectHypothesisWithPose[] results\nBoundingBox3D bbox\nstring id"
    ),
    "vision_msgs/Detection3DArray": "std_msgs/Header header\nDetection3D[] detections",
    "sensor_msgs/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data",
    "visualization_msgs/UVCoordinate": "float32 u\nfloat32 v",
    "visualization_msgs/MeshFile": "string filename\nuint8[] data",
    "visualization_msgs/Marker": "\n".join(
        [
            "int32 ARROW=0",
            "int32 CUBE=1",
            "int32 SPHERE=2",
            "int32 CYLINDER=3",
            "int32 LINE_STRIP=4",
            "int32 LINE_LIST=5",
            "int32 CUBE_LIST=6",
            "int32 SPHERE_LIST=7",
            "int32 POINTS=8",
            "int32 TEXT_VIEW_FACING=9",
            "int32 MESH_RESOURCE=10",
            "int32 TRIANGLE_LIST=11",
            "int32 ADD=0",
            "int32 MODIFY=0",
            "int32 DELETE=2",
            "int32 DELETEALL=3",
            "std_msgs/Header header",
            "string ns",
            "int32 id",
            "int32 type",
            "int32 action",
            "geometry_msgs/Pose pose",
            "geometry_msgs/Vector3 scale",
            "std_msgs/ColorRGBA color",
            "builtin_interfaces/Duration lifetime",
            "bool frame_locked",
            "geometry_msgs/Point[] points",
            "std_msgs/ColorRGBA[] colors",
            "string texture_resource",
            "sensor_msgs/CompressedImage texture",
            "UVCoordinate[] uv_coordinates",
            "string text",
            "string mesh_resource",
            "MeshFile mesh_file",
            "bool mesh_use_embedded_materials",
        ]
    ),
    "visualization_msgs/MarkerArray": "Marker[] markers",
}

# The types each type's text names, fully qualified (a bare name is the same package's).
_BUILTIN = {"bool", "int32", "uint32", "uint8", "float32", "float64", "string"}


def _dependencies(name: str) -> list[str]:
    package = name.split("/")[0]
    out = []
    for line in _TEXT[name].splitlines():
        field_type = line.split()[0].split("[")[0]
        if field_type in _BUILTIN or "=" in line:
            continue
        full = field_type if "/" in field_type else f"{package}/{field_type}"
        if full not in out:
            out.append(full)
    return out


def definition(name: str) -> str:
    """The ``ros2msg`` schema text of ``name`` (e.g. ``vision_msgs/msg/Detection3DArray`` or
    ``vision_msgs/Detection3DArray``): its text, then every dependency once, depth first."""
    name = name.replace("/msg/", "/")
    if name not in _TEXT:
        raise KeyError(f"sva.ros: no message definition for {name}")
    order: list[str] = []

    def visit(n: str) -> None:
        for d in _dependencies(n):
            if d not in order:
                order.append(d)
                visit(d)

    visit(name)
    parts = [_TEXT[name]] + [f"{_SEP}\nMSG: {d}\n{_TEXT[d]}" for d in order]
    return "\n".join(parts) + "\n"
