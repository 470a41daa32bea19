#pragma once
// Stage 5 of the estimate (estimate/pipeline.hpp): the public sva::Estimate, in the robot frame. The belief and the
// fits work in the pose grid's frame (the workspace frame); every pose leaves it here. The chosen object's pose is
// its fine pose when there is one: the belief's best keeps its own; a leading object the calibrated posterior named
// instead brings its own fit.
#include <cstddef>
#include <span>
#include <vector>

#include <sva/recognizer.hpp>

#include "estimate/calibrate.hpp"
#include "estimate/candidates.hpp"
#include "estimate/fit.hpp"
#include "map/pair_map.hpp"
#include "votes/pose_space.hpp"

namespace sva {

struct ReportOptions {
  bool hypotheses = true;  // the distinct hypotheses (Candidates::hypotheses) and the per-object ones
  bool fine_pose = true;   // Estimate::pose is the fine pose (else the parabolic peak; the fit still fed the rest)
};

Estimate report(const Candidates& c, const Fits& fits, const CalibratedPosterior& p, const PoseSpace& space,
                const std::vector<MapObject>& objects, const ReportOptions& options);

// Before any reading there is no evidence: the object posterior is the prior (uniform without one), and no
// object, pose or hypothesis is reported, so that a caller cannot take a placeholder for an answer.
// `object_weight`: per object, largest 1; empty: flat.
Estimate not_ready_estimate(std::size_t objects, std::span<const double> object_weight);

// Method::appearance: the appearance-only posterior of [15] times the prior; no pose.
Estimate appearance_estimate(const std::vector<double>& log_posterior, const std::vector<MapObject>& objects,
                             std::span<const double> object_weight);

}  // namespace sva
