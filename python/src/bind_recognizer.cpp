// sva.Recognizer, sva.Estimate, sva.Hypothesis: feed readings one at a time, read the estimate; a prior, saving and
// restoring the session, and recognizers sharing one sva.Engine. Options are keyword arguments with
// RecognizerOptions' names; the GIL is released during updates, estimates and restores.
#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <mutex>

#include <algorithm>

#include "bindings.hpp"
#include "recognizer_options.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

// A Recognizer with a lock: Python threads may share one (the engine's object is not thread-safe, so calls on
// one recognizer take turns; different recognizers run in parallel, the GIL released).
struct PyRecognizer {
  PyRecognizer(const Map& map, const PoseSpaceSpec& space, const RecognizerOptions& options)
      : rec(map, space, options) {}
  PyRecognizer(const Engine& engine, const PoseSpaceSpec& space, const RecognizerOptions& options)
      : rec(engine, space, options) {}
  Recognizer rec;
  mutable std::mutex mutex;
};

void bind_estimate(nb::module_& m) {
  nb::class_<Hypothesis>(m, "Hypothesis", "A pose bin of the belief: object, pose (bin centre) and posterior mass.")
      .def_ro("object", &Hypothesis::object)
      .def_ro("object_name", &Hypothesis::object_name)
      .def_rw("pose", &Hypothesis::pose)
      .def_ro("probability", &Hypothesis::probability)
      .def("__repr__", [](const Hypothesis& h) {
        return "Hypothesis(object='" + h.object_name + "', probability=" + std::to_string(h.probability) + ")";
      });
  nb::class_<PoseHypothesis>(m, "PoseHypothesis",
                             "A distinct mode of the belief: object, pose, posterior mass and a 6x6 covariance in "
                             "ROS PoseWithCovariance order (x, y, z in mm; rotation about X, Y, Z in rad).")
      .def_ro("object", &PoseHypothesis::object)
      .def_ro("object_name", &PoseHypothesis::object_name)
      .def_rw("pose", &PoseHypothesis::pose)
      .def_ro("probability", &PoseHypothesis::probability)
      .def_ro("valid", &PoseHypothesis::valid, "false for an object no vote has reached (object_hypotheses)")
      .def_prop_ro(
          "covariance",
          [](const PoseHypothesis& h) {
            auto* d = new double[36];
            std::copy(h.covariance.begin(), h.covariance.end(), d);
            nb::capsule owner(d, [](void* p) noexcept { delete[] static_cast<double*>(p); });
            return nb::ndarray<nb::numpy, double, nb::shape<6, 6>>(d, {6, 6}, owner);
          },
          nb::rv_policy::take_ownership, "6x6 NumPy array (a copy), row-major, ROS order")
      .def("__repr__", [](const PoseHypothesis& h) {
        return "PoseHypothesis(object='" + h.object_name + "', probability=" + std::to_string(h.probability) + ")";
      });
  nb::class_<Estimate>(m, "Estimate", "The recognizer's belief after the readings so far.")
      .def_ro("readings", &Estimate::readings, "readings seen so far")
      .def_ro("object", &Estimate::object, "the object with the most mass summed over poses")
      .def_ro("object_name", &Estimate::object_name)
      .def_prop_ro(
          "object_probability", [](const Estimate& e) { return doubles_copy(e.object_probability); },
          nb::rv_policy::automatic, "per object, sums to 1 (a NumPy array)")
      .def_rw("pose", &Estimate::pose, "continuous pose of `object` (the fine pose when refined)")
      .def_rw("parabolic_pose", &Estimate::parabolic_pose)
      .def_rw("bin_pose", &Estimate::bin_pose)
      .def_ro("pose_refined", &Estimate::pose_refined)
      .def_ro("pose_valid", &Estimate::pose_valid, "false until a pair has voted")
      .def_ro("top", &Estimate::top, "best bins, most probable first")
      .def_ro("hypotheses", &Estimate::hypotheses, "distinct modes after non-maximum suppression, most probable first")
      .def_ro("object_hypotheses", &Estimate::object_hypotheses, "each object's best mode, in object order")
      .def_ro("votes", &Estimate::votes)
      .def_ro("votes_outside", &Estimate::votes_outside)
      .def_ro("votes_zero", &Estimate::votes_zero)
      .def("__repr__", [](const Estimate& e) {
        return "Estimate(readings=" + std::to_string(e.readings) + ", object='" + e.object_name +
               "', pose_valid=" + (e.pose_valid ? "True" : "False") + ")";
      });
}

