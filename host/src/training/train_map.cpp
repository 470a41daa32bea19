// Training a map (sva::Map::train): the pair map is built (map/map_builder.hpp), then its calibration is learned
// from recognition sessions on training readings it never saw (training/calibration_fit.hpp). Learning sits above
// recognition, which reads the calibration the map carries (calibration/calibration.hpp): map building never runs
// the recogniser.
#include <sva/base/float_environment.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <chrono>
#include <memory>
#include <string>

#include "map/map_access.hpp"
#include "map/map_builder.hpp"
#include "map/map_file.hpp"
#include "map/pair_map.hpp"
#include "training/calibration_fit.hpp"

namespace sva {

namespace {

// The map's calibration: learned from held-out training readings, or the default with the reason in the report.
Calibration calibration_for(const Dataset& data, const TrainParameters& params, const TrainOptions& options,
                            TrainReport* report) {
  std::string note;
  Calibration c;
  const auto start = std::chrono::steady_clock::now();
  if (!options.calibrate) {
    note = "calibration off: the default temperature, no \"none of these\"";
  } else if (data.scene.objects.size() < 2) {
    note = "one object: nothing to calibrate";
  } else {
    CalibrationOptions co;
    co.held_out_share = options.calibration_held_out;
    co.sessions.known_sessions = options.calibration_sessions;
    co.sessions.unknown_sessions = (options.calibration_sessions + 1) / 2;
    co.sessions.readings = options.calibration_readings;
    co.sessions.fine_pose_from = options.fine_pose_from.value_or(0);
    co.surfaces = options.surfaces;
    try {
      c = learn_calibration(data, params, co);
    } catch (const Interrupted&) {
      throw;
    } catch (const Error& e) {
      // Too few readings to hold some out is not the user's error: the map is still good, with the default.
      c = Calibration{};
      note = std::string("the default calibration: it could not be learned (") + e.what() + ")";
    }
  }
  if (report) {
    report->calibration_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report->calibration_note = note;
  }
  return c;
}

}  // namespace

Map Map::train(const Dataset& data, const TrainOptions& options, TrainReport* report) {
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
  const TrainParameters params = resolve_train_parameters(data.scene, options);
  if (!options.surfaces.empty() && options.surfaces.size() != data.scene.objects.size())
    throw Error("train: " + std::to_string(options.surfaces.size()) + " surfaces for the scene's " +
                std::to_string(data.scene.objects.size()) + " objects (one per object, or none)");
  std::shared_ptr<PairMap> map = train_pair_map(data, params, report);
  map->surfaces = options.surfaces;
  validate_pair_map(*map, "train: the objects' surfaces");  // before the calibration trains on them
  map->calibration = calibration_for(data, params, options, report);
  map->calibration.fine_pose_from = options.fine_pose_from.value_or(0);
  map->calibration.fine_pose_from = map->fine_pose_from();  // the pose space's default said, when none was asked
  return MapAccess::wrap(std::move(map));
}

}  // namespace sva
