#pragma once
// The estimate (DESIGN 4): from any backend's belief reductions, the posterior
// per object, the best object's best bin refined below the bin size, and the
// top-k bins over all objects. Computed once, here, for every backend: each
// belief answers through BeliefState (summarise, best_bins, offsets), so no
// step here knows where the belief lives. Here too the public sva::Estimate is
// put together from it (the fine pose, the distinct hypotheses, the grid's
// frame to the robot's), so that one file answers for what a caller reads.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <sva/pose.hpp>
#include <sva/prior.hpp>
#include <sva/recognizer.hpp>

#include "belief/belief_state.hpp"
#include "calibration/calibration.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"
#include "recognition/observed_reading.hpp"
#include "recognition/pose_refinement.hpp"
#include "votes/pose_space.hpp"

namespace sva {

// A Gaussian pose prior per object (sva::PosePrior, robot frame) as log2 weights at poses of the grid: 0 at the
// mean, negative elsewhere, 0 for an object without one. The estimate adds them to the log-belief (in bits) of the
// bins it reads (docs/api.md, "Priors").
class PoseWeighting {
 public:
  PoseWeighting() = default;
  // `per_object`: empty, or one entry per object of `space` (checked by the recognizer).
  PoseWeighting(std::vector<std::optional<PosePrior>> per_object, const PoseSpace& space);
  bool empty() const { return per_object_.empty(); }
  bool applies_to(std::uint32_t object) const { return object < per_object_.size() && per_object_[object]; }
  // log2 of the prior's weight at `grid_pose` (the grid's frame) of `object`, or at the centre of bin `key`.
  double log2_weight(std::uint32_t object, const RigidPose& grid_pose) const;
  double log2_weight(std::uint64_t key) const;

