#pragma once
// The belief over (object, pose bin) in the log domain (DESIGN 4, Eq 3-5).
// Every pair factor has a floor: factor(x) = eps + S_p(x), with S_p the pair's
// votes normalised over the whole space. The common eps^P cancels, so the
// belief is stored as offset(x) = sum_p log(1 + S_p(x) / eps) for touched bins
// only; every untouched bin has offset 0 (the shared baseline).
#include <cstdint>
#include <vector>

#include <sva/pose.hpp>

#include "recognition/bin_accumulator.hpp"
#include "recognition/pose_space.hpp"
#include "recognition/vote_backend.hpp"

namespace sva {

struct BinHypothesis {
  std::uint64_t key = 0;
  std::uint32_t object = 0;
  RigidPose pose;          // bin centre
  double probability = 0;  // posterior mass of the bin
};

struct BeliefEstimate {
  std::uint32_t object = 0;
  std::vector<double> object_probability;  // sums to 1
  bool pose_valid = false;                 // the best object has a touched bin
  std::uint64_t best_key = 0;
  RigidPose pose;       // refined below the bin size: per-axis parabolic peak of the log-belief around the best bin
  RigidPose bin_pose;   // centre of the best bin
  std::vector<BinHypothesis> top;
};

class Belief {
 public:
  Belief(const PoseSpace& space, double eps);

  // Multiplies in one pair factor. A pair with no vote mass leaves the belief
  // unchanged (it carries no information about the pose). Returns whether it folded.
  bool fold(const PairVotes& votes);
  void reset();

  std::size_t touched() const { return offset_.size(); }
  std::size_t pairs_folded() const { return pairs_; }
  double eps() const { return eps_; }
  // Offset of a bin (0 when untouched).
  double offset(std::uint64_t key) const;
  // Posterior per object (untouched bins counted at the baseline).
  std::vector<double> object_probability() const;
  BeliefEstimate estimate(std::size_t top_k) const;

 private:
  struct Sorted {
    std::vector<std::uint64_t> keys;
    std::vector<double> offsets;
    double max_offset = 0.0;
  };
  Sorted sorted() const;
  std::vector<double> object_log_mass(const Sorted& s) const;  // log of mass relative to exp(max_offset)
  double offset_in(const Sorted& s, const BinIndex& b) const;
  double axis_shift(const Sorted& s, const BinIndex& c, bool rotation, int k) const;
  RigidPose refine(const Sorted& s, std::uint64_t best) const;

  const PoseSpace* space_;
  double eps_;
  BinTable<double> offset_;
  std::size_t pairs_ = 0;
};

}  // namespace sva
