#pragma once
// What an evaluation produces: per trial and per reading the estimate's
// correctness, pose errors and update time; and the curve that summarises
// them against the number of readings (the paper's Fig. 4 and 5).
#include <sva/pose.hpp>
#include <sva/recognizer.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sva::eval {

// The state after one more reading of a trial.
struct StepResult {
  std::uint32_t estimated_object = 0;
  bool correct = false;
  double true_object_probability = 0.0;
  double top_probability = 0.0;       // the estimated object's probability (calibrated: RecognizerOptions::calibrate)
  double p_unknown = 0.0;             // the estimate's probability that the object is none of the map's
  bool pose_valid = false;            // the recognizer had a pose estimate (never for the appearance-only method)
  double translation_error_mm = 0.0;  // meaningful when correct && pose_valid
  double angular_error_rad = 0.0;
  double inertial_error_mm = 0.0;
  // The surface errors of the BOP benchmark with the symmetries found on the mesh (docs/pose-errors.md): set with
  // the errors above when the object's mesh could be read.
  std::optional<double> mssd_mm, adds_mm;
  double update_ms = 0.0;        // add_reading + estimate (timing: varies run to run)
  double plan_ms = 0.0;          // choosing this reading (the active policies' plan; 0 for random)
  std::uint64_t votes = 0;       // votes cast inside the pose space by this reading's update
  std::uint64_t votes_zero = 0;  // of them, those whose fixed-point mass rounds to 0 (they add nothing)
  RigidPose estimate;            // the estimated pose (when pose_valid)
  ObjectEvidence evidence;       // what the estimate's object posterior was made of (`sva eval --evidence`)
  bool has_pose_error() const { return correct && pose_valid; }
};

struct TrialResult {
  std::size_t index = 0;
  std::uint32_t object = 0;          // in the test set's scene
  bool known = true;                 // the map holds the object (`sva eval --unknown-objects`: not always)
  std::int32_t map_object = 0;       // and its id there (-1 when it does not)
  RigidPose pose;                    // true pose
  std::vector<std::size_t> samples;  // test sample presented at each step
  std::vector<StepResult> steps;     // steps[n - 1]: after n readings
};

struct EvalResult;

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
  Spread mssd_mm, adds_mm;                          // over the trials among those whose mesh could be read
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

// How far the probabilities can be trusted (docs/evaluation.md, "Calibration"), over every trial-reading from 2
// readings on of trials whose object the map knows: the expected calibration error over 10 equal-width bins of
// the top object's probability, and the share that is confidently wrong (top >= 0.99 and wrong).
struct ReliabilityBin {
  std::size_t count = 0;
  double confidence = 0.0, accuracy = 0.0;  // means over the bin (0 when empty)
};
// The same over one range of reading counts (CalibrationSummary::by_readings): where the miscalibration lies, and
// which way (mean confidence above the accuracy: overconfident). One temperature per reading count cannot fix a
// range that errs both ways (docs/evaluation.md, "The temperature from a map of every object, and the top label").
struct ReadingRangeCalibration {
  std::size_t first = 0, last = 0;  // reading counts, inclusive (last: the most any trial reached in the range)
  std::size_t trial_readings = 0;
  double ece = 0.0, confidence = 0.0, accuracy = 0.0;  // the ECE of this range's trial-readings alone; means
};
struct CalibrationSummary {
  std::size_t trial_readings = 0;
  double ece = 0.0;
  double confidently_wrong = 0.0;    // share of trial_readings
  std::vector<ReliabilityBin> bins;  // 10: [0, 0.1), ..., [0.9, 1]
  // How far the ECE itself can be trusted (docs/evaluation.md, "How much an ECE can say"). The readings of one
  // trial are far from independent (a trial on the wrong twin stays wrong for many readings), so a few dozen
  // trials measure a perfectly calibrated belief well above 0:
  // - ece_interval: the 5th and 95th percentiles of the ECE over trials resampled with replacement (bootstrap);
  // - ece_if_calibrated: the mean ECE that a belief with these same probabilities would measure if they were
  //   exactly right, its outcomes drawn at random per trial-reading (`independent`, the floor) or one draw per
  //   trial for all its readings (`per_trial`, fully dependent readings); real trials lie between.
  std::array<double, 2> ece_interval{0.0, 0.0};
  double ece_if_calibrated_independent = 0.0, ece_if_calibrated_per_trial = 0.0;
  // Readings 2-5 (before the fine pose and the surface check), 6-10, 11-20, 21-30, then by 20 (31-50, ...), each
  // range present when some trial reached it.
  std::vector<ReadingRangeCalibration> by_readings;
};
CalibrationSummary calibration_summary(const EvalResult& result);