// With an engine, the backend and device are the engine's: asking for them again is a mistake worth naming.
RecognizerOptions engine_recognizer_options(const nb::kwargs& options) {
  for (const char* key : {"backend", "vulkan_device"})
    if (options.contains(key))
      throw Error(std::string("sva.Recognizer: ") + key +
                  " comes from the engine when one is given (make the Engine with it)");
  return recognizer_options(options, "sva.Recognizer");
}

void bind_session(nb::class_<PyRecognizer>& c) {
  c.def(
       "set_prior",
       [](PyRecognizer& r, const Prior& prior) {
         std::lock_guard lock(r.mutex);
         r.rec.set_prior(prior);
       },
       "prior"_a,
       "A prior for this session (sva.Prior), replacing any earlier one; it enters at estimate time. sva.Error when it "
       "does not fit the map.")
      .def(
          "save_session",
          [](const PyRecognizer& r, const std::filesystem::path& file) {
            EngineScope scope;
            std::lock_guard lock(r.mutex);
            r.rec.save_session(file);
          },
          "path"_a, "Saves the readings so far and the object prior to a small file (restore_session resumes).")
      .def(
          "restore_session",
          [](PyRecognizer& r, const std::filesystem::path& file) {
            EngineScope scope(true);
            std::lock_guard lock(r.mutex);
            r.rec.restore_session(file);
          },
          "path"_a,
          "Replaces this session by a saved one (its belief rebuilt bit for bit); sva.Error naming the file when it "
          "cannot be read or was saved with another map.");
}

}  // namespace

void bind_recognizer(nb::module_& m) {
  bind_estimate(m);
  auto c = nb::class_<PyRecognizer>(m, "Recognizer",
                                    "Recognition of one object from a stream of readings against a map (one session).");
  c.def(
       "__init__",
       [](PyRecognizer* self, const Map& map, const std::optional<PoseSpaceSpec>& pose_space,
          const nb::kwargs& options) {
         const RecognizerOptions o = recognizer_options(options, "sva.Recognizer");
         EngineScope scope;
         new (self) PyRecognizer(map, pose_space ? *pose_space : map.pose_space(), o);
       },
       "map"_a, "pose_space"_a = nb::none(), "options"_a, nb::keep_alive<1, 2>(),
       nb::sig("def __init__(self, map: Map, pose_space: PoseSpaceSpec | None = None, *, " RECOGNIZER_OPTIONS_SIG
               ") -> None"),
       "pose_space defaults to the map's; options as RecognizerOptions (docs/recognition.md).")
      .def(
          "__init__",
          [](PyRecognizer* self, const Engine& engine, const std::optional<PoseSpaceSpec>& pose_space,
             const nb::kwargs& options) {
            const RecognizerOptions o = engine_recognizer_options(options);
            EngineScope scope;
            new (self) PyRecognizer(engine, pose_space ? *pose_space : engine.map().pose_space(), o);
          },
          "engine"_a, "pose_space"_a = nb::none(), "options"_a,
          nb::sig("def __init__(self, engine: Engine, pose_space: PoseSpaceSpec | None = None, *, "
                  "method: str = 'sva', eps: float = 1e-06, likelihood_cutoff: float = 0.0, "
                  "object_prune_probability: float = 0.0, max_pairs_per_update: int = 0, refine_pose: bool = True, "
                  "threads: int = 0) -> None"),
          "A recognizer sharing `engine` (its map, backend and device; the engine is kept alive).")
      .def(
          "add_reading",
          [](PyRecognizer& r, const Reading& reading) {
            EngineScope scope;
            std::lock_guard lock(r.mutex);
            r.rec.add_reading(reading);
          },
          "reading"_a,
          "Adds one reading (robot frame) and updates the belief; refuses readings that are not converged or cannot "
          "be described (sva.Error).")
      .def(
          "estimate",
          [](const PyRecognizer& r, std::size_t top_k) {
            EngineScope scope;
            std::lock_guard lock(r.mutex);
            return r.rec.estimate(top_k);
          },
          "top_k"_a = 5)
      .def(
          "reset",
          [](PyRecognizer& r) {
            EngineScope scope;
            std::lock_guard lock(r.mutex);
            r.rec.reset();
          },
          "Forgets the readings and the prior: a fresh session (the belief's memory is kept for the next one).")
      .def("readings", [](const PyRecognizer& r) {
        std::lock_guard lock(r.mutex);
        return r.rec.readings();
      });
  bind_session(c);
}

}  // namespace sva::python
