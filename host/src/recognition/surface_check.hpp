#pragma once
// The surface check (docs/recognition.md, "Surface check"): the leading objects of the belief, each fitted to the
// readings at its own fine pose, weighed by how well its surface explains every reading. Eq 5 votes with pairs of
// readings whose keys (appearance classes and a distance bin) near-twins share: a clamp and its larger copy, a
// brick of 2x2 and of 2x4 studs agree on most pairs, and the belief may settle on the wrong one. The surface knows
// more: the larger clamp's readings lie off the smaller one's surface wherever the pose puts it. Each reading
// counts once here, unlike Eq 5's pairs; its bits enter the posterior with the calibration's learned surface weight,
// which discounts the sampling noise of the training contacts (calibration/calibration.hpp).
#include <cstdint>
#include <vector>

#include "map/surface_index.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/estimate.hpp"
#include "recognition/pose_refinement.hpp"

namespace sva {

// Objects checked: the leading ones by log-evidence. Each costs a fine pose per estimate; three (the best and two
// rivals). Five, under the same calibration, moved lookalikes' accuracy by a trial or two at any reading count, and
// recalibrated traded accuracy at 30 readings for accuracy at 13-17 (docs/evaluation.md, "The surface check's three
// constants", which also has sigma 0.35 and a floor of 0.001, both left).
inline constexpr std::size_t kSurfaceCheckObjects = 3;
// A reading's fit: a Gaussian of the residual's joint scale (point-to-plane and normal tilt, as the fine pose
// weighs them) with sigma half the fine pose's final scale (1 mm in 8 mm bins: the arm's 0.5 mm and the gaps
// between training contacts), and a floor for readings the surface does not explain (2^-6.6: an outlier costs
// 6.6 bits, so that one odd reading cannot overrule the pairs' evidence, a few can).
inline constexpr double kSurfaceSigmaOfScale = 0.5;
inline constexpr double kSurfaceFloor = 0.01;

struct CheckedObject {
  std::uint32_t object = 0;
  std::uint64_t best_key = 0;  // its best bin
  RigidPose parabolic_pose;    // its best bin's parabolic peak (the first start)
  RefinedPose fine;            // its fine pose
};

struct SurfaceCheck {
  // Per object (empty when not run): the fit in bits for the checked objects, the worst of theirs for the others
  // (not checked because the evidence already ranks them lower; never favoured by the check).
  std::vector<double> log2_fit;
  std::vector<CheckedObject> checked;  // by log-evidence, best first
  const CheckedObject* find(std::uint32_t object) const;
};

// Runs with at least `settings.min_readings` readings and two touched objects; else empty. Every object starts
// from its own modes without a pose prior, so that a pose prior moves the pose and never the object posterior;
// `estimate_modes_are_own` (no pose prior) lets b.object reuse b.modes, which are then the same.
SurfaceCheck check_surfaces(const BayesFilter& filter, const BeliefEstimate& b, const SurfaceIndex& surface,
                            const RefineSettings& settings, bool estimate_modes_are_own);

}  // namespace sva
