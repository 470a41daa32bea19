#pragma once
// Learning the calibration (calibration.hpp) when a map is trained: the held-out split, the calibration map and
// its sessions (held_out_sessions.hpp), then the fits. Deterministic: the same dataset and seed give the same
// calibration whatever the thread count.
#include <sva/dataset.hpp>

#include <vector>

#include "calibration/calibration.hpp"
#include "map/map_builder.hpp"
#include "training/held_out_sessions.hpp"

namespace sva {

struct CalibrationOptions {
  double held_out_share = 0.1;  // of each known object's readings
  HeldOutSessionOptions sessions;
  std::vector<ObjectSurface> surfaces;  // the map's (one per object of the scene), or none
};

// Temperature: scale and power minimising the negative log-likelihood of the true object over every step from 2
// readings on of the known sessions (a grid over the power, golden-section search over log2 scale).
void fit_temperature(const std::vector<CalibrationSession>& sessions, Calibration* calibration);
// The top label (Calibration::top_label), after the temperature: per regime (before the fine pose, from it on), a
// logistic regression of "the top object is right" on the logit of its tempered probability over every step from 2
// readings on of the known sessions, each step weighed alike (Platt scaling). A regime without both right and wrong
// steps keeps the identity.
void fit_top_label(const std::vector<CalibrationSession>& sessions, Calibration* calibration);
// "None of these": two logistic regressions of unknown against known sessions, each coefficient linear in log(n - 1)
// (the features drift with the reading count; one model per count had only the sessions' 90 steps of that count
// each, and held its last count's model past the sessions' length), the two kinds weighted equally, with a small
// ridge (Newton's method). The evidence model, over every step from 2 readings on, on the three features of
// earlier builds, is read before the fine pose; the fit model, over the steps with a fine pose, on the log of its
// cost share, from the fine pose on (calibration.hpp). Written out per reading count to twice the sessions' length.
// Sessions too short for a fine pose give the evidence model alone (the features of earlier builds). Leaves the
// model empty without unknown sessions.
void fit_unknown(const std::vector<CalibrationSession>& sessions, Calibration* calibration);

// Light estimates' calibration (Calibration::light), after the rest: the same fits on the sessions' light view (each
// step without its fine pose and surface check), the temperature over every step, the top label over the steps from
// the sessions' first fine pose on, "none of these" from the evidence alone (`sessions`: known and unknown). None
// when no step has a fine pose.
void fit_light(const std::vector<CalibrationSession>& tempering, const std::vector<CalibrationSession>& sessions,
               Calibration* calibration);

// The whole learning: split `data`, train a calibration map with `params` on the kept part, run the sessions, fit
// "none of these"; then the same on a map of every object (readings alone held out), whose sessions fit the
// temperature, the surface weight and the top label.
Calibration learn_calibration(const Dataset& data, const TrainParameters& params, const CalibrationOptions& options);

}  // namespace sva
