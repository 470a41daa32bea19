// sva.RigidPose: x_world = R x_object + T (mm), R and T as NumPy views of the pose (writable: they are the pose).
#include <sva/pose.hpp>

#include <nanobind/stl/string.h>

#include <cstdio>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_pose(nb::module_& m) {
  nb::class_<RigidPose>(m, "RigidPose",
                        "A rigid pose: x_world = R @ x_object + T (millimetres). R (3x3) and T (3,) are NumPy views "
                        "of the pose itself.")
      .def(nb::init<>(), "The identity.")
      .def(
          "__init__",
          [](RigidPose* p, nb::handle R, nb::handle T) {
            new (p) RigidPose{to_mat3(R, "RigidPose.R"), to_vec3(T, "RigidPose.T")};
          },
          "R"_a, "T"_a, nb::sig("def __init__(self, R: numpy.typing.ArrayLike, T: numpy.typing.ArrayLike) -> None"))
      .def_prop_rw(
          "R", [](RigidPose& p) { return mat3_view(p.R); },
          [](RigidPose& p, nb::handle R) { p.R = to_mat3(R, "RigidPose.R"); }, nb::rv_policy::reference_internal,
          nb::for_setter(nb::sig("def R(self, arg: numpy.typing.ArrayLike, /) -> None")), "rotation (3x3)")
      .def_prop_rw(
          "T", [](RigidPose& p) { return vec3_view(p.T); },
          [](RigidPose& p, nb::handle T) { p.T = to_vec3(T, "RigidPose.T"); }, nb::rv_policy::reference_internal,
          nb::for_setter(nb::sig("def T(self, arg: numpy.typing.ArrayLike, /) -> None")), "translation (3,), mm")
      .def(
          "matrix",
          [](const RigidPose& p) {
            auto* h = new double[16]{};
            for (int r = 0; r < 3; ++r) {
              for (int c = 0; c < 3; ++c) h[r * 4 + c] = p.R[c][r];
              h[r * 4 + 3] = p.T[r];
            }
            h[15] = 1.0;
            nb::capsule owner(h, [](void* q) noexcept { delete[] static_cast<double*>(q); });
            return nb::ndarray<nb::numpy, double, nb::shape<4, 4>>(h, {4, 4}, owner);
          },
          "The 4x4 homogeneous matrix (a copy).")
      .def("inverse", &RigidPose::inverse)
      .def(
          "apply", [](const RigidPose& p, nb::handle x) { return vec3_copy(p.apply(to_vec3(x, "RigidPose.apply"))); },
          "x"_a, nb::sig("def apply(self, x: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]"),
          "R @ x + T for one point x (3,).")
      .def("__mul__", [](const RigidPose& a, const RigidPose& b) { return a * b; })
      .def("__repr__", [](const RigidPose& p) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "RigidPose(T=[%.3f, %.3f, %.3f] mm)", p.T.x, p.T.y, p.T.z);
        return std::string(buf);
      });
}

}  // namespace sva::python
