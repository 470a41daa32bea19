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

template <std::size_t N>
nb::ndarray<nb::numpy, double> owned_doubles(const std::array<double, N>& values,
                                             std::initializer_list<std::size_t> shape) {
  auto* d = new std::array<double, N>(values);
  nb::capsule owner(d, [](void* p) noexcept { delete static_cast<std::array<double, N>*>(p); });
  return nb::ndarray<nb::numpy, double>(d->data(), shape, owner);
}

// sva::to_ros as three NumPy arrays: position (3,) m, orientation (4,) x y z w, covariance (6, 6) ROS order.
nb::tuple ros_tuple(const PoseHypothesis& h) {
  const RosPose r = to_ros(h);
  return nb::make_tuple(owned_doubles(r.position, {3}), owned_doubles(r.orientation, {4}),
                        owned_doubles(r.covariance, {6, 6}));
}

// Before the first reading the estimate names no object (sva::Estimate::ready): None, not a placeholder id.
nb::object if_ready(const Estimate& e, nb::object value) { return e.ready ? value : nb::none(); }

void bind_hypotheses(nb::module_& m) {
  nb::class_<Hypothesis>(m, "Hypothesis", "A pose bin of the belief: object, pose (bin centre) and posterior mass.")
      .def_ro("object", &Hypothesis::object, "object id (index into Map.object_names)")
      .def_ro("object_name", &Hypothesis::object_name, "the object's name")
      .def_rw("pose", &Hypothesis::pose, "the bin's pose of the object, robot frame (x_robot = R x_object + T, mm)")
      .def_ro("probability", &Hypothesis::probability, "posterior mass of this bin (0 to 1)")
      .def("__repr__", [](const Hypothesis& h) {
        return "Hypothesis(object='" + h.object_name + "', probability=" + std::to_string(h.probability) + ")";
      });
  nb::class_<PoseHypothesis>(m, "PoseHypothesis",
                             "A distinct mode of the belief: object, pose, posterior mass and a 6x6 covariance in "
                             "ROS PoseWithCovariance order (x, y, z in mm; rotation about X, Y, Z in rad).")
      .def_ro("object", &PoseHypothesis::object, "object id (index into Map.object_names)")
      .def_ro("object_name", &PoseHypothesis::object_name, "the object's name")
      .def_rw("pose", &PoseHypothesis::pose, "the mode's pose of the object, robot frame (mm)")
      .def_ro("probability", &PoseHypothesis::probability, "posterior mass of the mode (0 to 1)")
      .def_ro("valid", &PoseHypothesis::valid, "false for an object no vote has reached (object_hypotheses)")
      .def_prop_ro(
          "covariance",
          [](const PoseHypothesis& h) {
            auto* d = new double[36];
            std::copy(h.covariance.begin(), h.covariance.end(), d);
            nb::capsule owner(d, [](void* p) noexcept { delete[] static_cast<double*>(p); });
            return nb::ndarray<nb::numpy, double, nb::shape<6, 6>>(d, {6, 6}, owner);
          },
          nb::rv_policy::take_ownership, "6x6 NumPy array (a copy), row-major, ROS order (mm and rad)")
      .def("to_ros", &ros_tuple,
           nb::sig("def to_ros(self) -> tuple[numpy.typing.NDArray[numpy.float64], "
                   "numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]"),
           "(position, orientation, covariance) for geometry_msgs/PoseWithCovariance: position (3,) in metres, "
           "orientation (4,) a unit quaternion x, y, z, w (w >= 0), covariance (6, 6) in ROS order (x, y, z in m; "
           "rotation about X, Y, Z in rad). docs/api.md, \"Mapping an Estimate onto vision_msgs/Detection3D\".")
      .def("__repr__", [](const PoseHypothesis& h) {
        return "PoseHypothesis(object='" + h.object_name + "', probability=" + std::to_string(h.probability) + ")";
      });
}

void bind_evidence(nb::module_& m) {
  nb::class_<ObjectEvidence>(m, "ObjectEvidence",
                             "What Estimate.object_probability is made of, per object id: proportional to 2 ** "
                             "(temperature * pairs_log2_mass + surface_weight * surface_log2_fit) times the prior, "
                             "then the calibration's top label (docs/recognition.md, \"What the posterior is made "
                             "of\").")
      .def_prop_ro(
          "pairs_log2_mass", [](const ObjectEvidence& e) { return doubles_copy(e.pairs_log2_mass); },
          nb::rv_policy::automatic,
          "the pairs' votes: log2 of each object's mass over poses, relative to the belief's best bin (a NumPy array; "
          "empty before the first reading)")
      .def_prop_ro(
          "surface_log2_fit", [](const ObjectEvidence& e) { return doubles_copy(e.surface_log2_fit); },
          nb::rv_policy::automatic,
          "the surface check's bits per object (the leading ones fitted, the others at the worst of theirs; a NumPy "
          "array, empty when the check did not run)")
      .def_ro("temperature", &ObjectEvidence::temperature, "the calibration's temperature at this reading count")
      .def_ro("surface_weight", &ObjectEvidence::surface_weight, "the calibration's weight of surface_log2_fit");
}

