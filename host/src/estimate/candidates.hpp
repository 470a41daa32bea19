#pragma once
// Stage 1 of the estimate (estimate/pipeline.hpp): the candidates, read from the belief and nothing else. Every
// backend's belief answers through BeliefState (summarise, best_bins, offsets), so no stage after this one knows
// where the belief lives, and none reads it again: the object posterior as the pairs give it, the best object's
// best bin refined below the bin size and its distinct modes, the leading objects with the modes the fit starts
// from, the top bins and the distinct hypotheses.
#include <cstdint>
#include <span>
#include <vector>

#include <sva/pose.hpp>

#include "belief/belief_state.hpp"
#include "calibration/calibration.hpp"
#include "estimate/hypotheses.hpp"
#include "estimate/pose_prior.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct BinHypothesis {
  std::uint64_t key = 0;
  std::uint32_t object = 0;
  RigidPose pose;          // bin centre
  double probability = 0;  // posterior mass of the bin
};

// A leading object by log-evidence, with the modes its fine pose starts from (its own, without a pose prior, so
// that a pose prior moves the pose and never the object posterior).
struct LeadingObject {
  std::uint32_t object = 0;
  std::uint64_t best_key = 0;     // its best bin
  std::vector<RigidPose> starts;  // best first: its best bin's parabolic peak, then distinct modes
};

struct Candidates {
  std::uint32_t object = 0;
  std::vector<double> object_probability;      // sums to 1 (tempered by the request's temperature)
  std::vector<double> raw_object_probability;  // the untempered posterior the bins' probabilities are shares of
  EvidenceLevel level;                         // what the calibration reads (its `readings` left 0)
  bool pose_valid = false;                     // the best object has a touched bin
  std::uint64_t best_key = 0;
  RigidPose pose;            // the histogram's estimate, `parabolic_pose` (the fit stage then refines it)
  RigidPose parabolic_pose;  // below the bin size: per-axis parabolic peak of the log-belief around the best bin
  RigidPose bin_pose;        // centre of the best bin
  // Distinct modes of the best object, best first, for the fine pose to start from: the parabolic peak of the best
  // bin, then the centres of the next best bins that are not neighbours of an earlier mode (at most `modes`).
  std::vector<RigidPose> modes;
  std::vector<BinHypothesis> top;
  // The leading touched objects by log-evidence (CandidateRequest::leading of them), best first; empty unless
  // asked for and at least two objects are touched.
  std::vector<LeadingObject> leading;
  HypothesisSet hypotheses;  // the distinct modes over all objects (CandidateRequest::hypotheses)
  // The reductions it was read from, read once per estimate (the CPU belief sums its band of bins for them).
  BeliefSummary summary;
};

struct CandidateRequest {
  std::size_t top_k = 5;                          // best bins
  std::size_t modes = 1;                          // distinct modes of the best object
  std::span<const double> object_weight;          // a prior over objects (largest 1; empty: flat)
  const PoseWeighting* pose_weighting = nullptr;  // the pose priors (none: null or empty)
  // Tempers each object's log-evidence before the prior weighs it (calibration/calibration.hpp): 1 is Eq 5's
  // product as it stands; the best object is the one of most tempered posterior.
  double temperature = 1.0;
  std::size_t leading = 0;  // leading objects to give fit starts for (0: none)
  bool hypotheses = false;  // distinct hypotheses over all objects, `top_k` of them
  int hypothesis_radius_bins = 1;
  unsigned threads = 0;  // workers for the hypotheses' per-object work (0: all cores)
};

// The candidates of any backend's belief. `object_weight` scales every bin of an object, so it moves the object
// posterior and the bins' probabilities but not which bin of an object is best, nor the top bins' order. A pose
// prior moves each object's best bin to the candidate bin with the most evidence plus prior (among the object's
// best bin and its bins among the best bins read for the modes), adds the prior to the log-belief of the
// parabola's bins and orders the modes by it; it leaves the object posterior and `top` as they are.
Candidates find_candidates(const BeliefState& belief, const PoseSpace& space, const CandidateRequest& request);
// The most best bins find_candidates asks of a belief for `request` (its top bins, the modes' and hypotheses'
// candidates, a pose prior's): what a device reads ahead for many sessions at once (VoteBackend::read_ahead).
std::size_t best_bins_asked(const CandidateRequest& request);
// How keys_read chooses its keys for `request`, for a device to choose them after an update (off where a pose prior
// orders more candidates than one device invocation sorts: kPriorMostCandidates).
KeyChoice key_choice(const CandidateRequest& request);
// The bins find_candidates reads by key (BeliefState::offsets) for `request`, from what the belief's summary and best
// bins say: the neighbourhoods of the hypotheses' centres, which hold every parabola's bins (VoteBackend::
// look_up_ahead). A pose prior may move a best bin outside them; that read then goes to the belief alone.
std::vector<std::uint64_t> keys_read(const BeliefState& belief, const PoseSpace& space,
                                     const CandidateRequest& request);

}  // namespace sva
