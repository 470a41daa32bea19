// sva.PoseSpaceSpec: the recognizer's pose space (docs/recognition.md), a box of translations and rotations.
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
      .def("__repr__", [](const PoseSpaceSpec& p) {
        return std::string("PoseSpaceSpec(kind=") + (p.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial") +
               ", translation_bins=" + std::to_string(p.translation_bins) +
               ", translation_min_mm=" + std::to_string(p.translation_min_mm) +
               ", translation_max_mm=" + std::to_string(p.translation_max_mm) +
               ", rotation_bins=" + std::to_string(p.rotation_bins) + ")";
      });
}

}  // namespace sva::python
