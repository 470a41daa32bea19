// The probability metrics of an evaluation (host/eval/src/eval/calibration_metrics.cpp) on results made by hand.
#include <catch2/catch.hpp>

#include <sva/eval/results.hpp>

using namespace sva::eval;

namespace {

// A trial whose steps have the given top probabilities, right or wrong, and p_unknown.
TrialResult trial(bool known, const std::vector<std::tuple<double, bool, double>>& steps) {
  TrialResult t;
  t.known = known;
  for (const auto& [top, correct, unknown] : steps) {
    StepResult s;
    s.top_probability = top;
    s.correct = correct;
    s.p_unknown = unknown;
    t.steps.push_back(s);
  }
  return t;
}

}  // namespace

TEST_CASE("ECE and confidently wrong: from 2 readings on, over known objects, in 10 bins") {
  EvalResult r;
  r.max_readings = 3;
  // Step 1 never counts; a 0.95 bin all right (gap 0.05), a 0.995 wrong step (confidently wrong, gap 0.995).
  r.trials.push_back(trial(true, {{0.2, false, 0.0}, {0.95, true, 0.0}, {0.95, true, 0.0}}));
  r.trials.push_back(trial(true, {{0.9, true, 0.0}, {0.55, true, 0.0}, {0.995, false, 0.0}}));
  r.trials.push_back(trial(false, {{0.9, false, 0.9}, {0.999, false, 0.9}, {0.999, false, 0.9}}));  // unknown: out
  const CalibrationSummary c = calibration_summary(r);
  CHECK(c.trial_readings == 4);
  CHECK(c.confidently_wrong == Approx(0.25));
  REQUIRE(c.bins.size() == 10);
  CHECK(c.bins[5].count == 1);
  CHECK(c.bins[9].count == 3);
  CHECK(c.bins[9].confidence == Approx((0.95 + 0.95 + 0.995) / 3));
  CHECK(c.bins[9].accuracy == Approx(2.0 / 3));
  // |0.55 - 1| + |2.895 - 2| over 4.
  CHECK(c.ece == Approx((0.45 + 0.895) / 4));
}

TEST_CASE("ECE uncertainty: the bootstrap over trials and what exactly right probabilities would measure") {
  // 10 trials of 21 readings at 0.5 each, 5 trials right throughout and 5 wrong: the measured ECE is 0, while
  // 200 outcomes drawn at 0.5 are off by E|Bin(200, 1/2) / 200 - 1/2| = 0.0282 and 10 drawn per trial by
  // E|Bin(10, 1/2) / 10 - 1/2| = 0.1230 (both exact, the draws' spread well inside the margins).
  EvalResult r;
  r.max_readings = 21;
  for (int i = 0; i < 10; ++i) r.trials.push_back(trial(true, std::vector(21, std::tuple{0.5, i < 5, 0.0})));
  const CalibrationSummary c = calibration_summary(r);
  CHECK(c.trial_readings == 200);
  CHECK(c.ece == Approx(0.0).margin(1e-12));
  CHECK(c.ece_if_calibrated_independent == Approx(0.0282).margin(0.004));
  CHECK(c.ece_if_calibrated_per_trial == Approx(0.1230).margin(0.02));
  // Resampled trials are rarely 5 and 5: the interval starts at 0 (a 5-5 draw, p = 0.25) and reaches past 0.15.
  CHECK(c.ece_interval[0] == Approx(0.0).margin(1e-12));
  CHECK(c.ece_interval[1] > 0.15);
  CHECK(c.ece_interval[1] <= 0.5);
  // Seeded: the same figures every time.
  const CalibrationSummary again = calibration_summary(r);
  CHECK(again.ece_interval == c.ece_interval);
  CHECK(again.ece_if_calibrated_per_trial == c.ece_if_calibrated_per_trial);
  // Sure and right everywhere: nothing to draw.
  EvalResult sure;
  sure.max_readings = 3;
  for (int i = 0; i < 4; ++i) sure.trials.push_back(trial(true, std::vector(3, std::tuple{1.0, true, 0.0})));
  const CalibrationSummary s = calibration_summary(sure);
  CHECK(s.ece_interval[1] == 0.0);
  CHECK(s.ece_if_calibrated_independent == 0.0);
  CHECK(s.ece_if_calibrated_per_trial == 0.0);
}

