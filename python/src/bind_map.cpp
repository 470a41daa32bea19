// sva.Map: the SVA pair map (docs/map-format.md): load, save, train (sva.train), and what it holds.
#include <sva/map.hpp>

#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_map(nb::module_& m) {
  nb::class_<TrainReport>(m, "TrainReport", "What training did (sva.train(..., report=TrainReport())).")
      .def(nb::init<>())
      .def_ro("readings_used", &TrainReport::readings_used)
      .def_ro("readings_paired", &TrainReport::readings_paired)
      .def_ro("skipped_not_converged", &TrainReport::skipped_not_converged)
      .def_ro("skipped_undescribable", &TrainReport::skipped_undescribable)
      .def_ro("clustering_seconds", &TrainReport::clustering_seconds)
      .def_ro("map_build_seconds", &TrainReport::map_build_seconds)
      .def_ro("clustering_loss", &TrainReport::clustering_loss);
  nb::class_<Map>(m, "Map", "The SVA pair map (a .svam file): train it with sva.train, or load one.")
      .def(nb::init<>(), "An empty map (no recognizer accepts it).")
      .def_static(
          "load",
          [](const std::filesystem::path& file) {
            EngineScope scope(true);
            return Map::load(file);
          },
          "path"_a, "Load a .svam file (sva train).")
      .def(
          "save",
          [](const Map& map, const std::filesystem::path& file) {
            EngineScope scope(true);
            map.save(file);
          },
          "path"_a)
      .def_prop_ro("empty", &Map::empty)
      .def_prop_ro("objects", &Map::objects, "number of objects")
      .def_prop_ro("object_names", &Map::object_names)
      .def_prop_ro("classes", &Map::classes, "appearance classes")
      .def_prop_ro("entries", &Map::entries)
      .def_prop_ro("keys", &Map::keys)
      .def_prop_ro("readings", &Map::readings, "training readings used")
      .def_prop_ro("fine_pose_from", &Map::fine_pose_from,
                   "readings from which the fine pose and the surface check run (sva.train's fine_pose_from)")
      .def_prop_ro(
          "light_calibration_from", [](const Map& map) { return map.summary().calibration.light_from; },
          "readings from which light estimates (depth=\"light\") read their own calibration; 0: none (a map of format "
          "9 "
          "or older, or trained without calibration): retrain to give them one")
      .def_prop_ro("bytes", &Map::bytes, "in-memory size of the map's arrays (the objects' surfaces apart)")
      .def_prop_ro(
          "surface_objects", [](const Map& map) { return map.summary().surface_objects; },
          "objects whose mesh the map carries (sva.train's surfaces; 0: the verify stage reads the training contacts)")
      .def_prop_ro(
          "surface_bytes", [](const Map& map) { return map.summary().surface_bytes; },
          "bytes of the objects' meshes, apart from `bytes`")
      .def_prop_ro("scene_name", &Map::scene_name)
      .def_prop_ro("scene_hash", &Map::scene_hash)
      .def_prop_ro("pose_space", &Map::pose_space, "the pose space of the map's scene (a copy)")
      .def_prop_ro("sensor", &Map::sensor, "the tactile array the map was trained with (a copy)")
      .def_prop_ro(
          "rows", [](const Map& map) { return map.sensor().rows; },
          "the sensor's rows: readings' images are rows x cols")
      .def_prop_ro(
          "cols", [](const Map& map) { return map.sensor().cols; }, "the sensor's columns")
      .def("__repr__", [](const Map& map) {
        if (map.empty()) return std::string("Map(empty)");
        return "Map(scene='" + map.scene_name() + "', objects=" + std::to_string(map.objects()) +
               ", entries=" + std::to_string(map.entries()) + ")";
      });
}

}  // namespace sva::python
