#pragma once
// The fine pose (docs/recognition.md, "Fine pose"): after the histogram has
// found the mode, a robust point-to-plane alignment of the session's readings
// (robot frame) to the object's training contacts (object frame, the map's
// surface index) moves the pose continuously below the bin size. Gauss-Newton
// on SE(3) (SE(2) with fixed z in a planar pose space) with nearest-neighbour
// correspondences of compatible normal, Tukey's loss on a shrinking scale,
// warm-started from several modes of the belief; directions the readings do
// not constrain (a plane's slide, a body of revolution's spin) keep the
// histogram's value. Host only, deterministic: the same belief and readings
// give the same pose on every backend.
#include <sva/pose.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

#include "estimate/surface_model.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct RefineSettings {
  bool planar = false;                     // SE(2) about z, z kept (PoseSpace::planar())
  std::size_t min_readings = 6;            // fewer readings (or inliers at the end) keep the histogram pose
  double scale_start_mm = 16.0;            // Tukey scale of the first round: a bin-sized offset still matches
  double scale_final_mm = 2.0;             // ... halved round by round down to this one (the contacts' noise)
  double normal_weight_mm = 4.0;           // residual (mm) per radian of normal misfit
  double min_normal_cos = 0.5;             // a training contact matches only with a normal within 60 degrees
  std::size_t neighbours = 4;              // nearest training contacts tried per reading
  int iterations = 6;                      // Gauss-Newton steps per scale at most
  double min_information = 0.02;           // eigenvalue of the point-to-plane equations (observed normals) below which
  double min_relative_information = 2e-3;  // ... (or this share of the largest) a direction is unobservable
  unsigned threads = 0;                    // workers for the fits (RecognizerOptions::threads; 0: all cores)
  // Workers a run's fit may split its readings over (pose_fit::Problem::fit): more than 1 only where the workers
  // outnumber the runs side by side (one robot's session on many cores), so that the longest run, the estimate's
  // critical path, is not one core's. The same bits for any value.
  unsigned reading_threads = 1;
};

// The settings for `runs` fits side by side on settings.threads workers: each run's fits split their readings over
// the workers the runs leave idle (reading_threads), none where the runs fill them.
RefineSettings with_runs_side_by_side(const RefineSettings& settings, std::size_t runs);

// Settings for a pose space: scales in units of its translation bin (paper3d:
// 8 mm bins give 16 -> 2 mm and 1 mm/rad; the letters' 0.95 mm bins 1.9 -> 0.24 mm). `fine_pose_from`: the map's
// choice (Calibration::fine_pose_from; 0: the pose space's default).
RefineSettings refine_settings(const PoseSpace& space, std::uint32_t fine_pose_from);

struct RefinedPose {
  RigidPose pose;
  bool refined = false;     // false: the first start is kept (too few readings, nothing observable, no better fit)
  std::size_t start = 0;    // the start it came from
  double cost = 0.0;        // Tukey cost at the final scale (an unmatched reading costs scale^2 / 6)
  std::size_t inliers = 0;  // readings inside the final scale
  int observable = 0;       // directions the readings constrain at the end (of 6; planar: of 3)
};

// Refines `starts` (best first) of `object` against the surface and keeps the
// fit of least robust cost; a later start must beat the best so far by more
// than half a reading's outlier cost and a quarter of its cost. No start, too
// few readings or inliers, or no better fit than the first start's keep the
// first start (or an identity pose when there is none), `refined` false.
RefinedPose refine_pose(const SurfaceIndex& surface, std::uint32_t object, std::span<const ObservedReading> readings,
                        std::span<const RigidPose> starts, const RefineSettings& settings);

// `start` moved to fit `object`'s mesh (the map's surfaces, SurfaceModel): point-to-plane against the nearest facet
// and the facet's exact normal, weighed as the measurement model weighs them (`noise`), Tukey's loss from the model's
// reach down to the fine pose's final scale. The training contacts' fit leaves their sampling gaps in the pose
// (a few tenths of a mm); the measurement model, which compares each contact with the facet under it, sees them.
// Deterministic; fewer readings than the fine pose needs, or no better fit, keep `start`.
RigidPose polish_on_mesh(const SurfaceModel& model, std::uint32_t object, std::span<const ObservedReading> readings,
                         const RigidPose& start, const RefineSettings& settings, const ContactNoise& noise);

// How well `object`'s surface explains the readings at `pose`: per reading, log2(exp(-s2 / (2 sigma^2)) + floor)
// with s2 the squared joint residual to its matched training contact (point-to-plane and normal tilt, as the fit
// weighs them) and sigma `sigma_mm`; an unmatched reading scores log2(floor). Summed over the readings.
double surface_log2_fit(const SurfaceIndex& surface, std::uint32_t object, std::span<const ObservedReading> readings,
                        const RigidPose& pose, const RefineSettings& settings, double sigma_mm, double floor);

}  // namespace sva
