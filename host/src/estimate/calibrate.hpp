#pragma once
// Stage 4 of the estimate (estimate/pipeline.hpp): the calibrated object posterior and "none of these"
// (docs/recognition.md, "Calibration"). The map's calibration (calibration/calibration.hpp, learned when the map
// was trained: training/) tempers each object's log-evidence, adds the verify stage's surface bits with its learned
// weight, recalibrates the top object's probability and reads "none of these" from how well the best object's
// surface explains the readings. It may name another leading object than the belief's best: the report then takes
// that object's fit.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "calibration/calibration.hpp"
#include "estimate/candidates.hpp"
#include "estimate/fit.hpp"
#include "estimate/verify.hpp"

namespace sva {

// What the calibration reads after `readings` readings: the candidates' evidence level, the fit of the belief's
// own best object (its cost share, from `settings.min_readings` readings on) and the surfaces' bits. The
// calibration's held-out sessions record it (training/held_out_sessions.hpp), so it is the one reading of the
// stages' results that learning and recognition share.
EvidenceLevel evidence_after(const Candidates& c, const Fits& fits, const Verification& v, std::size_t readings,
                             const RefineSettings& settings);

struct CalibratedPosterior {
  std::uint32_t object = 0;                // the best object; a leading object other than the belief's best when
                                           // the surfaces' bits lift it
  std::vector<double> object_probability;  // sums to 1
  double p_unknown = 0.0;                  // "none of these" (0 without a calibration)
  bool reweighed = false;                  // the probabilities are no longer the candidates' raw shares
  double surface_weight = 0.0;             // the weight the surfaces' bits entered with (0: they did not)
};

struct CalibrationInput {
  const Calibration* calibration = nullptr;  // none: Eq 5's raw posterior (with the surfaces' bits at weight 1)
  double temperature = 1.0;                  // the calibration's temperature at this reading count
  std::span<const double> object_weight;     // the prior over objects (largest 1; empty: flat)
  double unknown_prior = 0.1;
};

CalibratedPosterior calibrate(const Candidates& c, const Fits& fits, const Verification& v, const EvidenceLevel& level,
                              const CalibrationInput& in);

}  // namespace sva
