#include <sva/eval/evaluation.hpp>

#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <sva/base/parallel.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/engine.hpp>

#include "backends/vote_backend_factory.hpp"
#include "eval/active_trials.hpp"
#include "eval/metrics.hpp"
#include "eval/surface_errors.hpp"
#include "eval/trial_runner.hpp"
#include "map/map_access.hpp"
#include "map/pair_map.hpp"

namespace sva::eval {

namespace {

class RecognizerSession final : public Session {
 public:
  RecognizerSession(const Map& map, const RecognizerOptions& options, EstimateDepth depth)
      : recognizer_(map, map.pose_space(), options), depth_(depth) {}
  RecognizerSession(const Engine& engine, const RecognizerOptions& options, EstimateDepth depth)
      : recognizer_(engine, engine.map().pose_space(), options), depth_(depth) {}
  void add_reading(const Reading& reading) override { recognizer_.add_reading(reading); }
  Estimate estimate() const override { return recognizer_.estimate(1, depth_); }
  Estimate estimate_top(std::size_t top_k) const override {
    return recognizer_.estimate(std::max<std::size_t>(top_k, 1), depth_);
  }
  void reset() override { recognizer_.reset(); }

 private:
  Recognizer recognizer_;
  EstimateDepth depth_;
};

class RecognizerBatch final : public SessionBatch {
 public:
  RecognizerBatch(const Map& map, std::size_t sessions, const RecognizerOptions& options, EstimateDepth depth)
      : batch_(map, map.pose_space(), sessions, options), depth_(depth) {}
  std::size_t size() const override { return batch_.sessions(); }
  void add_readings(std::span<const std::size_t> sessions, std::span<const Reading> readings) override {
    batch_.add_readings(sessions, readings);
  }
  std::vector<Estimate> estimates(std::span<const std::size_t> sessions) const override {
    return batch_.estimates(sessions, 1, depth_);
  }
  void reset() override {
    for (std::size_t s = 0; s < batch_.sessions(); ++s) batch_.reset(s);
  }
  const BatchRecognizer& recognizer() const { return batch_; }