// Deciding when to stop (`sva eval --stop-at P`): a trial decides at its first reading where "none of these"
// (p_unknown) or the top object ((1 - p_unknown) top_probability) reaches P; it is right when it names its object,
// or "none of these" for an object the map does not hold. Trials that never decide are counted apart.
struct StopSummary {
  double threshold = 0.95;
  std::size_t trials = 0, decided = 0, right = 0;
  std::optional<double> mean_readings;  // over decided trials
  std::optional<double> accuracy;       // right / decided
  // Readings to a right decision, per trial: a wrong or no decision counts max_readings + 1 (a lower bound then).
  double mean_readings_to_right = 0.0;
};
StopSummary stop_summary(const EvalResult& result, double threshold);

// Objects outside the map (`--unknown-objects`): p_unknown as a detector at `readings` readings, trials on
// unknown objects the positives. ROC points from the highest threshold down; the area under the curve; the share
// of unknown trials caught at the threshold that rejects at most 5% of known trials.
struct UnknownSummary {
  std::size_t readings = 0, known_trials = 0, unknown_trials = 0;
  double auc = 0.0;
  double caught_at_5 = 0.0, threshold_at_5 = 1.0, rejected_at_5 = 0.0;
  std::vector<std::pair<double, double>> roc;  // (false positive rate, true positive rate)
};
std::optional<UnknownSummary> unknown_summary(const EvalResult& result, std::size_t readings);

struct Curve {
  std::string label;  // legend text (the method, or a file name)
  std::string scene, backend, method;
  std::string policy = "random";  // how each next reading was chosen (host/eval/src/eval/active_trials.hpp)
  std::string estimate = "full";  // each step's estimate: "full" or "light" (EstimateDepth)
  Confidence to_95;               // readings until the true object holds >= 95%
  std::optional<double> plan_ms;  // median time per plan (active policies)
  std::size_t trials = 0;
  std::vector<CurvePoint> points;
  CalibrationSummary calibration;
  std::optional<StopSummary> stop;        // with a --stop-at threshold
  std::optional<UnknownSummary> unknown;  // when some trials' objects are not in the map
};

struct EvalResult {
  std::string scene;
  std::string backend;            // "cpu" | "vulkan"
  std::string method;             // "sva" | "appearance"
  std::string policy = "random";  // "random" | "active" | "active-sim"
  std::string estimate = "full";  // "full" | "light": each step's estimate (EvalOptions::estimate)
  std::uint64_t seed = 0;
  std::size_t max_readings = 0;
  std::vector<std::string> objects;   // the test set's, by TrialResult::object
  std::vector<std::string> families;  // their look-alike families (SceneObject::family; "" none)
  std::vector<std::string>
      map_objects;  // the map's, by StepResult::estimated_object (= objects unless some are unknown)
  std::vector<TrialResult> trials;
  // Not in the reports' files: what ran the votes ("vulkan: GPU name (type)",
  // "CPU reference (N threads)") and, when auto found no usable Vulkan device, why.
  std::string device;
  std::string backend_fallback_reason;
};

// The curve of a result: one point per reading count 1..max_readings, the calibration summary, and the unknown
// objects' summary at min(15, max_readings) readings when the result has some; `stop_at` adds the stop summary.
Curve summarize(const EvalResult& result, std::optional<double> stop_at = std::nullopt);

Confidence readings_to_confidence(const EvalResult& result, double threshold);

// A curve's legend: the method, with a policy other than random ("sva active") and a light estimate ("sva light").
std::string curve_label(const std::string& method, const std::string& policy, const std::string& estimate);

}  // namespace sva::eval