 private:
  std::vector<std::optional<PosePrior>> per_object_;
  const PoseSpace* space_ = nullptr;
};

struct BinHypothesis {
  std::uint64_t key = 0;
  std::uint32_t object = 0;
  RigidPose pose;          // bin centre
  double probability = 0;  // posterior mass of the bin
};

struct BeliefEstimate {
  std::uint32_t object = 0;
  std::vector<double> object_probability;      // sums to 1 (tempered by the estimate's temperature)
  std::vector<double> raw_object_probability;  // the untempered posterior the bins' probabilities are shares of
  EvidenceLevel level;                         // what the calibration reads (its `readings` left 0)
  bool pose_valid = false;                     // the best object has a touched bin
  std::uint64_t best_key = 0;
  RigidPose pose;            // the histogram's estimate, `parabolic_pose` (the recognizer then refines it against
                             // the surface: recognition/pose_refinement.hpp, sva::Estimate::pose)
  RigidPose parabolic_pose;  // below the bin size: per-axis parabolic peak of the log-belief around the best bin
  RigidPose bin_pose;        // centre of the best bin
  // Distinct modes of the best object, best first, for the fine pose to start
  // from: the parabolic peak of the best bin, then the centres of the next best
  // bins that are not neighbours of an earlier mode (at most `modes` in all).
  std::vector<RigidPose> modes;
  std::vector<BinHypothesis> top;
  // The reductions it was read from, read once per estimate (the CPU belief sums its band of bins for them).
  BeliefSummary summary;
};

// Up to `count` distinct modes of the object of bin `best` (its best bin), best first, as BeliefEstimate::modes
// (without a pose prior): the fine pose's starts for an object other than the best one.
std::vector<RigidPose> object_modes(const BeliefState& belief, const PoseSpace& space, std::uint64_t best,
                                    std::size_t count);

// Each object's log-evidence (calibration/calibration.hpp, EvidenceLevel::object_log2_mass): log2 of its mass over
// poses relative to one bin at the maximum, untouched bins at the baseline; never -inf.
std::vector<double> object_log2_mass(const BeliefSummary& summary, const PoseSpace& space);
// What the calibration reads of a belief's reductions after `readings` readings.
EvidenceLevel evidence_level(const BeliefSummary& summary, std::size_t pairs_folded, const PoseSpace& space,
                             std::size_t readings);

// The fine pose's fit (its inliers and robust cost over `readings` readings) as the calibration reads it.
void set_surface_fit(const RefinedPose& fine, std::size_t readings, const RefineSettings& settings,
                     EvidenceLevel* level);

// The belief's total mass in the units of object_probability's (a bin at the maximum weighs 2^mass_bits).
// `object_weight`: the prior per object (largest 1; empty: flat), as in estimate().
double total_mass(const BeliefSummary& summary, const PoseSpace& space, std::span<const double> object_weight = {});
// Posterior per object from the reductions (untouched bins at the baseline).
std::vector<double> object_probability(const BeliefSummary& summary, const PoseSpace& space);
// The estimate of any backend's belief: best object, its best bin refined
// below the bin size, up to `modes` distinct modes of that object, and the
// top-k bins over all objects. `object_weight` (per object, largest 1; empty: flat) is a prior over objects: it
// scales every bin of an object (a per-object offset of log2(weight) in the log-domain belief), so it moves the
// object posterior and the bins' probabilities but not which bin of an object is best, nor the top bins' order.
// `pose_weighting` (a pose prior) moves each object's best bin to the candidate bin with the most evidence plus
// prior (candidates: the object's best bin and its bins among the best bins read for the modes), adds the prior to
// the log-belief of the parabola's bins and orders the modes by it; it leaves the object posterior and `top`
// (the evidence's best bins) as they are.
// `temperature` (calibration/calibration.hpp) tempers each object's log-evidence before the prior weighs it: 1 is
// Eq 5's product as it stands; the best object is the one of most tempered posterior.
BeliefEstimate estimate(const BeliefState& belief, const PoseSpace& space, std::size_t top_k, std::size_t modes = 1,
                        std::span<const double> object_weight = {}, const PoseWeighting& pose_weighting = {},
                        double temperature = 1.0);
// The candidates a pose prior chooses an object's best bin among: how many of the best bins (over all objects)
// are read.
constexpr std::size_t kPosePriorCandidates = 64;
// The object's best bin under a pose prior: the most evidence plus prior among its best bin and its bins among
// the kPosePriorCandidates best bins over all objects (the bins the estimate reads; an unread bin is not a
// candidate). Ties to the smaller key. `summary` is belief.summarise().
std::uint64_t best_bin_under_prior(const BeliefState& belief, const BeliefSummary& summary, std::uint32_t object,
                                   const PoseWeighting& prior);
// Bins ordered by their log-belief plus the pose prior's log2 weight, best first (ties keep best_bins' order:
// the smaller key first). Without a prior: as given.
std::vector<BinOffset> order_by_pose_prior(std::vector<BinOffset> bins, const PoseWeighting& prior);

// The public estimate (sva::Estimate, robot frame). The belief and the fine pose work in the pose grid's frame (the
// workspace frame); readings enter it through to_grid and every pose leaves it here.

// A reading in the pose grid's frame: the belief and the fine pose never see the robot frame.
ObservedReading to_grid(const PoseSpace& space, ObservedReading r);

// Before any reading there is no evidence: the object posterior is the prior (uniform without one), and no
// object, pose or hypothesis is reported, so that a caller cannot take a placeholder for an answer.
// `object_weight`: per object, largest 1; empty: flat.
Estimate not_ready_estimate(std::size_t objects, std::span<const double> object_weight);

// Method::appearance: the appearance-only posterior of [15] times the prior; no pose.
Estimate appearance_estimate(const std::vector<double>& log_posterior, const std::vector<MapObject>& objects,
                             std::span<const double> object_weight);

class BayesFilter;  // recognition/bayes_filter.hpp

// What a session's estimate asks of its belief.
struct EstimateRequest {
  std::size_t top_k = 5;  // best bins and distinct hypotheses (0: neither)
  int hypothesis_radius_bins = 1;
  std::span<const double> object_weight;     // the prior over objects (largest 1; empty: flat)
  const PoseWeighting& pose_weighting;       // the pose priors (none: empty)
  const SurfaceIndex* surface = nullptr;     // the fine pose's training contacts; none: the parabolic pose
  RefineSettings refine;                     // the fine pose's settings (with `surface`); its `threads` are the
                                             // estimate's workers, for the fits and the per-object work alike
  bool refine_pose = true;                   // Estimate::pose is the fine pose (else the fit only feeds p_unknown)
  bool surface_check = true;                 // with `surface`: weigh the leading objects by their surfaces' fits
  const Calibration* calibration = nullptr;  // none: Eq 5's raw posterior and p_unknown = unknown_prior
  double unknown_prior = 0.1;
};

// Method::sva: the estimate of the filter's belief, refined against the surface when there is one, in the robot
// frame, with the distinct hypotheses (hypotheses[0] carries Estimate::pose).
Estimate filter_estimate(const BayesFilter& filter, const std::vector<MapObject>& objects, const EstimateRequest& r);

// What filter_estimate's calibration reads of the filter (the evidence level, with the fine pose's fit from the same
// starts), without the rest of the estimate: the calibration's held-out sessions.
EvidenceLevel calibration_evidence(const BayesFilter& filter, const SurfaceIndex& surface,
                                   const RefineSettings& settings, bool surface_check = true);

}  // namespace sva
