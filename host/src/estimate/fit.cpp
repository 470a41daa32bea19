#include "estimate/fit.hpp"

#include <sva/base/parallel.hpp>

namespace sva {

const FittedObject* Fits::find(std::uint32_t object) const {
  for (const FittedObject& f : leading)
    if (f.object == object) return &f;
  return nullptr;
}

Fits fit_candidates(const Candidates& c, std::span<const ObservedReading> readings, const SurfaceIndex* surface,
                    const RefineSettings& settings, bool modes_are_own) {
  Fits fits;
  if (!surface || !c.pose_valid) return fits;
  fits.leading.resize(c.leading.size());
  std::size_t runs = 0;  // every leading object's starts run side by side
  for (const LeadingObject& l : c.leading) runs += l.starts.size();
  const RefineSettings side_by_side = with_runs_side_by_side(settings, runs);
  util::parallel_for(
      c.leading.size(),
      [&](std::size_t i) {
        const LeadingObject& l = c.leading[i];
        FittedObject& f = fits.leading[i];
        f.object = l.object;
        f.best_key = l.best_key;
        f.parabolic_pose = l.starts.front();
        f.fine = refine_pose(*surface, l.object, readings, l.starts, side_by_side);
      },
      settings.threads);
  const FittedObject* own = modes_are_own ? fits.find(c.object) : nullptr;
  fits.best =
      own ? own->fine
          : refine_pose(*surface, c.object, readings, c.modes, with_runs_side_by_side(settings, c.modes.size()));
  return fits;
}

}  // namespace sva
