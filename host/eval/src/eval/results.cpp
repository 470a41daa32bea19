#include <sva/eval/results.hpp>

#include <cassert>
#include <numbers>

#include "eval/metrics.hpp"

namespace sva::eval {

Spread spread_of(const std::vector<double>& values) { return {median(values), mean(values), percentile(values, 90.0)}; }

Confidence readings_to_confidence(const EvalResult& result, double threshold) {
  Confidence c;
  c.threshold = threshold;
  std::vector<double> n;
  for (const auto& trial : result.trials) {
    if (!trial.known) continue;  // no true object in the map to reach
    ++c.trials;
    std::size_t first = result.max_readings + 1;
    for (std::size_t k = 0; k < trial.steps.size(); ++k)
      if (trial.steps[k].true_object_probability >= threshold) {
        first = k + 1;
        break;
      }
    c.reached += first <= result.max_readings;
    n.push_back(static_cast<double>(first));
  }
  c.mean = mean(n);
  c.median = median(n);
  return c;
}

std::string curve_label(const std::string& method, const std::string& policy, const std::string& estimate) {
  std::string label = method;
  if (method == "sva" && policy != "random") label += " " + policy;
  if (method == "sva" && estimate == "light") label += " light";
  return label;
}

Curve summarize(const EvalResult& result, std::optional<double> stop_at) {
  Curve c;
  c.calibration = calibration_summary(result);
  if (stop_at) c.stop = stop_summary(result, *stop_at);
  c.unknown = unknown_summary(result, std::min<std::size_t>(15, result.max_readings));
  c.label = curve_label(result.method, result.policy, result.estimate);
  c.policy = result.policy;
  c.estimate = result.estimate;
  c.to_95 = readings_to_confidence(result, 0.95);
  std::vector<double> plans;
  for (const auto& trial : result.trials)
    for (const StepResult& s : trial.steps)
      if (s.plan_ms > 0.0) plans.push_back(s.plan_ms);
  c.plan_ms = median(plans);
  c.scene = result.scene;
  c.backend = result.backend;
  c.method = result.method;
  c.trials = result.trials.size();
  for (std::size_t n = 1; n <= result.max_readings; ++n) {
    CurvePoint p;
    p.readings = n;
    std::size_t correct = 0, known = 0;
    std::vector<double> t_err, a_err, i_err, mssd_err, adds_err, ms;
    for (const auto& trial : result.trials) {
      assert(trial.steps.size() == result.max_readings);
      const StepResult& s = trial.steps[n - 1];
      correct += s.correct;
      known += trial.known;
      ms.push_back(s.update_ms);
      p.votes += s.votes;
      p.votes_zero += s.votes_zero;
      if (!s.has_pose_error()) continue;
      t_err.push_back(s.translation_error_mm);
      a_err.push_back(s.angular_error_rad * 180.0 / std::numbers::pi);
      i_err.push_back(s.inertial_error_mm);
      if (s.mssd_mm) mssd_err.push_back(*s.mssd_mm);
      if (s.adds_mm) adds_err.push_back(*s.adds_mm);
    }
    // Over the trials whose object the map holds (all of them unless --unknown-objects).
    p.accuracy = known == 0 ? 0.0 : static_cast<double>(correct) / static_cast<double>(known);
    p.pose_trials = t_err.size();
    p.translation_mm = spread_of(t_err);
    p.angular_deg = spread_of(a_err);
    p.inertial_mm = spread_of(i_err);
    p.mssd_mm = spread_of(mssd_err);
    p.adds_mm = spread_of(adds_err);
    p.update_ms = spread_of(ms);
    p.update_ms_p95 = percentile(ms, 95.0);
    c.points.push_back(p);
  }
  return c;
}

}  // namespace sva::eval
