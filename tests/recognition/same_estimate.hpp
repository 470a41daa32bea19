#pragma once
// Two estimates equal in every figure, bit for bit (a batch against sessions alone, one backend against another).
#include <sva/recognizer.hpp>

namespace sva::test {

inline bool same_pose(const RigidPose& a, const RigidPose& b) { return a.R == b.R && a.T == b.T; }

// Every figure of two estimates, bit for bit.
inline bool same(const Estimate& a, const Estimate& b) {
  bool ok = a.ready == b.ready && a.readings == b.readings && a.object == b.object && a.object_name == b.object_name &&
            a.object_probability == b.object_probability && a.p_unknown == b.p_unknown && same_pose(a.pose, b.pose) &&
            same_pose(a.parabolic_pose, b.parabolic_pose) && same_pose(a.bin_pose, b.bin_pose) &&
            a.pose_refined == b.pose_refined && a.pose_valid == b.pose_valid && a.top.size() == b.top.size() &&
            a.hypotheses.size() == b.hypotheses.size() && a.object_hypotheses.size() == b.object_hypotheses.size() &&
            a.votes == b.votes && a.votes_outside == b.votes_outside && a.votes_zero == b.votes_zero &&
            a.evidence.pairs_log2_mass == b.evidence.pairs_log2_mass &&
            a.evidence.surface_log2_fit == b.evidence.surface_log2_fit &&
            a.evidence.temperature == b.evidence.temperature && a.evidence.surface_weight == b.evidence.surface_weight;
  for (std::size_t i = 0; ok && i < a.top.size(); ++i)
    ok = a.top[i].object == b.top[i].object && a.top[i].probability == b.top[i].probability &&
         same_pose(a.top[i].pose, b.top[i].pose);
  const auto same_hypothesis = [](const PoseHypothesis& x, const PoseHypothesis& y) {
    return x.object == y.object && x.probability == y.probability && same_pose(x.pose, y.pose) &&
           x.covariance == y.covariance && x.valid == y.valid;
  };
  for (std::size_t i = 0; ok && i < a.hypotheses.size(); ++i) ok = same_hypothesis(a.hypotheses[i], b.hypotheses[i]);
  for (std::size_t i = 0; ok && i < a.object_hypotheses.size(); ++i)
    ok = same_hypothesis(a.object_hypotheses[i], b.object_hypotheses[i]);
  return ok;
}

}  // namespace sva::test
