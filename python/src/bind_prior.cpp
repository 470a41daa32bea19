// sva.Prior and sva.PosePrior: what the robot believed before touching (per object probabilities, and a Gaussian
// over each object's pose), given to Recognizer.set_prior. Values are checked by the engine when set (sva.Error).
#include <sva/prior.hpp>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstdio>
#include <string>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

nb::ndarray<nb::numpy, double, nb::shape<3, 3>> mat3_copy(const glm::dmat3& m) {
  auto* d = new double[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d[r * 3 + c] = m[c][r];
  nb::capsule owner(d, [](void* p) noexcept { delete[] static_cast<double*>(p); });
  return nb::ndarray<nb::numpy, double, nb::shape<3, 3>>(d, {3, 3}, owner);
}

std::vector<double> to_doubles(nb::handle obj, const char* what) {
  std::vector<double> out;
  if (obj.is_none()) return out;
  if (!nb::try_cast(obj, out))
    throw nb::type_error((std::string(what) + ": expected a sequence of numbers, got " +
                          nb::cast<std::string>(obj.type().attr("__name__")))
                             .c_str());
  return out;
}

void bind_pose_prior(nb::module_& m) {
  nb::class_<PosePrior>(m, "PosePrior",
                        "A Gaussian over one object's pose in the robot frame (a camera's detection): position "
                        "(mm) with position_sigma_mm, and optionally rotation (3x3) with rotation_sigma_rad.")
      .def(
          "__init__",
          [](PosePrior* p, nb::handle position, double position_sigma_mm, nb::handle rotation,
             double rotation_sigma_rad) {
            new (p) PosePrior{};
            p->position = to_vec3(position, "PosePrior.position");
            p->position_sigma_mm = position_sigma_mm;
            if (!rotation.is_none()) {
              p->has_rotation = true;
              p->rotation = to_mat3(rotation, "PosePrior.rotation");
              p->rotation_sigma_rad = rotation_sigma_rad;
            }
          },
          "position"_a, "position_sigma_mm"_a, "rotation"_a = nb::none(), "rotation_sigma_rad"_a = 0.0,
          nb::sig("def __init__(self, position: numpy.typing.ArrayLike, position_sigma_mm: float, rotation: "
                  "numpy.typing.ArrayLike | None = None, rotation_sigma_rad: float = 0.0) -> None"))
      .def_prop_ro(
          "position", [](const PosePrior& p) { return vec3_copy(p.position); }, nb::rv_policy::automatic,
          "mean position (a copy), mm")
      .def_ro("position_sigma_mm", &PosePrior::position_sigma_mm)
      .def_prop_ro(
          "rotation",
          [](const PosePrior& p) -> nb::object {
            if (!p.has_rotation) return nb::none();
            return nb::cast(mat3_copy(p.rotation), nb::rv_policy::automatic);
          },
          nb::rv_policy::automatic, "mean rotation (a copy), or None when the prior says nothing about the rotation")
      .def_ro("rotation_sigma_rad", &PosePrior::rotation_sigma_rad)
      .def("__repr__", [](const PosePrior& p) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "PosePrior(position=[%.3f, %.3f, %.3f], position_sigma_mm=%g%s)", p.position.x,
                      p.position.y, p.position.z, p.position_sigma_mm, p.has_rotation ? ", rotation=..." : "");
        return std::string(buf);
      });
}

}  // namespace

void bind_prior(nb::module_& m) {
  bind_pose_prior(m);
  nb::class_<Prior>(m, "Prior",
                    "A prior for Recognizer.set_prior: object_probability (per object id, any positive scale; None: "
                    "flat) and object_pose (per object id, a PosePrior or None; None: no pose prior).")
      .def(
          "__init__",
          [](Prior* p, nb::handle object_probability,
             std::optional<std::vector<std::optional<PosePrior>>> object_pose) {
            new (p) Prior{};
            p->object_probability = to_doubles(object_probability, "Prior.object_probability");
            if (object_pose) p->object_pose = std::move(*object_pose);
          },
          "object_probability"_a = nb::none(), "object_pose"_a = nb::none(),
          nb::sig("def __init__(self, object_probability: numpy.typing.ArrayLike | None = None, object_pose: "
                  "collections.abc.Sequence[PosePrior | None] | None = None) -> None"))
      .def_prop_ro(
          "object_probability", [](const Prior& p) { return doubles_copy(p.object_probability); },
          nb::rv_policy::automatic, "per object (a copy; empty: flat)")
      .def_ro("object_pose", &Prior::object_pose, "per object: a PosePrior or None (empty: none)")
      .def("__repr__", [](const Prior& p) {
        return "Prior(objects=" + std::to_string(p.object_probability.size()) +
               ", pose_priors=" + std::to_string(p.object_pose.size()) + ")";
      });
  m.def("pose_space_around", &pose_space_around, "grid"_a, "prior"_a, "sigmas"_a = 3.0,
        "The pose space's box placed around a pose prior: centred on its mean position, half side `sigmas` position "
        "sigmas, turned by its mean rotation when it has one.");
}

}  // namespace sva::python
