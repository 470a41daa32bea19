#include "recognition/surface_check.hpp"

#include <algorithm>
#include <numeric>

namespace sva {

const CheckedObject* SurfaceCheck::find(std::uint32_t object) const {
  for (const CheckedObject& c : checked)
    if (c.object == object) return &c;
  return nullptr;
}

namespace {

// The leading touched objects by log-evidence (ties to the smaller id): an order no temperature changes.
std::vector<std::uint32_t> leading_objects(const BeliefEstimate& b, const BeliefSummary& s) {
  std::vector<std::uint32_t> order(b.level.object_log2_mass.size());
  std::iota(order.begin(), order.end(), 0u);
  const std::vector<double>& l = b.level.object_log2_mass;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return l[x] > l[y]; });
  std::vector<std::uint32_t> out;
  for (std::uint32_t o : order) {
    if (out.size() >= kSurfaceCheckObjects) break;
    if (s.touched[o] > 0) out.push_back(o);
  }
  return out;
}

}  // namespace

SurfaceCheck check_surfaces(const BayesFilter& filter, const BeliefEstimate& b, const SurfaceIndex& surface,
                            const RefineSettings& settings, bool estimate_modes_are_own) {
  SurfaceCheck check;
  if (filter.readings() < settings.min_readings) return check;
  const BeliefSummary& s = b.summary;
  const std::vector<std::uint32_t> leading = leading_objects(b, s);
  if (leading.size() < 2) return check;
  const double sigma = kSurfaceSigmaOfScale * settings.scale_final_mm;
  check.log2_fit.assign(b.level.object_log2_mass.size(), 0.0);
  double worst = 0.0;
  for (std::uint32_t o : leading) {
    CheckedObject c;
    c.object = o;
    c.best_key = s.best_key[o];
    const bool own = estimate_modes_are_own && o == b.object && b.pose_valid && !b.modes.empty();
    const std::vector<RigidPose> starts =
        own ? b.modes : object_modes(filter.belief(), filter.space(), c.best_key, b.modes.empty() ? 1 : b.modes.size());
    c.parabolic_pose = starts.front();
    c.fine = refine_pose(surface, o, filter.observed(), starts, settings);
    const double fit = surface_log2_fit(surface, o, filter.observed(), c.fine.pose, settings, sigma, kSurfaceFloor);
    check.log2_fit[o] = fit;
    worst = check.checked.empty() ? fit : std::min(worst, fit);
    check.checked.push_back(c);
  }
  for (std::uint32_t o = 0; o < check.log2_fit.size(); ++o)
    if (!check.find(o)) check.log2_fit[o] = worst;
  return check;
}

}  // namespace sva
