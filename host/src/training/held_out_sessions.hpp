#pragma once
// The data the calibration learns from (calibration.hpp): training readings the map never saw.
//
// Training splits its dataset: a fifth of the objects (at least one, when there are three or more) are held out
// whole, as objects "none of these" should catch, and a share of every other object's readings is held out. A
// calibration map is trained on the rest; sessions drawn from the held-out readings (as the evaluation draws its
// trials: training/session_sampling.hpp) run on it through the CPU reference, and each step's evidence level is
// recorded. The test set is never read.
#include <sva/dataset.hpp>

#include <cstdint>
#include <vector>

#include "calibration/calibration.hpp"
#include "map/pair_map.hpp"

namespace sva {

struct CalibrationSplit {
  Dataset map_part;  // the known objects (a scene of them alone) and their readings that are not held out
  Dataset held_out;  // the held-out readings, in the full scene's object ids
  // Per object of the full scene: its id in map_part, or -1 when it is held out whole.
  std::vector<std::int32_t> map_object;
};

// `fraction`: the share of each known object's converged readings held out, in (0, 1). Deterministic in `seed`.
// `hold_out_objects` false: every object is known (the map for the temperature, calibration_fit.hpp); the same
// readings are held out of each object as with it.
CalibrationSplit split_for_calibration(const Dataset& data, double fraction, std::uint64_t seed,
                                       bool hold_out_objects = true);

struct CalibrationSession {
  bool known = true;                 // the touched object is in the map
  std::uint32_t object = 0;          // its id in the map (known) or in the full scene (unknown)
  std::vector<EvidenceLevel> steps;  // steps[n - 1]: after n readings
};

struct HeldOutSessionOptions {
  std::size_t known_sessions = 60, unknown_sessions = 30;
  std::size_t readings = 12;         // per session
  std::uint32_t fine_pose_from = 0;  // the map's choice (Calibration::fine_pose_from; 0: the pose space's default)
  std::uint64_t seed = 1;
  unsigned threads = 0;
  bool progress = false;
};

// Sessions on `map` (trained on split.map_part) from split.held_out's readings, known objects first, then unknown
// ones (none when the split holds no object out).
std::vector<CalibrationSession> run_held_out_sessions(const PairMap& map, const CalibrationSplit& split,
                                                      const HeldOutSessionOptions& options);

}  // namespace sva
