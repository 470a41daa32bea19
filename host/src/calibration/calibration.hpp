#pragma once
// Calibrated object probabilities and "none of these" (docs/recognition.md, "Calibration").
//
// Eq 5 multiplies the evidence of every pair as if the pairs were independent. n readings make n(n-1)/2 pairs and
// each reading enters n-1 of them, so the same evidence is counted many times over and the raw posterior saturates
// long before the answer is safe. The estimate therefore tempers each object's log-evidence L_o (log2 of its
// posterior mass summed over poses) by a temperature that falls with the reading count,
//
//   p(o | n readings) = w_o 2^(tau(n) L_o) / sum_k w_k 2^(tau(n) L_k),   tau(n) = scale (n - 1)^-power,
//
// with w the caller's prior: temperature scaling (Guo et al. 2017) on the object log-marginals, its temperature a
// function of the reading count because the over-counting grows with it (about (n-1)/2-fold). scale and power are
// learned when the map is trained, from sessions on training readings the map never saw (held_out_sessions.hpp).
//
// "None of these" asks how well the map explains the readings, against what known and unknown objects gave at the
// same reading count on those held-out sessions: the evidence the best pose gathered per pair, how far the best
// object stands above the next, and above all how well the best object's surface fits the contacts at the fine
// pose (an unseen object's contacts do not lie on a known surface), which replaces the other two once it exists.
// Two logistic models (the evidence model before the fine pose, the fit model from it on) whose coefficients are
// linear in log(n - 1), fitted with the two kinds weighted equally, then moved to the caller's prior odds.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sva {

// What one step of a session shows the calibration.
struct EvidenceLevel {
  std::size_t readings = 0;
  // Per object: log2 of its posterior mass over poses, relative to one bin at the belief's maximum (so <= log2 of
  // the bins per object). Exact for objects with bins near the maximum; below them, from the object's best bin and
  // its untouched bins (a lower bound that never underflows).
  std::vector<double> object_log2_mass;
  // The best bin's evidence in bits over the ordered pairs folded so far (0 before any pair).
  double best_bits_per_pair = 0.0;
  // How well the best object's surface explains the contacts at the fine pose (estimate/fine_pose.hpp):
  // the robust cost per reading over the final scale^2/6 (an unmatched reading's cost: 1). Negative when the fine
  // pose was not computed (too few readings).
  double fit_cost_share = -1.0;
  // The reading count at which the session's fine pose first exists (RefineSettings::min_readings); 0: not known
  // (the top label then applies its fine-pose regime in full).
  std::size_t fine_pose_from = 0;
  // The verify stage (estimate/verify.hpp), per object: log2 of how well its surface explains the
  // readings at its own fine pose, added to the tempered log-evidence with the calibration's surface weight.
  // Empty when it was not run (too few readings, no surface, switched off).
  std::vector<double> surface_log2_fit;
  // A light estimate's level (EstimateDepth::light: no fit, no surface check, by the caller's choice rather than for
  // too few readings): from the light calibration's first reading count on, the calibration reads its light regime.
  bool light_estimate = false;
};

// The features "none of these" reads (Calibration::unknown_features). Before the fine pose exists (fewer readings
// than it needs), the evidence: the best bin's evidence per pair and the gap between the two best objects'
// log-evidence (both log2(1 + x)), weighed by the evidence model. From the fine pose on, the fit alone, weighed by
// the fit model: an indicator that it exists and log2(kFitShareFloor + its cost share, at most kFitShareCap)
// (calibration_fit.hpp). The evidence's level is the object's as much as the session's (a plate's or a book's pairs
// spread their votes over many poses, so known flat objects looked unseen), while nothing in the fit depends on the
// shape; its log makes the known objects' skewed shares, mostly near 0, count by ratio (docs/evaluation.md,
// "Calibration"). (The readings' appearance log-likelihood under the best object was tried as another feature: on a
// small paper3d its ROC area fell from 0.91 to 0.74 by overfitting; left out.)
inline constexpr std::size_t kUnknownFeatures = 4;
// One reading in fifty unexplained: keeps the log of a perfect fit finite.
inline constexpr double kFitShareFloor = 0.02;
// Three readings in four unexplained: a share above it says no more. The calibration's known sessions hold few such
// shares (the first fine poses, the object still unsure), so the model's tail there would be extrapolation, and one
// poor first fit read as a sure "none of these" (docs/evaluation.md, "Calibration").
inline constexpr double kFitShareCap = 0.75;
// Which features a model reads: this build's, or those of maps of earlier builds (map versions 4 and 5): the evidence
// per pair, the gap and the fit cost share (0 before the fine pose) at every step, the fourth weight 0.
enum class UnknownFeatureSet : std::uint8_t { evidence_then_fit, evidence_gap_share };
using UnknownCoefficients = std::array<double, kUnknownFeatures + 1>;  // bias first