 private:
  BatchRecognizer batch_;
  EstimateDepth depth_;
};

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The adaptive policies: every trial steps on its own (the next reading depends on the estimate), each worker with a
// recognizer of one engine (auto resolved once, the map held once).
EvalResult run_active(const Map& map, const Dataset& test, TrialSetup setup, const EvalOptions& options) {
  RecognizerOptions ro = options.recognizer;
  if (ro.method == Method::appearance) ro.backend = BackendKind::cpu;
  EngineOptions eo;
  eo.backend = ro.backend;
  eo.vulkan_device = ro.vulkan_device;
  const Engine engine(map, eo);
  setup.backend = backend_name(engine.backend());
  if (engine.backend() == BackendKind::cpu && options.trials > 1) ro.threads = 1;  // trials occupy the cores
  const TouchPlanner planner(map);
  ActiveSetup active = options.active;
  active.policy = options.policy;
  EvalResult r = run_trials_active(
      test, setup, [&] { return std::make_unique<RecognizerSession>(engine, ro, options.estimate); }, planner, active);
  r.device = engine.backend_description();
  r.backend_fallback_reason = engine.fallback_reason();
  return r;
}

}  // namespace

const char* backend_name(BackendKind backend) { return backend_kind_name(backend); }
const char* method_name(Method method) { return method == Method::appearance ? "appearance" : "sva"; }

std::vector<std::int32_t> map_objects_of(const Map& map, const Dataset& test) {
  const auto names = map.object_names();
  std::vector<std::int32_t> out;
  for (const auto& o : test.scene.objects) {
    const auto it = std::find(names.begin(), names.end(), o.name);
    out.push_back(it == names.end() ? -1 : static_cast<std::int32_t>(it - names.begin()));
  }
  return out;
}

std::string light_calibration_warning(const Map& map, const std::string& map_name, EstimateDepth depth,
                                      bool calibrate) {
  const MapSummary::Calibration c = map.summary().calibration;
  if (depth != EstimateDepth::light || !calibrate || !c.learned || c.light_from != 0) return "";
  return "the map " + map_name +
         " has no light calibration (map format 9 or older): light estimates from the fine pose's first reading on "
         "read the full calibration's evidence regime, which is underconfident among near-twins; retrain it (sva "
         "train) to give them their own";
}

void check_compatible(const Map& map, const Dataset& test, const std::string& map_name, const std::string& data_name,
                      bool unknown_objects) {
  const std::string both = "the map " + map_name + " and the test set " + data_name;
  if (map.scene_name() != test.scene.name)
    throw Error(both + " come from different scenes (\"" + map.scene_name() + "\" and \"" + test.scene.name + "\")");
  const auto names = map.object_names();
  std::vector<std::string> test_names;
  for (const auto& o : test.scene.objects) test_names.push_back(o.name);
  if (unknown_objects) {
    const std::vector<std::int32_t> in_map = map_objects_of(map, test);
    std::vector<std::string> missing;
    for (const auto& n : names)
      if (std::find(test_names.begin(), test_names.end(), n) == test_names.end()) missing.push_back(n);
    if (!missing.empty())
      throw Error(both + ": the map's objects [" + join(missing) + "] are not in the test set (--unknown-objects " +
                  "needs the map's objects among the test set's)");
  } else if (names != test_names) {
    throw Error(both + " have different objects ([" + join(names) + "] and [" + join(test_names) +
                "]); with objects the map does not hold, give --unknown-objects");
  }
  const auto& cal = MapAccess::pair_map(map).appearance.calibration;
  const SensorSpec& s = test.scene.sensor;
  if (cal.sensor.rows != s.rows || cal.sensor.cols != s.cols || std::abs(cal.sensor.pitch_mm - s.pitch_mm) > 1e-9)
    throw Error(both + " use different sensors (" + std::to_string(cal.sensor.rows) + "x" +
                std::to_string(cal.sensor.cols) + " at " + fmt(cal.sensor.pitch_mm) + " mm and " +
                std::to_string(s.rows) + "x" + std::to_string(s.cols) + " at " + fmt(s.pitch_mm) +
                " mm): their descriptors do not compare");
  if (std::abs(cal.contact_threshold_kpa - test.scene.skin.contact_threshold_kpa) > 1e-9 ||
      std::abs(cal.stiffness_kpa_per_mm - test.scene.skin.stiffness_kpa_per_mm) > 1e-9)
    throw Error(both + " use different skin calibrations (contact threshold " + fmt(cal.contact_threshold_kpa) +
                " and " + fmt(test.scene.skin.contact_threshold_kpa) + " kPa, stiffness " +
                fmt(cal.stiffness_kpa_per_mm) + " and " + fmt(test.scene.skin.stiffness_kpa_per_mm) + " kPa/mm)");
}

namespace {

EvalResult run_checked_evaluation(const Map& map, const Dataset& test, const EvalOptions& options) {
  TrialSetup setup;
  if (options.unknown_objects) setup.map_object = map_objects_of(map, test);
  setup.trials = options.trials;
  setup.max_readings = options.max_readings;
  setup.seed = options.seed;
  setup.pose_space = map.pose_space();
  setup.threads = options.threads;
  setup.progress = options.progress;
  setup.source = options.data_name;
  setup.keep_evidence = options.keep_evidence;
  setup.scene = map.scene_name();
  setup.backend = backend_name(options.recognizer.backend);
  setup.method = method_name(options.recognizer.method);
  setup.estimate = estimate_depth_name(options.estimate);
  if (options.policy != Policy::random) return run_active(map, test, setup, options);
  RecognizerOptions ro = options.recognizer;
  // The Vulkan backend runs the trials in lock step, a batch per submission
  // (one device, one upload of the map), as batch recognition does.
  // With auto, the backend factory decides (BatchRecognizer::backend()).
  std::string fallback;
  if (ro.backend != BackendKind::cpu && ro.method == Method::sva) {
    RecognizerBatch batch(map, std::min<std::size_t>(options.trials, options.vulkan_batch), ro, options.estimate);
    if (batch.recognizer().backend() == BackendKind::vulkan) {
      setup.backend = backend_name(BackendKind::vulkan);
      EvalResult r = run_trials_batched(test, setup, batch);
      r.device = batch.recognizer().backend_description();
      return r;
    }
    fallback = batch.recognizer().backend_fallback_reason();
  }
  // Whatever the backend asked for, the appearance-only baseline votes nowhere.
  if (ro.backend == BackendKind::automatic) ro.backend = BackendKind::cpu;
  setup.backend = backend_name(ro.backend);
  // Trials already occupy the cores; a recognizer on one thread each avoids
  // oversubscription (its results do not depend on its thread count).
  if (options.trials > 1) ro.threads = 1;
  EvalResult r =
      run_trials(test, setup, [&] { return std::make_unique<RecognizerSession>(map, ro, options.estimate); });
  const unsigned threads = options.threads ? options.threads : util::default_threads();
  r.device = "CPU reference (" + std::to_string(std::min<std::size_t>(threads, options.trials)) + " threads)";
  r.backend_fallback_reason = fallback;
  return r;
}

}  // namespace

EvalResult run_evaluation(const Map& map, const Dataset& test, const EvalOptions& options) {
  check_compatible(map, test, options.map_name, options.data_name, options.unknown_objects);
  EvalResult r = run_checked_evaluation(map, test, options);
  add_surface_errors(r, test.scene, options.threads);
  r.map_objects = map.object_names();
  return r;
}

SpeedComparison compare_with_cpu_reference(const Map& map, const Dataset& test, const EvalOptions& options,
                                           const EvalResult& run, std::size_t trials) {
  auto median_update_ms = [](const EvalResult& r, std::size_t n) {
    std::vector<double> ms;
    for (std::size_t t = 0; t < std::min(n, r.trials.size()); ++t)
      for (const StepResult& s : r.trials[t].steps) ms.push_back(s.update_ms);
    return median(ms);
  };
  SpeedComparison c;
  c.device = run.device;
  c.trials = std::min(trials, run.trials.size());
  c.update_ms = median_update_ms(run, c.trials);
  if (run.backend == backend_name(BackendKind::cpu)) {
    c.cpu_device = run.device;
    c.cpu_update_ms = c.update_ms;
    return c;
  }
  EvalOptions o = options;
  o.trials = c.trials;
  o.recognizer.backend = BackendKind::cpu;
  const EvalResult cpu = run_evaluation(map, test, o);
  c.cpu_device = cpu.device;
  c.cpu_update_ms = median_update_ms(cpu, c.trials);
  return c;
}

}  // namespace sva::eval
