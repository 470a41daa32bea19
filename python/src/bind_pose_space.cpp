// sva.PoseSpaceSpec: the recognizer's pose space (docs/recognition.md), a box of translations and rotations, and
// its workspace frame (where the box lies in the robot frame: sva.placed_pose_space).
#include <sva/pose_space.hpp>
#include <sva/scene.hpp>

#include <nanobind/stl/string.h>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_pose_space(nb::module_& m) {
  nb::enum_<PoseSpaceSpec::Kind>(m, "PoseSpaceKind")
      .value("spatial", PoseSpaceSpec::Kind::spatial, "6-DOF: translation xyz, Rodrigues rotation xyz")
      .value("planar", PoseSpaceSpec::Kind::planar, "x, y and the angle about z");
  nb::class_<PoseSpaceSpec>(m, "PoseSpaceSpec", "The pose space of recognition: bins over translation and rotation.")
      .def(
          "__init__",
          [](PoseSpaceSpec* p, PoseSpaceSpec::Kind kind, int translation_bins, double translation_min_mm,
             double translation_max_mm, int rotation_bins) {
            new (p) PoseSpaceSpec{kind, translation_bins, translation_min_mm, translation_max_mm, rotation_bins};
          },
          "kind"_a = PoseSpaceSpec::Kind::spatial, "translation_bins"_a = 50, "translation_min_mm"_a = -200.0,
          "translation_max_mm"_a = 200.0, "rotation_bins"_a = 9)
      .def_rw("kind", &PoseSpaceSpec::kind)
      .def_rw("translation_bins", &PoseSpaceSpec::translation_bins)
      .def_rw("translation_min_mm", &PoseSpaceSpec::translation_min_mm)
      .def_rw("translation_max_mm", &PoseSpaceSpec::translation_max_mm)
      .def_rw("rotation_bins", &PoseSpaceSpec::rotation_bins, "per Rodrigues axis (planar: over [-pi, pi])")
      .def_rw("workspace", &PoseSpaceSpec::workspace,
              "where the box lies in the robot frame (x_robot = workspace.apply(x_box)); identity by default")
      .def("__repr__", [](const PoseSpaceSpec& p) {
        return std::string("PoseSpaceSpec(kind=") + (p.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial") +
               ", translation_bins=" + std::to_string(p.translation_bins) +
               ", translation_min_mm=" + std::to_string(p.translation_min_mm) +
               ", translation_max_mm=" + std::to_string(p.translation_max_mm) +
               ", rotation_bins=" + std::to_string(p.rotation_bins) + ")";
      });
  m.def(
      "placed_pose_space",
      [](const PoseSpaceSpec& grid, nb::handle centre, double half_extent_mm, nb::handle rotation) {
        return placed_pose_space(
            grid, to_vec3(centre, "placed_pose_space: centre"), half_extent_mm,
            rotation.is_none() ? glm::dmat3(1.0) : to_mat3(rotation, "placed_pose_space: rotation"));
      },
      "grid"_a, "centre"_a, "half_extent_mm"_a, "rotation"_a = nb::none(),
      nb::sig("def placed_pose_space(grid: PoseSpaceSpec, centre: numpy.typing.ArrayLike, half_extent_mm: float, "
              "rotation: numpy.typing.ArrayLike | None = None) -> PoseSpaceSpec"),
      "The grid of `grid`, its box a cube of half side half_extent_mm centred on `centre` (robot frame, mm) and "
      "turned by `rotation`.");
}

}  // namespace sva::python
