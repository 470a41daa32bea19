#include "estimate/calibrate.hpp"

namespace sva {

EvidenceLevel evidence_after(const Candidates& c, const Fits& fits, const Verification& v, std::size_t readings,
                             const RefineSettings& settings) {
  EvidenceLevel level = c.level;
  level.readings = readings;
  // "None of these" reads the fit of the belief's own best object, as the calibration's sessions do.
  if (fits.best && readings >= settings.min_readings && readings > 0) {
    const double outlier_cost = settings.scale_final_mm * settings.scale_final_mm / 6.0;
    level.fit_cost_share = fits.best->cost / (outlier_cost * static_cast<double>(readings));
    level.fine_pose_from = settings.min_readings;
  }
  level.surface_log2_fit = v.log2_fit;
  return level;
}

namespace {

// The posterior with the surfaces' bits; the object it names when that is a fitted leading object (one the verify
// stage did not fit rises only through its prior, and is not followed).
void weigh_surfaces(const Candidates& c, const Fits& fits, const Verification& v, const EvidenceLevel& level,
                    const CalibrationInput& in, CalibratedPosterior* out) {
  // Uncalibrated, the surfaces' bits count as they are, each reading once.
  const double weight = in.calibration ? in.calibration->surface_weight : 1.0;
  out->surface_weight = weight;
  out->object_probability =
      tempered_posterior(level.object_log2_mass, in.temperature, in.object_weight, v.log2_fit, weight);
  std::uint32_t best = c.object;
  for (std::uint32_t o = 0; o < out->object_probability.size(); ++o)
    if (out->object_probability[o] > out->object_probability[best]) best = o;
  if (best != c.object && fits.find(best)) out->object = best;
}

}  // namespace

CalibratedPosterior calibrate(const Candidates& c, const Fits& fits, const Verification& v, const EvidenceLevel& level,
                              const CalibrationInput& in) {
  CalibratedPosterior out;
  out.object = c.object;
  out.object_probability = c.object_probability;
  out.reweighed = in.temperature != 1.0;
  if (!v.log2_fit.empty()) {
    weigh_surfaces(c, fits, v, level, in, &out);
    out.reweighed = true;
  }
  // The top label last: it keeps the top object, so the poses the report takes stand.
  if (in.calibration && level.readings >= 2) {
    in.calibration->recalibrate_top(level, &out.object_probability);
    out.reweighed = true;
  }
  out.p_unknown = in.calibration ? in.calibration->p_unknown(level, in.unknown_prior) : 0.0;
  return out;
}

}  // namespace sva
