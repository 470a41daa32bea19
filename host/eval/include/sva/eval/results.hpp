#pragma once
// What an evaluation produces: per trial and per reading the estimate's
// correctness, pose errors and update time; and the curve that summarises
// them against the number of readings (the paper's Fig. 4 and 5).
#include <sva/pose.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sva::eval {

// The state after one more reading of a trial.
struct StepResult {
  std::uint32_t estimated_object = 0;
  bool correct = false;
  double true_object_probability = 0.0;
  bool pose_valid = false;            // the recognizer had a pose estimate (never for the appearance-only method)
  double translation_error_mm = 0.0;  // meaningful when correct && pose_valid
  double angular_error_rad = 0.0;
  double inertial_error_mm = 0.0;
  double update_ms = 0.0;        // add_reading + estimate (timing: varies run to run)
  double plan_ms = 0.0;          // choosing this reading (the active policies' plan; 0 for random)
  std::uint64_t votes = 0;       // votes cast inside the pose space by this reading's update
  std::uint64_t votes_zero = 0;  // of them, those whose fixed-point mass rounds to 0 (they add nothing)
  RigidPose estimate;            // the estimated pose (when pose_valid)
  bool has_pose_error() const { return correct && pose_valid; }
};

struct TrialResult {
  std::size_t index = 0;
  std::uint32_t object = 0;
  RigidPose pose;                    // true pose
  std::vector<std::size_t> samples;  // test sample presented at each step
  std::vector<StepResult> steps;     // steps[n - 1]: after n readings
};

// Median, mean and 90th percentile of a set (empty when the set is).
struct Spread {
  std::optional<double> median, mean, p90;
};
Spread spread_of(const std::vector<double>& values);

// One point of the curve. Error statistics are over the trials whose estimated
// object is right (and which have a pose) at that step; empty when none.
struct CurvePoint {
  std::size_t readings = 0;
  double accuracy = 0.0;                            // fraction of trials with the right object, 0..1
  std::size_t pose_trials = 0;                      // trials the error statistics are over
  Spread translation_mm, angular_deg, inertial_mm;  // errors
  Spread update_ms;                                 // over all trials
  std::optional<double> update_ms_p95;
  std::uint64_t votes = 0, votes_zero = 0;  // summed over all trials at this step
};

// Readings until the true object first holds at least `threshold` of the posterior, per trial: the mean and
// median over all trials, a trial that never gets there counted as max_readings + 1 (so both are lower bounds
// when `reached` < `trials`).
struct Confidence {
  double threshold = 0.95;
  std::size_t trials = 0, reached = 0;
  std::optional<double> mean, median;
};

struct Curve {
  std::string label;  // legend text (the method, or a file name)
  std::string scene, backend, method;
  std::string policy = "random";  // how each next reading was chosen (host/eval/src/eval/active_trials.hpp)
  Confidence to_95;               // readings until the true object holds >= 95%
  std::optional<double> plan_ms;  // median time per plan (active policies)
  std::size_t trials = 0;
  std::vector<CurvePoint> points;
};

struct EvalResult {
  std::string scene;
  std::string backend;            // "cpu" | "vulkan"
  std::string method;             // "sva" | "appearance"
  std::string policy = "random";  // "random" | "active" | "active-sim"
  std::uint64_t seed = 0;
  std::size_t max_readings = 0;
  std::vector<std::string> objects;
  std::vector<TrialResult> trials;
  // Not in the reports' files: what ran the votes ("vulkan: GPU name (type)",
  // "CPU reference (N threads)") and, when auto found no usable Vulkan device, why.
  std::string device;
  std::string backend_fallback_reason;
};

// The curve of a result: one point per reading count 1..max_readings.
Curve summarize(const EvalResult& result);

Confidence readings_to_confidence(const EvalResult& result, double threshold);

}  // namespace sva::eval
