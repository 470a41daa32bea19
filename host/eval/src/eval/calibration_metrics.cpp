// The probability metrics of an evaluation (results.hpp): calibration, stopping, objects outside the map.
#include <sva/eval/results.hpp>

#include <algorithm>
#include <cmath>

namespace sva::eval {

CalibrationSummary calibration_summary(const EvalResult& result) {
  CalibrationSummary c;
  c.bins.assign(10, {});
  std::size_t wrong_sure = 0;
  for (const TrialResult& t : result.trials) {
    if (!t.known) continue;
    for (std::size_t k = 1; k < t.steps.size(); ++k) {  // from 2 readings on
      const StepResult& s = t.steps[k];
      const double p = std::clamp(s.top_probability, 0.0, 1.0);
      ReliabilityBin& b = c.bins[std::min<std::size_t>(static_cast<std::size_t>(p * 10.0), 9)];
      ++b.count;
      b.confidence += p;
      b.accuracy += s.correct ? 1.0 : 0.0;
      wrong_sure += (p >= 0.99 && !s.correct) ? 1 : 0;
      ++c.trial_readings;
    }
  }
  for (ReliabilityBin& b : c.bins) {
    if (b.count == 0) continue;
    c.ece += std::abs(b.confidence - b.accuracy);  // sums: count x the gap of the means
    b.confidence /= static_cast<double>(b.count);
    b.accuracy /= static_cast<double>(b.count);
  }
  if (c.trial_readings > 0) {
    c.ece /= static_cast<double>(c.trial_readings);
    c.confidently_wrong = static_cast<double>(wrong_sure) / static_cast<double>(c.trial_readings);
  }
  return c;
}

StopSummary stop_summary(const EvalResult& result, double threshold) {
  StopSummary s;
  s.threshold = threshold;
  s.trials = result.trials.size();
  double readings = 0.0, to_right = 0.0;
  for (const TrialResult& t : result.trials) {
    double trial_to_right = static_cast<double>(result.max_readings + 1);
    for (std::size_t k = 0; k < t.steps.size(); ++k) {
      const StepResult& st = t.steps[k];
      const bool unknown = st.p_unknown >= threshold;
      if (!unknown && (1.0 - st.p_unknown) * st.top_probability < threshold) continue;
      ++s.decided;
      readings += static_cast<double>(k + 1);
      const bool right = unknown ? !t.known : st.correct;
      s.right += right;
      if (right) trial_to_right = static_cast<double>(k + 1);
      break;
    }
    to_right += trial_to_right;
  }
  if (s.trials > 0) s.mean_readings_to_right = to_right / static_cast<double>(s.trials);
  if (s.decided > 0) {
    s.mean_readings = readings / static_cast<double>(s.decided);
    s.accuracy = static_cast<double>(s.right) / static_cast<double>(s.decided);
  }
  return s;
}

std::optional<UnknownSummary> unknown_summary(const EvalResult& result, std::size_t readings) {
  UnknownSummary u;
  u.readings = readings;
  std::vector<std::pair<double, bool>> scored;  // (p_unknown, unknown)
  for (const TrialResult& t : result.trials) {
    if (readings == 0 || t.steps.size() < readings) continue;
    scored.push_back({t.steps[readings - 1].p_unknown, !t.known});
    ++(t.known ? u.known_trials : u.unknown_trials);
  }
  if (u.known_trials == 0 || u.unknown_trials == 0) return std::nullopt;
  // Thresholds from the highest score down; equal scores enter together (a tie is one point of the curve).
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  const double nk = static_cast<double>(u.known_trials), nu = static_cast<double>(u.unknown_trials);
  std::size_t tp = 0, fp = 0;
  u.roc.push_back({0.0, 0.0});
  for (std::size_t i = 0; i < scored.size();) {
    const double score = scored[i].first;
    for (; i < scored.size() && scored[i].first == score; ++i) ++(scored[i].second ? tp : fp);
    const double fpr = static_cast<double>(fp) / nk, tpr = static_cast<double>(tp) / nu;
    u.auc += 0.5 * (fpr - u.roc.back().first) * (tpr + u.roc.back().second);
    u.roc.push_back({fpr, tpr});
    if (fpr <= 0.05 && tpr > u.caught_at_5) {  // the strictest threshold of the best catch
      u.caught_at_5 = tpr;
      u.threshold_at_5 = score;
      u.rejected_at_5 = fpr;
    }
  }
  return u;
}

}  // namespace sva::eval
