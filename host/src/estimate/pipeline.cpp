#include "estimate/pipeline.hpp"

#include <chrono>

#include <sva/base/parallel.hpp>
#include <sva/error.hpp>

#include "estimate/calibrate.hpp"
#include "estimate/candidates.hpp"
#include "estimate/fit.hpp"
#include "estimate/report.hpp"
#include "estimate/verify.hpp"

namespace sva {

namespace {

// Stage 1's request: the fits' starts only where stage 2 will fit (a surface, enough readings, verification on).
CandidateRequest candidate_request(const EstimateRequest& r, std::size_t readings, double temperature) {
  CandidateRequest c;
  c.top_k = r.top_k;
  c.modes = r.surface ? kFitStarts : 1;
  c.object_weight = r.object_weight;
  c.pose_weighting = &r.pose_weighting;
  c.temperature = temperature;
  c.leading = r.surface && r.surface_check && readings >= r.refine.min_readings ? kFittedObjects : 0;
  c.hypotheses = r.top_k > 0;
  c.hypothesis_radius_bins = r.hypothesis_radius_bins;
  c.threads = r.refine.threads;
  return c;
}

}  // namespace

EstimateRequest at_depth(const EstimateRequest& r, EstimateDepth depth) {
  if (depth == EstimateDepth::full) return r;
  EstimateRequest light = r;
  light.surface = nullptr;
  light.surface_model = nullptr;
  light.refine_pose = false;
  light.surface_check = false;
  light.depth = EstimateDepth::light;
  return light;
}

EstimateDepth parse_estimate_depth(const std::string& text, const std::string& option) {
  if (text == "full") return EstimateDepth::full;
  if (text == "light") return EstimateDepth::light;
  throw Error(option + " expects full or light, got \"" + text + "\"");
}

const char* estimate_depth_name(EstimateDepth depth) { return depth == EstimateDepth::light ? "light" : "full"; }

Estimate estimate_session(const EstimateInput& in, const std::vector<MapObject>& objects, const EstimateRequest& r) {
  return estimate_from(estimate_candidates(in, r), in.readings, in.space, objects, r);
}

namespace {

double temperature_at(const EstimateRequest& r, std::size_t readings) {
  return r.calibration ? r.calibration->temperature(readings, r.depth == EstimateDepth::light) : 1.0;
}

}  // namespace

Candidates estimate_candidates(const EstimateInput& in, const EstimateRequest& r) {
  const std::size_t n = in.readings.size();
  const double temperature = temperature_at(r, n);
  return find_candidates(in.belief, in.space, candidate_request(r, n, temperature));
}

std::size_t estimate_best_bins(const EstimateRequest& r, std::size_t readings) {
  return best_bins_asked(candidate_request(r, readings, 1.0));
}

KeyChoice estimate_key_choice(const EstimateRequest& r, std::size_t readings) {
  return key_choice(candidate_request(r, readings, 1.0));
}

std::vector<std::uint64_t> estimate_keys(const EstimateInput& in, const EstimateRequest& r) {
  return keys_read(in.belief, in.space, candidate_request(r, in.readings.size(), 1.0));
}

namespace {

// Milliseconds since `t0`, and restarts it.
double lap_ms(std::chrono::steady_clock::time_point* t0) {
  const auto now = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - *t0).count();
  *t0 = now;
  return ms;
}

}  // namespace

Estimate estimate_from(const Candidates& c, std::span<const ObservedReading> readings, const PoseSpace& space,
                       const std::vector<MapObject>& objects, const EstimateRequest& r) {
  const std::size_t n = readings.size();
  const double temperature = temperature_at(r, n);
  auto t0 = std::chrono::steady_clock::now();
  util::SpanLap span;
  EstimateStageTimes took;
  const Fits fits = fit_candidates(c, readings, r.surface, r.refine, r.pose_weighting.empty());
  took.fit_ms = lap_ms(&t0);
  took.fit_span_ms = span.lap_ms();
  const Verification v = r.surface
                             ? verify_candidates(fits, readings, *r.surface, r.refine, objects.size(), r.surface_model)
                             : Verification{};
  took.verify_ms = lap_ms(&t0);
  took.verify_span_ms = span.lap_ms();
  EvidenceLevel level = evidence_after(c, fits, v, n, r.refine);
  level.light_estimate = r.depth == EstimateDepth::light;
  const CalibratedPosterior p = calibrate(c, fits, v, level,
                                          {.calibration = r.calibration,
                                           .temperature = temperature,
                                           .object_weight = r.object_weight,
                                           .unknown_prior = r.unknown_prior});
  Estimate out = report(c, fits, p, space, objects, {.hypotheses = r.top_k > 0, .fine_pose = r.refine_pose});
  out.evidence = {.pairs_log2_mass = level.object_log2_mass,
                  .surface_log2_fit = v.log2_fit,
                  .temperature = temperature,
                  .surface_weight = p.surface_weight};
  took.posterior_ms = lap_ms(&t0);
  took.posterior_span_ms = span.lap_ms();
  if (r.times) {
    r.times->fit_ms += took.fit_ms;
    r.times->verify_ms += took.verify_ms;
    r.times->posterior_ms += took.posterior_ms;
    r.times->fit_span_ms += took.fit_span_ms;
    r.times->verify_span_ms += took.verify_span_ms;
    r.times->posterior_span_ms += took.posterior_span_ms;
  }
  return out;
}

EvidenceLevel estimate_evidence(const EstimateInput& in, const SurfaceIndex& surface, const RefineSettings& settings,
                                bool surface_check, const SurfaceModel* surface_model) {
  const std::size_t n = in.readings.size();
  const bool fit = n >= settings.min_readings;
  CandidateRequest cr;
  cr.top_k = 0;
  cr.modes = fit ? kFitStarts : 1;
  cr.leading = fit && surface_check ? kFittedObjects : 0;
  cr.threads = settings.threads;
  const Candidates c = find_candidates(in.belief, in.space, cr);
  const Fits fits = fit ? fit_candidates(c, in.readings, &surface, settings, true) : Fits{};
  const Verification v = verify_candidates(fits, in.readings, surface, settings, in.space.objects(), surface_model);
  return evidence_after(c, fits, v, n, settings);
}

}  // namespace sva
