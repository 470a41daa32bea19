#include "estimate/pose_prior.hpp"

#include <sva/base/so3.hpp>

#include <algorithm>
#include <numbers>

#include "belief/belief_math.hpp"

namespace sva {

std::vector<BinOffset> order_by_pose_prior(std::vector<BinOffset> bins, const PoseWeighting& prior) {
  if (prior.empty()) return bins;
  std::vector<std::pair<double, BinOffset>> scored;
  for (const BinOffset& b : bins)
    scored.push_back({belief_math::units_to_bits(b.offset) + prior.log2_weight(b.key), b});
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; i < bins.size(); ++i) bins[i] = scored[i].second;
  return bins;
}

std::uint64_t best_bin_under_prior(const BeliefState& belief, const BeliefSummary& s, std::uint32_t object,
                                   const PoseWeighting& prior) {
  std::uint64_t best = s.best_key[object];
  double score = belief_math::units_to_bits(s.best_offset[object]) + prior.log2_weight(best);
  for (const BinOffset& b : belief.best_bins(kPosePriorCandidates)) {
    if (PoseSpace::object_of(b.key) != object) continue;
    const double v = belief_math::units_to_bits(b.offset) + prior.log2_weight(b.key);
    if (v > score || (v == score && b.key < best)) best = b.key, score = v;
  }
  return best;
}

PoseWeighting::PoseWeighting(std::vector<std::optional<PosePrior>> per_object, const PoseSpace& space)
    : per_object_(std::move(per_object)), space_(&space) {
  bool any = false;
  for (const auto& p : per_object_) any = any || p.has_value();
  if (!any) per_object_.clear();
}

double PoseWeighting::log2_weight(std::uint32_t object, const RigidPose& grid_pose) const {
  if (!applies_to(object)) return 0.0;
  const PosePrior& p = *per_object_[object];
  const RigidPose pose = space_->to_robot(grid_pose);
  const glm::dvec3 d = pose.T - p.position;
  double nats = 0.5 * glm::dot(d, d) / (p.position_sigma_mm * p.position_sigma_mm);
  if (p.has_rotation) {
    const double a = so3::angle(glm::transpose(p.rotation) * pose.R);
    nats += 0.5 * a * a / (p.rotation_sigma_rad * p.rotation_sigma_rad);
  }
  return -nats / std::numbers::ln2;
}

double PoseWeighting::log2_weight(std::uint64_t key) const {
  const std::uint32_t object = PoseSpace::object_of(key);
  return applies_to(object) ? log2_weight(object, space_->centre(key)) : 0.0;
}

}  // namespace sva
