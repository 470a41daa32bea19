#include "estimate/verify.hpp"

#include <sva/base/parallel.hpp>

#include <algorithm>

#include "votes/pose_space.hpp"

namespace sva {

ContactNoise contact_noise(const RefineSettings& settings) {
  ContactNoise n;
  n.sigma_mm = kSurfaceSigmaOfScale * settings.scale_final_mm;
  n.normal_weight_mm = n.sigma_mm / kMeshTiltSigma;
  n.floor = kSurfaceFloor;
  n.reach_mm = 4.0 * n.sigma_mm;
  n.pad_sigma_mm = kPadSigmaMm;
  return n;
}

PadGeometry pad_geometry(const PairMap& map) {
  const SensorCalibration& c = map.appearance.calibration;
  PadGeometry pad;
  pad.rows = c.sensor.rows, pad.cols = c.sensor.cols, pad.pitch_mm = c.sensor.pitch_mm;
  pad.contact_depth_mm = c.contact_threshold_kpa / c.stiffness_kpa_per_mm;
  return pad;
}

std::unique_ptr<SurfaceModel> surface_model_of(const PairMap& map) {
  if (map.surfaces.empty()) return nullptr;
  const PoseSpace space(map.pose_space, static_cast<std::uint32_t>(map.objects.size()));
  return std::make_unique<SurfaceModel>(map.surfaces, contact_noise(refine_settings(space, 0)).reach_mm,
                                        pad_geometry(map));
}

namespace {

// The measurement model's bits for one leading object: each leading fit's pose polished on the object's own mesh
// (the same starts for every object, so that copies of one mesh still score alike), the best of them by the contacts,
// then that one with the pad's images too (36 surface queries a reading: only at the pose that counts).
double model_bits(const SurfaceModel& model, std::uint32_t object, const Fits& fits,
                  std::span<const ObservedReading> readings, const RefineSettings& settings,
                  const ContactNoise& noise) {
  ContactNoise contacts = noise;
  contacts.pad_sigma_mm = 0.0;
  double best = 0.0;
  RigidPose best_pose;
  for (std::size_t j = 0; j < fits.leading.size(); ++j) {
    const RigidPose pose = polish_on_mesh(model, object, readings, fits.leading[j].fine.pose, settings, contacts);
    const double b = model.log2_likelihood(object, readings, pose, contacts);
    if (j == 0 || b > best) best = b, best_pose = pose;
  }
  return noise.pad_sigma_mm > 0.0 ? model.log2_likelihood(object, readings, best_pose, noise) : best;
}

}  // namespace

Verification verify_candidates(const Fits& fits, std::span<const ObservedReading> readings, const SurfaceIndex& surface,
                               const RefineSettings& settings, std::size_t objects, const SurfaceModel* model) {
  Verification v;
  if (fits.leading.empty()) return v;
  const double sigma = kSurfaceSigmaOfScale * settings.scale_final_mm;
  const ContactNoise noise = contact_noise(settings);
  std::vector<double> bits(fits.leading.size(), 0.0);
  util::parallel_for(
      fits.leading.size(),
      [&](std::size_t i) {
        const FittedObject& f = fits.leading[i];
        bits[i] = model ? model_bits(*model, f.object, fits, readings, settings, noise)
                        : surface_log2_fit(surface, f.object, readings, f.fine.pose, settings, sigma, kSurfaceFloor);
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