// The logistic model of "none of these", written out per reading count: logit = c[0] + sum_i c[i + 1] f_i(level).
// Learned maps write the coefficients of both models (each linear in log(n - 1); a row holds both, as each model's
// features are 0 on the other side) to twice the calibration sessions' length (calibration_fit.hpp); maps of earlier
// builds hold one model, some of them one per count to the sessions' length.
struct UnknownModel {
  std::vector<UnknownCoefficients> per_readings;  // index n - 2 for n readings; past the last, the last
  UnknownFeatureSet features = UnknownFeatureSet::evidence_then_fit;
  bool empty() const { return per_readings.empty(); }
};

// The posterior of objects whose log-evidence (bits) is tempered by `temperature`, plus `surface_weight` times
// `surface_log2_fit` (bits; empty: none), and weighed by `object_weight` (largest 1; empty: flat; a weight of 0
// gives 0).
std::vector<double> tempered_posterior(std::span<const double> log2_mass, double temperature,
                                       std::span<const double> object_weight,
                                       std::span<const double> surface_log2_fit = {}, double surface_weight = 1.0);

// A light estimate's calibration (EstimateDepth::light), learned from the same held-out sessions with their fits
// left out. From the fine pose's first reading count on, a full estimate's probabilities rest on the fine pose and the
// surface check, and its calibration was learned with them; a light estimate has neither, and the evidence regime
// extrapolated past the fine pose's start left it uninformative among near-twins (lookalikes: the true object reached
// 0.95 in 1 trial of 100, against 65 with the fits; docs/recognition.md, "Light and full estimates"). Before that
// count a light estimate is the full one and reads the calibration above.
struct LightCalibration {
  using TopLabel = std::array<double, 2>;
  std::uint32_t from = 0;  // the first reading count it applies at; 0: none (maps of format 1-9, no fine pose in
                           // the sessions, calibration off): the evidence regime, extrapolated
  double temperature_scale = 0.25, temperature_power = 0.8;  // tau(n), as Calibration's
  TopLabel top_label{0.0, 1.0};  // Platt scaling of the top object, phased in from the first regime's over
                                 // kTopLabelBlendReadings readings from `from`, as Calibration's second
  UnknownModel unknown;          // "none of these" from the evidence alone (evidence_gap_share, the share's weight 0)
  bool empty() const { return from == 0; }
};

struct Calibration {
  // The temperature of maps trained without held-out readings (map format versions 1-3, or training with
  // calibration off): fitted on paper3d and household50 (docs/recognition.md, "Calibration").
  static constexpr double kDefaultScale = 0.25;
  static constexpr double kDefaultPower = 0.8;
  static constexpr double kMaxTemperature = 4.0;
  // The surface check's weight in maps without a learned one (format versions 1-4, or calibration off): its bits
  // come from one sparse sample of training contacts per object, whose gaps differ between twins even where their
  // surfaces agree, so they are discounted too (fitted on household50 and lookalikes: docs/recognition.md).
  static constexpr double kDefaultSurfaceWeight = 0.25;

