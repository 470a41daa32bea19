// The extension module sva._sva_core; the package `sva` (python/sva/__init__.py) re-exports it.
#include "bindings.hpp"

NB_MODULE(_sva_core, m) {
  using namespace sva::python;
  m.doc() = "sva: tactile object recognition and localization by spatially-varying appearance (C++ engine).";
  m.attr("__version__") = SVA_VERSION;
  bind_errors(m);
  bind_pose(m);
  bind_pose_space(m);
  bind_scene(m);
  bind_reading(m);
  bind_dataset(m);
  bind_map(m);
  bind_engine(m);
  bind_prior(m);
  bind_recognizer(m);
  bind_batch_recognizer(m);
  bind_workflow(m);
  bind_touch_planner(m);
  bind_sessions(m);
}
