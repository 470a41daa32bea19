#pragma once
// What a TouchPlanner holds (sva/touch_planner.hpp): the map, its surfaces as k-d trees of training contacts per
// object, each contact's appearance classes, and the scales the planner's kernels default to. Shared by the
// planner's stages (planning/*.cpp); immutable once built.
#include <sva/touch_planner.hpp>

#include <memory>
#include <vector>

#include "appearance/appearance_model.hpp"
#include "estimate/surface_model.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"

namespace sva {

struct TouchPlanner::Impl {
  explicit Impl(std::shared_ptr<const PairMap> map);

  std::shared_ptr<const PairMap> map;
  SurfaceIndex surface;
  std::unique_ptr<SurfaceModel> model;  // the map's meshes (format 9), or none: predictions from training contacts
  std::vector<std::vector<ClassWeight>> classes;  // per map reading row
  double sigma_mm = 5.0;                          // twice the median spacing of the training contacts
  double shortest_pair_mm = 0.0, longest_pair_mm = 0.0;
};

}  // namespace sva