TEST_CASE("stop summary: the first reading that decides, right or wrong, unknown objects right only as unknown") {
  EvalResult r;
  r.max_readings = 3;
  r.trials.push_back(trial(true, {{0.5, true, 0.0}, {0.97, true, 0.0}, {0.99, true, 0.0}}));      // right at 2
  r.trials.push_back(trial(true, {{0.96, false, 0.0}, {0.99, true, 0.0}, {0.99, true, 0.0}}));    // wrong at 1
  r.trials.push_back(trial(true, {{0.96, true, 0.2}, {0.5, true, 0.2}, {0.6, true, 0.2}}));       // never
  r.trials.push_back(trial(false, {{0.9, false, 0.5}, {0.9, false, 0.96}, {0.9, false, 0.99}}));  // unknown at 2
  const StopSummary s = stop_summary(r, 0.95);
  CHECK(s.trials == 4);
  CHECK(s.decided == 3);
  CHECK(s.right == 2);
  CHECK(*s.accuracy == Approx(2.0 / 3));
  CHECK(*s.mean_readings == Approx((2 + 1 + 2) / 3.0));
  CHECK(s.mean_readings_to_right == Approx((2 + 4 + 4 + 2) / 4.0));
}

TEST_CASE("unknown summary: ROC of p_unknown, its area, and the catch at 5% false rejection") {
  EvalResult r;
  r.max_readings = 2;
  for (int i = 0; i < 20; ++i) r.trials.push_back(trial(true, {{0.9, true, 0.0}, {0.9, true, 0.01 * i}}));
  for (int i = 0; i < 4; ++i) r.trials.push_back(trial(false, {{0.9, false, 0.0}, {0.9, false, 0.5 + 0.1 * i}}));
  CHECK_FALSE(unknown_summary(r, 3).has_value());  // no trial has 3 readings
  auto u = unknown_summary(r, 2);
  REQUIRE(u.has_value());
  CHECK(u->known_trials == 20);
  CHECK(u->unknown_trials == 4);
  CHECK(u->auc == Approx(1.0));
  CHECK(u->caught_at_5 == 1.0);
  CHECK(u->rejected_at_5 == 0.0);
  CHECK(u->threshold_at_5 == Approx(0.5));
  // One unknown trial scored below every known one: the area loses a quarter.
  r.trials.back().steps[1].p_unknown = 0.0;
  u = unknown_summary(r, 2);
  CHECK(u->auc == Approx(0.75 + 0.25 * 0.5 / 20).epsilon(1e-9));  // a tie with the 0.0 known trial counts half
  CHECK(u->caught_at_5 == Approx(0.75));
  // Only known trials: no summary.
  r.trials.resize(20);
  CHECK_FALSE(unknown_summary(r, 2).has_value());
}

TEST_CASE("ECE by reading range: 2-5, 6-10, 11-20, 21-30 and by 20 on, each range's own ECE and which way it errs") {
  // Two trials of 35 readings: overconfident before 6 readings (0.9, wrong), exactly right from 6 to 20 (1.0,
  // right), underconfident from 21 on (0.6, right).
  EvalResult r;
  r.max_readings = 35;
  for (int i = 0; i < 2; ++i) {
    std::vector<std::tuple<double, bool, double>> steps;
    for (int n = 1; n <= 35; ++n) steps.emplace_back(n <= 5 ? 0.9 : n <= 20 ? 1.0 : 0.6, n > 5, 0.0);
    r.trials.push_back(trial(true, steps));
  }
  const CalibrationSummary c = calibration_summary(r);
  REQUIRE(c.by_readings.size() == 5);
  const std::vector<std::pair<std::size_t, std::size_t>> ranges{{2, 5}, {6, 10}, {11, 20}, {21, 30}, {31, 35}};
  std::size_t total = 0;
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    CHECK(c.by_readings[i].first == ranges[i].first);
    CHECK(c.by_readings[i].last == ranges[i].second);  // 31-35: as far as the trials reached
    total += c.by_readings[i].trial_readings;
  }
  CHECK(total == c.trial_readings);
  CHECK(c.by_readings[0].trial_readings == 8);
  CHECK(c.by_readings[0].ece == Approx(0.9));
  CHECK(c.by_readings[0].confidence == Approx(0.9));
  CHECK(c.by_readings[0].accuracy == 0.0);
  CHECK(c.by_readings[1].ece == Approx(0.0).margin(1e-12));
  CHECK(c.by_readings[2].ece == Approx(0.0).margin(1e-12));
  CHECK(c.by_readings[3].ece == Approx(0.4));
  CHECK(c.by_readings[3].accuracy == 1.0);
  CHECK(c.by_readings[4].trial_readings == 10);
  // The whole run's ECE mixes the ranges: (8 x 0.9 + 30 x 0.4) / 68.
  CHECK(c.ece == Approx((8 * 0.9 + 30 * 0.4) / 68.0));
}
