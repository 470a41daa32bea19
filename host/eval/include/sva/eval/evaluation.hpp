#pragma once
// The evaluation the CLI (`sva eval`) and the demo call: recognition trials of
// a map against a test set through sva::Recognizer, summarised as a curve.
//
//   eval::EvalOptions o;  o.trials = 30;  o.max_readings = 30;
//   eval::EvalResult r = eval::run_evaluation(map, test, o);
//   eval::Curve c = eval::summarize(r);          // results.hpp
//   std::fputs(eval::format_table(c).c_str(), stdout);  // report.hpp
//   eval::write_figure({c, baseline}, "fig.png");  // figure.hpp
#include <sva/dataset.hpp>
#include <sva/eval/active_setup.hpp>
#include <sva/eval/results.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <optional>
#include <string>

namespace sva::eval {

struct EvalOptions {
  std::size_t trials = 0;         // >= 1
  std::size_t max_readings = 30;  // >= 1
  std::uint64_t seed = 1;
  RecognizerOptions recognizer;                  // backend, method, eps, speed knobs
  EstimateDepth estimate = EstimateDepth::full;  // each step's estimate (light: the belief's answer, no host fits)
  unsigned threads = 0;                          // trials in parallel; 0 = util::default_threads()
  std::size_t vulkan_batch = 64;                 // Vulkan backend: trials stepped together per submission
  bool progress = true;
  std::string map_name = "map";  // names the files in errors
  std::string data_name = "test set";
  // How each next reading is chosen (host/eval/src/eval/active_trials.hpp): random (the paper's protocol, the default)
  // or planned; the adaptive policies step every trial on its own (no lock-step batches), on the resolved backend.
  Policy policy = Policy::random;
  // The test set may hold objects the map does not (matched by name): their trials count as right only when
  // they say "none of these" (the stop summary), and the curve reports p_unknown's ROC.
  bool unknown_objects = false;
  // Keep each step's ObjectEvidence in the result (`sva eval --evidence`): two numbers per object per trial-reading,
  // so off unless asked (10,000 trials of 30 readings on 100 objects would hold 480 MB).
  bool keep_evidence = false;
  std::optional<double> stop_at;  // the stop summary's threshold (summarize)
  ActiveSetup active;             // its policy is set from `policy`
};

// Throws sva::Error naming both files when the test set cannot be evaluated
// against the map: another scene, other objects (names or order), another
// sensor geometry or skin calibration (the descriptors would not compare).
// `unknown_objects`: the map's objects need only be among the test set's (by name; at least one shared).
void check_compatible(const Map& map, const Dataset& test, const std::string& map_name, const std::string& data_name,
                      bool unknown_objects = false);
// A warning for light estimates (`depth` light, calibrated) on a map whose calibration was learned without their own
// (map format 9 or older): their probabilities then read the full calibration's evidence regime, underconfident among
// near-twins (docs/recognition.md, "Light and full estimates"). "" when there is nothing to say.
std::string light_calibration_warning(const Map& map, const std::string& map_name, EstimateDepth depth, bool calibrate);
// Per object of the test set: its id in the map, or -1 when the map does not hold it.
std::vector<std::int32_t> map_objects_of(const Map& map, const Dataset& test);

// Runs the trials; poses are drawn from the map's pose space.
EvalResult run_evaluation(const Map& map, const Dataset& test, const EvalOptions& options);

// A run's time per update next to the CPU reference's on the same trials (the
// first `trials` of the run: same seed, same poses and readings). Times are
// medians over every update of those trials, as `sva eval` reports them (a
// batched update's time is shared by the trials in it).
struct SpeedComparison {
  std::string device, cpu_device;  // what ran the run, and the CPU reference
  std::size_t trials = 0;
  std::optional<double> update_ms, cpu_update_ms;
};
// Runs the CPU reference on those trials unless the run already was the CPU's.
SpeedComparison compare_with_cpu_reference(const Map& map, const Dataset& test, const EvalOptions& options,
                                           const EvalResult& run, std::size_t trials);

const char* backend_name(BackendKind backend);
const char* method_name(Method method);

}  // namespace sva::eval
