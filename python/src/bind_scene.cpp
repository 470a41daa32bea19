// sva.Scene, sva.SensorSpec, sva.load_scene: the objects, sensor and pose space a dataset was made of, and where the
// built-in scenes live (sva.assets_dir; the package registers the assets inside its wheel with set_assets_dir).
#include <sva/scene.hpp>

#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"

#if __has_include(<sva/sim/mesh.hpp>)
#include <sva/sim/mesh.hpp>
#define SVA_HAVE_SIM_MESH 1
#endif

#include <nanobind/stl/tuple.h>

namespace sva::python {

using namespace nb::literals;

namespace {

#ifdef SVA_HAVE_SIM_MESH
// A new NumPy (n, 3) array of `values` (3 per row), owning its copy.
template <class T>
nb::ndarray<nb::numpy, T, nb::shape<-1, 3>> rows3(std::vector<T> values) {
  auto* data = new std::vector<T>(std::move(values));
  nb::capsule owner(data, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::ndarray<nb::numpy, T, nb::shape<-1, 3>>(data->data(), {data->size() / 3, 3}, owner);
}

// Object `i`'s mesh as the simulator sees it: fitted to the scene's size and centre (mm, object frame).
std::tuple<nb::ndarray<nb::numpy, float, nb::shape<-1, 3>>, nb::ndarray<nb::numpy, std::uint32_t, nb::shape<-1, 3>>>
object_mesh(const Scene& s, std::size_t i) {
  if (i >= s.objects.size())
    throw nb::index_error(("Scene.object_mesh: object " + std::to_string(i) + " out of range (" +
                           std::to_string(s.objects.size()) + " objects)")
                              .c_str());
  sim::Mesh mesh;
  {
    nb::gil_scoped_release release;
    mesh = sim::load_object_mesh(s.objects[i]);
  }
  std::vector<float> v;
  for (const glm::vec3& p : mesh.positions) v.insert(v.end(), {p.x, p.y, p.z});
  std::vector<std::uint32_t> t;
  for (const glm::uvec3& f : mesh.triangles) t.insert(t.end(), {f.x, f.y, f.z});
  return {rows3(std::move(v)), rows3(std::move(t))};
}
#endif

}  // namespace

void bind_scene(nb::module_& m) {
  nb::class_<SensorSpec>(m, "SensorSpec", "Geometry of the tactile array (square elements, row-major image).")
      .def(nb::init<>())
      .def_rw("rows", &SensorSpec::rows)
      .def_rw("cols", &SensorSpec::cols)
      .def_rw("pitch_mm", &SensorSpec::pitch_mm)
      .def_prop_ro("elements", &SensorSpec::elements);
  nb::class_<Scene>(m, "Scene", "A scene: objects, sensor, pose space, appearance defaults and protocol.")
      .def_ro("name", &Scene::name)
      .def_ro("file", &Scene::file)
      .def_prop_ro(
          "object_names",
          [](const Scene& s) {
            std::vector<std::string> names;
            for (const auto& o : s.objects) names.push_back(o.name);
            return names;
          },
          "names of the objects, in id order")
      .def_prop_ro(
          "meshes",
          [](const Scene& s) {
            std::vector<std::filesystem::path> meshes;
            for (const auto& o : s.objects) meshes.push_back(o.mesh);
            return meshes;
          },
          "mesh file of each object, in id order")
#ifdef SVA_HAVE_SIM_MESH
      .def("object_mesh", &object_mesh, "object"_a,
           "(vertices, triangles) of object `object` as the simulator places it: vertices (n, 3) float32 in mm in "
           "the object's frame (scaled and centred as the scene says), triangles (m, 3) uint32, counter-clockwise "
           "seen from outside.")
#endif
      .def_rw("sensor", &Scene::sensor)
      .def_rw("pose_space", &Scene::pose_space)
      .def("to_json", &scene_to_json, "The scene as JSON text (mesh paths absolute).")
      .def("__repr__", [](const Scene& s) {
        return "Scene(name='" + s.name + "', objects=" + std::to_string(s.objects.size()) + ")";
      });
  m.def("load_scene", &load_scene, "name_or_file"_a,
        "A scene file, or a built-in scene by name (paper3d, letters2d, tiny, household10|25|50).");
  m.def("parse_scene", &parse_scene, "json_text"_a, "origin"_a,
        "A scene from JSON text; `origin` names it in errors and relative mesh paths resolve against its directory.");
  m.def("assets_dir", &assets_dir, "Directory of the built-in assets (env SVA_ASSETS overrides).");
  m.def("_set_assets_dir", &set_assets_dir, "dir"_a);
}

}  // namespace sva::python
