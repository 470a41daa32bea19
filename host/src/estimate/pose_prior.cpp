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

std::vector<float> PoseWeighting::device_terms() const {
  std::vector<float> out;
  if (empty()) return out;
  out.assign(per_object_.size() * kPriorDeviceFloats, 0.0f);
  // The robot frame is the workspace times the grid's: a mean moved into the grid's frame keeps every distance and
  // every angle (log2_weight measures in the robot's).
  const RigidPose& w = space_->spec().workspace;
  const glm::dmat3 wt = glm::transpose(w.R);
  for (std::size_t o = 0; o < per_object_.size(); ++o) {
    if (!per_object_[o]) continue;
    const PosePrior& p = *per_object_[o];
    float* t = out.data() + o * kPriorDeviceFloats;
    const glm::dvec3 mean = wt * (p.position - w.T);
    t[0] = 1.0f;
    for (int k = 0; k < 3; ++k) t[1 + k] = static_cast<float>(mean[k]);
    t[4] = static_cast<float>(0.5 / (p.position_sigma_mm * p.position_sigma_mm) / std::numbers::ln2);
    if (p.has_rotation) {
      t[5] = static_cast<float>(0.5 / (p.rotation_sigma_rad * p.rotation_sigma_rad) / std::numbers::ln2);
      const glm::dmat3 r = wt * p.rotation;
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) t[6 + 3 * c + k] = static_cast<float>(r[c][k]);
    }
  }
  return out;
}

double PoseWeighting::log2_weight(std::uint64_t key) const {
  const std::uint32_t object = PoseSpace::object_of(key);
  return applies_to(object) ? log2_weight(object, space_->centre(key)) : 0.0;
}

}  // namespace sva
