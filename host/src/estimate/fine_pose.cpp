#include "estimate/fine_pose.hpp"

#include <sva/base/parallel.hpp>
#include <sva/base/portable_math.hpp>

#include <algorithm>
#include <utility>
#include <vector>

#include "calibration/calibration.hpp"
#include "estimate/fit_problem.hpp"
#include "estimate/surface_model.hpp"

namespace sva {

using pose_fit::ContactCorrespondences;
using pose_fit::Fit;
using pose_fit::Match;
using pose_fit::MeshCorrespondences;
using pose_fit::Problem;

RefineSettings refine_settings(const PoseSpace& space, std::uint32_t fine_pose_from) {
  const PoseSpaceSpec& spec = space.spec();
  const double bin = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  RefineSettings s;
  s.planar = space.planar();
  s.min_readings = Calibration::fine_pose_start(fine_pose_from, s.planar);
  s.scale_start_mm = 2.0 * bin;
  s.scale_final_mm = 0.25 * bin;
  // Light: a training contact's normal is one noisy sample at a point near the
  // reading, not the surface's normal there (paper3d: 4 mm/rad cost accuracy).
  s.normal_weight_mm = 0.125 * bin;
  return s;
}

RefineSettings with_runs_side_by_side(const RefineSettings& settings, std::size_t runs) {
  RefineSettings s = settings;
  const unsigned threads = settings.threads ? settings.threads : util::default_threads();
  s.reading_threads = runs < threads ? threads : 1;
  return s;
}

RefinedPose refine_pose(const SurfaceIndex& surface, std::uint32_t object, std::span<const ObservedReading> readings,
                        std::span<const RigidPose> starts, const RefineSettings& settings) {
  RefinedPose out;
  if (starts.empty()) return out;
  out.pose = starts[0];
  if (readings.size() < std::max<std::size_t>(settings.min_readings, 1) || object >= surface.objects() ||
      surface.points(object).empty())
    return out;
  const ContactCorrespondences contacts(surface, object, settings);
  const Problem problem(contacts, readings, settings);
  const double final_scale = settings.scale_final_mm;
  // The starts are fitted side by side on the workers (an estimate's latency on a robot), then weighed in their own
  // order, so the answer does not depend on the thread count. The first start's run gives its unrefined fit.
  std::vector<std::pair<RigidPose, Fit>> runs(starts.size());
  std::vector<int> observables(starts.size(), 0);
  Fit unrefined;
  util::parallel_for(
      starts.size(),
      [&](std::size_t k) { runs[k] = problem.run(starts[k], &observables[k], k == 0 ? &unrefined : nullptr); },
      settings.threads);
  out.cost = unrefined.cost;
  out.inliers = unrefined.inliers;
  // A later (less probable) mode wins only by a clear margin: half a
  // reading's outlier cost, or a quarter of the cost. Modes the shape cannot
  // tell apart (a cube's faces) fit alike, and the histogram's order stands.
  bool have = false;
  RefinedPose best;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const int observable = observables[k];
    const auto& [pose, f] = runs[k];
    const double margin = std::max(final_scale * final_scale / 12.0, 0.25 * best.cost);
    if (have && !(f.cost < best.cost - margin)) continue;
    have = true;
    best.pose = pose;
    best.refined = true;
    best.start = k;
    best.cost = f.cost;
    best.inliers = f.inliers;
    best.observable = observable;
  }
  // Too few readings explained, or no better than the histogram's own pose:
  // keep the histogram's.
  if (best.inliers < settings.min_readings || !(best.cost < unrefined.cost)) return out;
  return best;
}

RigidPose polish_on_mesh(const SurfaceModel& model, std::uint32_t object, std::span<const ObservedReading> readings,
                         const RigidPose& start, const RefineSettings& settings, const ContactNoise& noise) {
  if (readings.size() < std::max<std::size_t>(settings.min_readings, 1) || object >= model.objects()) return start;
  RefineSettings s = settings;
  // From the model's reach down to the fine pose's final scale: the start is already within a few mm (the fit on
  // the training contacts), and the mesh's exact facets weigh the normal as the model does.
  s.scale_start_mm = noise.reach_mm;
  s.scale_final_mm = std::min(settings.scale_final_mm, noise.reach_mm);
  s.normal_weight_mm = noise.normal_weight_mm;
  const MeshCorrespondences mesh(model, object, s);
  const Problem problem(mesh, readings, s);
  int observable = 0;
  Fit unpolished;
  const auto [pose, f] = problem.run(start, &observable, &unpolished);
  return f.cost < unpolished.cost ? pose : start;
}

double surface_log2_fit(const SurfaceIndex& surface, std::uint32_t object, std::span<const ObservedReading> readings,
                        const RigidPose& pose, const RefineSettings& settings, double sigma_mm, double floor) {
  if (readings.empty() || object >= surface.objects() || surface.points(object).empty())
    return static_cast<double>(readings.size()) * pmath::log2(floor);
  const ContactCorrespondences contacts(surface, object, settings);
  const Problem problem(contacts, readings, settings);
  const Fit f = problem.fit(pose, settings.scale_final_mm);
  double bits = 0.0;
  for (const Match& m : f.matches)
    bits += pmath::log2((m.found ? pmath::exp(-0.5 * m.s2 / (sigma_mm * sigma_mm)) : 0.0) + floor);
  return bits;
}

}  // namespace sva
