// The probability metrics of an evaluation (results.hpp): calibration, stopping, objects outside the map.
#include <sva/eval/results.hpp>

#include <sva/base/rng.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace sva::eval {

namespace {

// One trial-reading as the calibration sees it: the top object's probability, whether the top object was right, and
// the reading count.
struct Scored {
  double p;
  bool right;
  std::size_t readings;
};

// The trial-readings from 2 readings on of the trials whose object the map knows, trial by trial.
std::vector<std::vector<Scored>> scored_trials(const EvalResult& result) {
  std::vector<std::vector<Scored>> out;
  for (const TrialResult& t : result.trials) {
    if (!t.known || t.steps.size() < 2) continue;
    std::vector<Scored>& trial = out.emplace_back();
    for (std::size_t k = 1; k < t.steps.size(); ++k)
      trial.push_back({std::clamp(t.steps[k].top_probability, 0.0, 1.0), t.steps[k].correct, k + 1});
  }
  return out;
}

std::size_t bin_of(double p) { return std::min<std::size_t>(static_cast<std::size_t>(p * 10.0), 9); }

// The ECE of 10 equal-width bins, from per-bin sums of confidence and of right answers.
struct BinSums {
  std::array<double, 10> confidence{}, right{};
  std::size_t count = 0;
  void add(double p, bool r) {
    confidence[bin_of(p)] += p;
    right[bin_of(p)] += r ? 1.0 : 0.0;
    ++count;
  }
  double ece() const {
    double e = 0.0;
    for (std::size_t b = 0; b < 10; ++b) e += std::abs(confidence[b] - right[b]);
    return count ? e / static_cast<double>(count) : 0.0;
  }
};

// The bootstrap interval over trials and the ECE a belief with these probabilities would measure if they were
// exactly right (CalibrationSummary says why). Seeded, so a run reports the same figures every time.
void ece_uncertainty(const std::vector<std::vector<Scored>>& trials, CalibrationSummary* c) {
  constexpr int kDraws = 400;
  if (trials.empty()) return;
  util::Rng rng(0xece, trials.size(), c->trial_readings);
  std::vector<double> resampled;
  double independent = 0.0, per_trial = 0.0;
  for (int d = 0; d < kDraws; ++d) {
    BinSums boot, ind, dep;
    for (std::size_t i = 0; i < trials.size(); ++i) {
      for (const Scored& s : trials[rng.below(trials.size())]) boot.add(s.p, s.right);
      const double u = rng.uniform();
      for (const Scored& s : trials[i]) {
        ind.add(s.p, rng.uniform() < s.p);
        dep.add(s.p, u < s.p);
      }
    }
    resampled.push_back(boot.ece());
    independent += ind.ece();
    per_trial += dep.ece();
  }
  std::sort(resampled.begin(), resampled.end());
  c->ece_interval = {resampled[kDraws / 20], resampled[kDraws - 1 - kDraws / 20]};
  c->ece_if_calibrated_independent = independent / kDraws;
  c->ece_if_calibrated_per_trial = per_trial / kDraws;
}

// The first reading count of the range that `readings` (>= 2) falls in: 2-5, 6-10, 11-20, 21-30, then 31-50, 51-70,
// ... (the first ranges split where the fine pose and the surface check start, at 6 readings).
std::size_t range_first(std::size_t readings) {
  if (readings <= 5) return 2;
  if (readings <= 10) return 6;
  if (readings <= 30) return 11 + 10 * ((readings - 11) / 10);
  return 31 + 20 * ((readings - 31) / 20);
}

std::vector<ReadingRangeCalibration> by_reading_range(const std::vector<std::vector<Scored>>& trials) {
  std::vector<ReadingRangeCalibration> out;
  std::vector<BinSums> sums;
  for (const std::vector<Scored>& trial : trials) {
    for (const Scored& s : trial) {
      const std::size_t first = range_first(s.readings);
      std::size_t i = 0;
      while (i < out.size() && out[i].first != first) ++i;
      if (i == out.size()) {
        out.push_back({first, first, 0, 0.0, 0.0, 0.0});
        sums.emplace_back();
      }
      out[i].last = std::max(out[i].last, s.readings);  // the range as far as the trials reached
      sums[i].add(s.p, s.right);
      out[i].confidence += s.p;
      out[i].accuracy += s.right ? 1.0 : 0.0;
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].trial_readings = sums[i].count;
    out[i].ece = sums[i].ece();
    out[i].confidence /= static_cast<double>(sums[i].count);
    out[i].accuracy /= static_cast<double>(sums[i].count);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return out;
}

}  // namespace

CalibrationSummary calibration_summary(const EvalResult& result) {
  CalibrationSummary c;
  c.bins.assign(10, {});
  std::size_t wrong_sure = 0;
  const std::vector<std::vector<Scored>> trials = scored_trials(result);
  BinSums sums;
  for (const std::vector<Scored>& trial : trials) {
    for (const Scored& s : trial) {
      ++c.bins[bin_of(s.p)].count;
      sums.add(s.p, s.right);
      wrong_sure += (s.p >= 0.99 && !s.right) ? 1 : 0;
    }
  }
  c.trial_readings = sums.count;
  c.ece = sums.ece();
  for (std::size_t k = 0; k < c.bins.size(); ++k) {
    ReliabilityBin& b = c.bins[k];
    if (b.count == 0) continue;
    b.confidence = sums.confidence[k] / static_cast<double>(b.count);
    b.accuracy = sums.right[k] / static_cast<double>(b.count);
  }
  if (c.trial_readings > 0)
    c.confidently_wrong = static_cast<double>(wrong_sure) / static_cast<double>(c.trial_readings);
  ece_uncertainty(trials, &c);
  c.by_readings = by_reading_range(trials);
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