  bool learned = false;  // false: the defaults above
  double temperature_scale = kDefaultScale;
  double temperature_power = kDefaultPower;
  double surface_weight = kDefaultSurfaceWeight;  // lambda: bits of the surface check per bit of the posterior
  // The top object's probability recalibrated (Platt scaling on the top label): logit p' = a + b logit p, with
  // {a, b} = top_label[0] before the fine pose exists and top_label[1] from it on; the other objects keep their
  // ratios. One temperature per reading count cannot fix a reading count whose posteriors err both ways (too unsure
  // when flat, too sure when peaked: docs/recognition.md, "Calibration"). Identity in maps without one (format 1-6).
  // The fine-pose regime comes in over its first kTopLabelBlendReadings readings (top_label_at): at 6 readings the
  // fine pose and the surface check lift the top object's probability at once, while the share of right answers
  // follows over the next four readings, so one label from 6 readings on was too sure at 6-8 and too unsure at 10-12
  // (lookalikes: docs/notes/evaluation-2026-11.md, "The top label phased in").
  using TopLabel = std::array<double, 2>;
  std::array<TopLabel, 2> top_label{TopLabel{0.0, 1.0}, TopLabel{0.0, 1.0}};
  static constexpr double kTopLabelBlendReadings = 5.0;
  // The {a, b} recalibrate_top applies at `level`: the first regime before the fine pose, then (1 - w) of it and w
  // of the second, w = (readings - fine_pose_from + 1) / kTopLabelBlendReadings up to 1 (1 when fine_pose_from is 0);
  // in the light regime, the first and the light calibration's blended the same way from its `from`.
  TopLabel top_label_at(const EvidenceLevel& level) const;
  UnknownModel unknown;  // empty: the map cannot say "none of these" (p_unknown is then the prior)
  // The reading count from which the fine pose, the surface check and the fit's "none of these" model run, and the
  // second top label's regime starts: chosen when the map is trained (TrainOptions::fine_pose_from), since the
  // calibration is learned with it. 0: the pose space's default (maps of format 1-7). From 4 instead of 6, scenes of
  // distinct objects are named right sooner and twins' probabilities trusted less (docs/evaluation.md, "The fine
  // pose from 4 readings").
  std::uint32_t fine_pose_from = 0;
  static constexpr std::uint32_t kFinePoseFromSpatial = 6, kFinePoseFromPlanar = 3;
  static constexpr std::uint32_t kMinFinePoseFrom = 3, kMaxFinePoseFrom = 1000;
  // `chosen`, or the default of a planar or spatial pose space when it is 0.
  static std::uint32_t fine_pose_start(std::uint32_t chosen, bool planar) {
    return chosen != 0 ? chosen : planar ? kFinePoseFromPlanar : kFinePoseFromSpatial;
  }
  // How the fit was made (sva inspect): held-out sessions on known and unknown objects, readings per session.
  std::uint32_t known_sessions = 0, unknown_sessions = 0, session_readings = 0;

  LightCalibration light;
  // Whether a light estimate after `readings` readings reads the light calibration.
  bool light_regime(std::size_t readings, bool light_estimate) const {
    return light_estimate && !light.empty() && readings >= light.from;
  }

  // tau(n); 1 for n < 2 (no pair, nothing counted twice). `light_estimate`: a light estimate's (light_regime).
  double temperature(std::size_t readings, bool light_estimate = false) const;
  // The calibrated object posterior; `object_weight`: the prior per object (largest 1; empty: flat).
  std::vector<double> object_probability(const EvidenceLevel& level, std::span<const double> object_weight) const;
  // Recalibrates the top object of `p` (a posterior over objects at `level`) by top_label, the rest scaled to sum to
  // 1. It may lower a top and raise an unsure one up to one half, never make a top surer than the temperature left it
  // past one half (on two objects, whose sessions were nearly all right at 2-5 readings, the fit read a coin flip as
  // 0.95). The top object stays the top (held at least at the second's); a posterior with nothing outside its top
  // object is left as it is.
  void recalibrate_top(const EvidenceLevel& level, std::vector<double>* p) const;
  // The logit the top-label recalibration reads: of p held within [kTopLabelClamp, 1 - kTopLabelClamp], so that a
  // sure posterior's logit stays finite (20.7 at most).
  static constexpr double kTopLabelClamp = 1e-9;
  static double top_logit(double p);
  // A top label the map may hold: a finite bias within +-kTopLabelMaxBias and a slope in [0, kTopLabelMaxSlope] (a
  // falling slope would turn the order of confidence around). The fit keeps the identity otherwise; the loader refuses.
  static constexpr double kTopLabelMaxBias = 1e3, kTopLabelMaxSlope = 100.0;
  static bool valid_bias(double a) { return std::isfinite(a) && std::abs(a) <= kTopLabelMaxBias; }
  static bool valid_slope(double b) { return std::isfinite(b) && b >= 0.0 && b <= kTopLabelMaxSlope; }
  // The probability that the touched object is none of the map's, at prior probability `unknown_prior` of that.
  // The prior itself before any pair or without a model. In the light regime, the light calibration's model.
  double p_unknown(const EvidenceLevel& level, double unknown_prior) const;
  // The features a model of `set` reads.
  static std::array<double, kUnknownFeatures> unknown_features(
      const EvidenceLevel& level, UnknownFeatureSet set = UnknownFeatureSet::evidence_then_fit);
};

}  // namespace sva