void bind_estimate(nb::module_& m) {
  bind_hypotheses(m);
  bind_evidence(m);
  nb::class_<Estimate>(m, "Estimate", "The recognizer's belief after the readings so far.")
      .def_ro("ready", &Estimate::ready,
              "False before the first reading: no answer yet (object and object_name are None, object_probability "
              "is the prior, the poses are the identity, top and the hypotheses are empty)")
      .def_ro("readings", &Estimate::readings, "readings seen so far")
      .def_prop_ro(
          "object", [](const Estimate& e) { return if_ready(e, nb::cast(e.object)); },
          nb::sig("def object(self) -> int | None"),
          "id of the object with the most mass summed over poses (None before the first reading)")
      .def_prop_ro(
          "object_name", [](const Estimate& e) { return if_ready(e, nb::cast(e.object_name)); },
          nb::sig("def object_name(self) -> str | None"), "that object's name (None before the first reading)")
      .def_prop_ro(
          "object_probability", [](const Estimate& e) { return doubles_copy(e.object_probability); },
          nb::rv_policy::automatic,
          "per object, sums to 1: the posterior given that the object is one of the map's (calibrated unless "
          "calibrate=False; a NumPy array)")
      .def_ro("p_unknown", &Estimate::p_unknown,
              "the probability that the touched object is none of the map's: object o has (1 - p_unknown) * "
              "object_probability[o] (docs/recognition.md, \"None of these\")")
      .def_ro("evidence", &Estimate::evidence, "what object_probability is made of (sva.ObjectEvidence)")
      .def_rw("pose", &Estimate::pose, "continuous pose of `object` (the fine pose when refined)")
      .def_rw("parabolic_pose", &Estimate::parabolic_pose,
              "the histogram's pose of `object`: the parabolic peak of the log-belief at its best bin")
      .def_rw("bin_pose", &Estimate::bin_pose,
              "the centre of `object`'s best pose bin (robot frame; the pose space's resolution)")
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
          "path"_a,
          "Saves the readings so far and the object prior to a small file (restore_session resumes); sva.Error "
          "naming the path for an empty name, a folder, or a folder that does not exist (none is created).")
      .def(
          "restore_session",
          [](PyRecognizer& r, const std::filesystem::path& file) {
            EngineScope scope(true);
            std::lock_guard lock(r.mutex);
            r.rec.restore_session(file);
          },
          "path"_a,
          "Replaces this session by a saved one (its belief rebuilt bit for bit); sva.Error naming the file when it "
          "cannot be read or was saved with another map.")
      .def(
          "reading_count",
          [](const PyRecognizer& r) {
            std::lock_guard lock(r.mutex);
            return r.rec.reading_count();
          },
          "How many readings the session holds (0 after reset()).")
      .def(
          "readings",
          [](const PyRecognizer& r) {
            if (PyErr_WarnEx(PyExc_DeprecationWarning, "Recognizer.readings() is deprecated: use reading_count()", 1))
              throw nb::python_error();
            std::lock_guard lock(r.mutex);
            return r.rec.reading_count();
          },
          "Deprecated: reading_count().");
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
          [](const PyRecognizer& r, std::size_t top_k, const std::string& depth) {
            const EstimateDepth d = parse_estimate_depth(depth, "Recognizer.estimate: depth");
            EngineScope scope;
            std::lock_guard lock(r.mutex);
            return r.rec.estimate(top_k, d);
          },
          "top_k"_a = 5, "depth"_a = "full",
          "The belief after the readings so far (sva.Estimate): the object posterior, the best object's pose, the "
          "top_k best bins (top) and distinct modes (hypotheses). Before the first reading est.ready is False and "
          "est.object is None: there is no answer yet. depth=\"light\": the belief's answer without the host's fits "
          "(the parabolic pose, no surface check; docs/recognition.md, \"Light and full estimates\"), for an answer "
          "after every touch.")
      .def(
          "reset",
          [](PyRecognizer& r) {
            EngineScope scope;
            std::lock_guard lock(r.mutex);
            r.rec.reset();
          },
          "Forgets the readings and the prior: a fresh session (the belief's memory is kept for the next one).");
  bind_session(c);
}

}  // namespace sva::python
