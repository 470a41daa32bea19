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

// The measurement model's bits for the leading objects: each leading fit's pose polished on each object's own mesh
// (the same starts for every object, so that copies of one mesh still score alike), the best start by the contacts,
// then that pose with the pad's images too (36 surface queries a reading: only at the pose that counts). The
// polishes, leading objects times starts, are the surface check's work: they run side by side on the workers, one
// task each (a many-core host had one worker per object, each polishing its starts in turn), and are weighed in the
// starts' order afterwards, so the bits do not depend on the thread count.
std::vector<double> model_bits(const SurfaceModel& model, const Fits& fits, std::span<const ObservedReading> readings,
                               const RefineSettings& settings, const ContactNoise& noise) {
  ContactNoise contacts = noise;
  contacts.pad_sigma_mm = 0.0;
  const std::size_t n = fits.leading.size();
  const RefineSettings side_by_side = with_runs_side_by_side(settings, n * n);
  std::vector<RigidPose> pose(n * n);  // [object i * n + start j]
  std::vector<double> bits(n * n, 0.0);
  util::parallel_for(
      n * n,
      [&](std::size_t t) {
        const std::uint32_t object = fits.leading[t / n].object;
        pose[t] = polish_on_mesh(model, object, readings, fits.leading[t % n].fine.pose, side_by_side, contacts);
        bits[t] = model.log2_likelihood(object, readings, pose[t], contacts);
      },
      settings.threads);
  std::vector<double> out(n, 0.0);
  std::vector<std::size_t> best(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 1; j < n; ++j)
      if (bits[i * n + j] > bits[i * n + best[i]]) best[i] = j;
    out[i] = bits[i * n + best[i]];
  }
  if (!(noise.pad_sigma_mm > 0.0)) return out;
  // The pad's images: 36 surface queries a reading, each (object, reading) a task of its own, summed in the readings'
  // order as SurfaceModel::log2_likelihood sums them.
  const std::size_t m = readings.size();
  std::vector<double> term(n * m, 0.0);
  util::parallel_for(
      n * m,
      [&](std::size_t t) {
        const std::size_t i = t / m;
        term[t] = model.log2_likelihood(fits.leading[i].object, readings[t % m], pose[i * n + best[i]], noise);
      },
      settings.threads);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = 0.0;
    for (std::size_t k = 0; k < m; ++k) out[i] += term[i * m + k];
  }
  return out;
}

}  // namespace

Verification verify_candidates(const Fits& fits, std::span<const ObservedReading> readings, const SurfaceIndex& surface,
                               const RefineSettings& settings, std::size_t objects, const SurfaceModel* model) {
  Verification v;
  if (fits.leading.empty()) return v;
  const double sigma = kSurfaceSigmaOfScale * settings.scale_final_mm;
  std::vector<double> bits(fits.leading.size(), 0.0);
  if (model) {
    bits = model_bits(*model, fits, readings, settings, contact_noise(settings));
  } else {
    util::parallel_for(
        fits.leading.size(),
        [&](std::size_t i) {
          const FittedObject& f = fits.leading[i];
          bits[i] = surface_log2_fit(surface, f.object, readings, f.fine.pose, settings, sigma, kSurfaceFloor);
        },
        settings.threads);
  }
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
