#include "recognition/surface_check.hpp"

#include <sva/base/parallel.hpp>

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
  // Each object's starts come from the belief (one caller at a time); its fits, on the host alone, run side by side
  // on the workers and are kept in the leading order.
  std::vector<CheckedObject> checked(leading.size());
  std::vector<std::vector<RigidPose>> starts(leading.size());
  for (std::size_t i = 0; i < leading.size(); ++i) {
    const std::uint32_t o = leading[i];
    checked[i].object = o;
    checked[i].best_key = s.best_key[o];
    const bool own = estimate_modes_are_own && o == b.object && b.pose_valid && !b.modes.empty();
    starts[i] =
        own ? b.modes
            : object_modes(filter.belief(), filter.space(), s.best_key[o], b.modes.empty() ? 1 : b.modes.size());
    checked[i].parabolic_pose = starts[i].front();
  }
  std::vector<double> fits(leading.size(), 0.0);
  util::parallel_for(
      leading.size(),
      [&](std::size_t i) {
        CheckedObject& c = checked[i];
        c.fine = refine_pose(surface, c.object, filter.observed(), starts[i], settings);
        fits[i] = surface_log2_fit(surface, c.object, filter.observed(), c.fine.pose, settings, sigma, kSurfaceFloor);
      },
      settings.threads);
  check.log2_fit.assign(b.level.object_log2_mass.size(), 0.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < leading.size(); ++i) {
    check.log2_fit[leading[i]] = fits[i];
    worst = i == 0 ? fits[i] : std::min(worst, fits[i]);
  }
  check.checked = std::move(checked);
  for (std::uint32_t o = 0; o < check.log2_fit.size(); ++o)
    if (!check.find(o)) check.log2_fit[o] = worst;
  return check;
}

}  // namespace sva
