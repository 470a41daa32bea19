#pragma once
// The estimate, as stages called in order (docs/architecture.md), data flowing one way:
//
//   1. candidates (estimate/candidates.hpp): read from the belief, the only stage that reads it: the objects'
//      evidence, the best object's best bin, parabolic peak and modes, the leading objects and their starts, the
//      top bins and the distinct hypotheses;
//   2. fit (estimate/fit.hpp): the fine pose of the best object and of each leading object;
//   3. verify (estimate/verify.hpp): how well each leading object's surface explains every reading;
//   4. calibrate (estimate/calibrate.hpp): the tempered, recalibrated posterior and "none of these";
//   5. report (estimate/report.hpp): the public sva::Estimate, in the robot frame.
//
// The recognizers run all five; the calibration's held-out sessions (training/) run the first three and read what
// stage 4 would (estimate_evidence), so that the calibration learns from exactly what recognition computes.
#include <cstddef>
#include <span>
#include <vector>

#include <sva/recognizer.hpp>

#include "belief/belief_state.hpp"
#include "calibration/calibration.hpp"
#include "estimate/candidates.hpp"
#include "estimate/fine_pose.hpp"
#include "estimate/pose_prior.hpp"
#include "estimate/surface_model.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"
#include "votes/pose_space.hpp"

namespace sva {

// What the estimate reads of a session: its belief, its pose space and its readings (grid frame, oldest first).
struct EstimateInput {
  const BeliefState& belief;
  const PoseSpace& space;
  std::span<const ObservedReading> readings;
};

// Where estimates' time went, in ms, summed over those that add to it: stage 1 (reading the belief) is timed by
// whoever calls it; stages 2, 3 and 4-5 by estimate_from.
struct EstimateStageTimes {
  double belief_ms = 0.0;     // 1: candidates (with a device's reads)
  double fit_ms = 0.0;        // 2: the fine poses
  double verify_ms = 0.0;     // 3: the surface check
  double posterior_ms = 0.0;  // 4-5: the calibrated posterior and the report
  // Under a util::SpanProbe, each stage's span (BatchRecognizer::EstimateTiming); 0 without one.
  double belief_span_ms = 0.0, fit_span_ms = 0.0, verify_span_ms = 0.0, posterior_span_ms = 0.0;
};

// What a session's estimate asks.
struct EstimateRequest {
  std::size_t top_k = 5;  // best bins and distinct hypotheses (0: neither)
  int hypothesis_radius_bins = 1;
  std::span<const double> object_weight;        // the prior over objects (largest 1; empty: flat)
  const PoseWeighting& pose_weighting;          // the pose priors (none: empty)
  const SurfaceIndex* surface = nullptr;        // the fine pose's training contacts; none: the parabolic pose
  RefineSettings refine;                        // the fine pose's settings (with `surface`); its `threads` are the
                                                // estimate's workers, for the fits and the per-object work alike
  bool refine_pose = true;                      // Estimate::pose is the fine pose (else the fit only feeds p_unknown)
  bool surface_check = true;                    // with `surface`: verify the leading objects against their surfaces
  const SurfaceModel* surface_model = nullptr;  // the map's meshes (verify's measurement model); none: the contacts
  const Calibration* calibration = nullptr;     // none: Eq 5's raw posterior and p_unknown = 0
  EstimateDepth depth = EstimateDepth::full;    // light (at_depth): the calibration's light regime applies
  double unknown_prior = 0.1;
  EstimateStageTimes* times = nullptr;  // when given, estimate_from adds its stages' times to it
};

// The request at `depth`: a light estimate is stages 1, 4 and 5 alone (no surface: the parabolic pose, no fit, no
// surface check; the calibration reads the evidence as before the fine pose exists, and from the fine pose's first
// reading count on its light regime where the map learned one: Calibration::light).
EstimateRequest at_depth(const EstimateRequest& r, EstimateDepth depth);

// The estimate of a session with at least one reading (stages 1-5).
Estimate estimate_session(const EstimateInput& in, const std::vector<MapObject>& objects, const EstimateRequest& r);
// The same in two steps: stage 1, the only one that reads the belief (a device's belief: one session at a time),
// then stages 2-5 on the host alone (many sessions' at once on the workers: BatchRecognizer::estimates).
Candidates estimate_candidates(const EstimateInput& in, const EstimateRequest& r);
Estimate estimate_from(const Candidates& c, std::span<const ObservedReading> readings, const PoseSpace& space,
                       const std::vector<MapObject>& objects, const EstimateRequest& r);
// The most best bins stage 1 asks of a session's belief after `readings` readings (VoteBackend::read_ahead).
std::size_t estimate_best_bins(const EstimateRequest& r, std::size_t readings);
// How stage 1 chooses the bins it reads by key, for a device to choose them in the next update
// (VoteBackend::read_ahead).
KeyChoice estimate_key_choice(const EstimateRequest& r, std::size_t readings);
// The bins stage 1 reads by key (VoteBackend::look_up_ahead), after the belief's summary and best bins were read.
std::vector<std::uint64_t> estimate_keys(const EstimateInput& in, const EstimateRequest& r);

// What stage 4 reads after stages 1-3, without a prior, a temperature or the report: the calibration's
// held-out sessions record it.
EvidenceLevel estimate_evidence(const EstimateInput& in, const SurfaceIndex& surface, const RefineSettings& settings,
                                bool surface_check = true, const SurfaceModel* surface_model = nullptr);

}  // namespace sva
