// sva.Engine: a map with its backend chosen once (on Vulkan, the device and one uploaded copy of the map), shared
// by any number of sva.Recognizer(engine, ...) (docs/api.md, "Engines and sessions").
#include <sva/engine.hpp>

#include <nanobind/stl/string.h>

#include "bindings.hpp"
#include "recognizer_options.hpp"

namespace sva::python {

using namespace nb::literals;

void bind_engine(nb::module_& m) {
  nb::class_<Engine>(m, "Engine",
                     "A map and its backend, chosen once: recognizers made from one engine share the device and one "
                     "uploaded copy of the map (and the host map and fine-pose index on every backend).")
      .def(
          "__init__",
          [](Engine* e, const Map& map, const std::string& backend, const std::string& vulkan_device) {
            EngineOptions o;
            o.backend = to_backend(backend, "sva.Engine: backend");
            o.vulkan_device = vulkan_device;
            EngineScope scope;
            new (e) Engine(map, o);
          },
          "map"_a, "backend"_a = "auto", "vulkan_device"_a = "",
          "backend: 'auto' (a GPU where one is usable, else the CPU reference), 'cpu' or 'vulkan'.")
      .def_prop_ro("map", &Engine::map, "the engine's map (shares its memory)")
      .def_prop_ro(
          "backend", [](const Engine& e) { return std::string(backend_name(e.backend())); },
          "'cpu' or 'vulkan' (auto resolved)")
      .def_prop_ro("fallback_reason", &Engine::fallback_reason,
                   "with backend 'auto' on the CPU: why no Vulkan device was usable ('' otherwise)")
      .def_prop_ro("backend_description", &Engine::backend_description, "'cpu', or 'vulkan: DEVICE'")
      .def(
          "sessions_per_submission",
          [](const Engine& e, const nb::kwargs& options) {
            return e.sessions_per_submission(recognizer_options(options, "sva.Engine.sessions_per_submission"));
          },
          "options"_a, nb::sig("def sessions_per_submission(self, *, " RECOGNIZER_OPTIONS_SIG ") -> int"),
          "The sessions a BatchRecognizer on this engine steps together by default (sva.recognize_batch): on a GPU "
          "as many as half its memory holds with every belief at belief_budget_bins, shared by the groups in "
          "flight, 64 to 4096 each; 64 on the CPU.")
      .def("submissions_in_flight", &Engine::submissions_in_flight,
           "The groups of sessions sva.recognize_batch keeps in flight at once, one recognizer each: 2 on a GPU (the "
           "host prepares one group's update while the device runs another's), 1 on the CPU.")
      .def("__repr__", [](const Engine& e) { return "Engine(" + e.backend_description() + ")"; });
}

}  // namespace sva::python
