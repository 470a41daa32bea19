#pragma once
// Stage 2 of the estimate (estimate/pipeline.hpp): the fine pose. The best object is aligned to the readings from
// its modes, and each leading object (stage 1) from its own, so that the verify stage can weigh every leading object
// at the pose that explains the readings best for it (estimate/fine_pose.hpp). Host only, after the belief: the
// same candidates and readings give the same fits on every backend.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "estimate/candidates.hpp"
#include "estimate/fine_pose.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"

namespace sva {

// Leading objects fitted when the verify stage runs: each costs a fine pose per estimate; three (the best and two
// rivals). Five, under the same calibration, moved lookalikes' accuracy by a trial or two at any reading count, and
// recalibrated traded accuracy at 30 readings for accuracy at 13-17 (docs/evaluation.md, "The surface check's three
// constants").
inline constexpr std::size_t kFittedObjects = 3;
// Modes of the belief the fine pose starts from (the best bin's parabolic peak first).
inline constexpr std::size_t kFitStarts = 4;

struct FittedObject {
  std::uint32_t object = 0;
  std::uint64_t best_key = 0;  // its best bin
  RigidPose parabolic_pose;    // its best bin's parabolic peak (the first start)
  RefinedPose fine;            // its fine pose
};

struct Fits {
  std::vector<FittedObject> leading;  // Candidates::leading, fitted, in its order (empty: not run)
  // The fine pose of the candidates' best object from its own modes (Candidates::modes, in a pose prior's order);
  // none without a surface or a touched best object.
  std::optional<RefinedPose> best;
  const FittedObject* find(std::uint32_t object) const;
};

// The fits of `c` against `surface` (none: no fit). The leading objects' fits run side by side on the workers
// (settings.threads), kept in the leading order; the best object reuses its leading fit when `modes_are_own` (no
// pose prior: its modes are then its own).
Fits fit_candidates(const Candidates& c, std::span<const ObservedReading> readings, const SurfaceIndex* surface,
                    const RefineSettings& settings, bool modes_are_own);

}  // namespace sva
