#include "estimate/verify.hpp"

#include <sva/base/parallel.hpp>

#include <algorithm>

namespace sva {

Verification verify_candidates(const Fits& fits, std::span<const ObservedReading> readings, const SurfaceIndex& surface,
                               const RefineSettings& settings, std::size_t objects) {
  Verification v;
  if (fits.leading.empty()) return v;
  const double sigma = kSurfaceSigmaOfScale * settings.scale_final_mm;
  std::vector<double> bits(fits.leading.size(), 0.0);
  util::parallel_for(
      fits.leading.size(),
      [&](std::size_t i) {
        const FittedObject& f = fits.leading[i];
        bits[i] = surface_log2_fit(surface, f.object, readings, f.fine.pose, settings, sigma, kSurfaceFloor);
      },
      settings.threads);
  v.log2_fit.assign(objects, 0.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    v.log2_fit[fits.leading[i].object] = bits[i];
    worst = i == 0 ? bits[i] : std::min(worst, bits[i]);
  }
  for (std::uint32_t o = 0; o < objects; ++o)
    if (!fits.find(o)) v.log2_fit[o] = worst;
  return v;
}

}  // namespace sva
