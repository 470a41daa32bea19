#include "calibration/calibration.hpp"

#include <sva/base/portable_math.hpp>

#include <algorithm>
#include <cmath>

namespace sva {

double Calibration::temperature(std::size_t readings, bool light_estimate) const {
  if (readings < 2) return 1.0;
  const bool l = light_regime(readings, light_estimate);
  const double scale = l ? light.temperature_scale : temperature_scale;
  const double power = l ? light.temperature_power : temperature_power;
  const double t = scale * pmath::exp2(-power * pmath::log2(static_cast<double>(readings - 1)));
  return std::min(t, kMaxTemperature);
}

std::vector<double> tempered_posterior(std::span<const double> log2_mass, double temperature,
                                       std::span<const double> object_weight, std::span<const double> surface_log2_fit,
                                       double surface_weight) {
  const std::size_t n = log2_mass.size();
  std::vector<double> q(n);
  double top = -INFINITY;
  for (std::size_t o = 0; o < n; ++o) {
    q[o] = temperature * log2_mass[o] + (surface_log2_fit.empty() ? 0.0 : surface_weight * surface_log2_fit[o]);
    if (!object_weight.empty()) q[o] = object_weight[o] > 0.0 ? q[o] + pmath::log2(object_weight[o]) : -INFINITY;
    top = std::max(top, q[o]);
  }
  double z = 0.0;
  for (double& v : q) z += v = std::isinf(v) ? 0.0 : pmath::exp2(v - top);
  for (double& v : q) v /= z;
  return q;
}

std::vector<double> Calibration::object_probability(const EvidenceLevel& level,
                                                    std::span<const double> object_weight) const {
  return tempered_posterior(level.object_log2_mass, temperature(level.readings, level.light_estimate), object_weight,
                            level.surface_log2_fit, surface_weight);
}

namespace {

// From `first` to `then` over kTopLabelBlendReadings readings from reading `from` on.
Calibration::TopLabel blended(const Calibration::TopLabel& first, const Calibration::TopLabel& then,
                              std::size_t readings, std::size_t from) {
  const double w = static_cast<double>(readings - from + 1) / Calibration::kTopLabelBlendReadings;
  if (w >= 1.0) return then;
  return {(1.0 - w) * first[0] + w * then[0], (1.0 - w) * first[1] + w * then[1]};
}

}  // namespace

Calibration::TopLabel Calibration::top_label_at(const EvidenceLevel& level) const {
  // Light estimates phase their own in as the fine pose's regime is: one label from `from` on was too sure at 6-10
  // readings on lookalikes (a mean top probability of 0.57 where 47% were right; 0.53 blended).
  if (light_regime(level.readings, level.light_estimate))
    return blended(top_label[0], light.top_label, level.readings, light.from);
  if (level.fit_cost_share < 0.0) return top_label[0];
  if (level.fine_pose_from == 0 || level.readings < level.fine_pose_from) return top_label[1];
  return blended(top_label[0], top_label[1], level.readings, level.fine_pose_from);
}

void Calibration::recalibrate_top(const EvidenceLevel& level, std::vector<double>* p) const {
  const TopLabel c = top_label_at(level);
  if (p->size() < 2 || (c[0] == 0.0 && c[1] == 1.0)) return;
  std::size_t top = 0;
  for (std::size_t o = 1; o < p->size(); ++o)
    if ((*p)[o] > (*p)[top]) top = o;
  double second = 0.0;
  for (std::size_t o = 0; o < p->size(); ++o)
    if (o != top) second = std::max(second, (*p)[o]);
  const double was = (*p)[top], rest = 1.0 - was;
  if (!(rest > 0.0) || !(second > 0.0)) return;
  const double z = top_logit(was);
  double now = 1.0 / (1.0 + pmath::exp(-std::clamp(c[0] + c[1] * z, -700.0, 700.0)));
  // Never surer than the temperature left it past one half: the fit extrapolates where its sessions were all right
  // (two objects, few readings), and a decision taken at 0.95 must rest on the belief's own evidence.
  now = std::min(now, std::max(was, 0.5));
  now = std::max(now, second / (rest + second));  // the others grow by (1 - now) / rest: the top stays the top
  for (std::size_t o = 0; o < p->size(); ++o) (*p)[o] = o == top ? now : (*p)[o] * ((1.0 - now) / rest);
}

double Calibration::top_logit(double p) {
  const double q = std::clamp(p, kTopLabelClamp, 1.0 - kTopLabelClamp);
  return pmath::log(q / (1.0 - q));
}

std::array<double, kUnknownFeatures> Calibration::unknown_features(const EvidenceLevel& level, UnknownFeatureSet set) {
  double first = -INFINITY, second = -INFINITY;
  for (double l : level.object_log2_mass) {
    if (l > first) {
      second = first;
      first = l;
    } else if (l > second) {
      second = l;
    }
  }
  const double gap = std::isfinite(second) ? first - second : 0.0;
  const double evidence = pmath::log2(1.0 + std::max(level.best_bits_per_pair, 0.0));
  const double separation = pmath::log2(1.0 + std::max(gap, 0.0));
  if (set == UnknownFeatureSet::evidence_gap_share)
    return {evidence, separation, std::max(level.fit_cost_share, 0.0), 0.0};
  if (level.fit_cost_share < 0.0) return {evidence, separation, 0.0, 0.0};  // no fine pose yet
  return {0.0, 0.0, 1.0, pmath::log2(kFitShareFloor + std::min(level.fit_cost_share, kFitShareCap))};
}

double Calibration::p_unknown(const EvidenceLevel& level, double unknown_prior) const {
  const UnknownModel& model = light_regime(level.readings, level.light_estimate) ? light.unknown : unknown;
  if (model.empty() || level.readings < 2 || !(unknown_prior > 0.0 && unknown_prior < 1.0)) return unknown_prior;
  const UnknownCoefficients& c = model.per_readings[std::min(level.readings - 2, model.per_readings.size() - 1)];
  const std::array<double, kUnknownFeatures> f = unknown_features(level, model.features);
  // The model was fitted with known and unknown sessions weighted equally (even odds); the prior moves the odds.
  double logit = c[0] + pmath::log(unknown_prior / (1.0 - unknown_prior));
  for (std::size_t i = 0; i < kUnknownFeatures; ++i) logit += c[i + 1] * f[i];
  if (logit > 700.0) return 1.0;
  if (logit < -700.0) return 0.0;
  return 1.0 / (1.0 + pmath::exp(-logit));
}

}  // namespace sva
