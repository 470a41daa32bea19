#pragma once
// A session's Prior (sva/prior.hpp) checked against the map before it enters the estimate: a caller's mistake
// (wrong object count, a negative probability, a matrix that is no rotation) is an sva::Error at set_prior, not a
// silently wrong posterior later.
#include <sva/prior.hpp>

#include <cstddef>
#include <vector>

namespace sva {

// A prior over objects as weights whose largest is 1 (empty: flat), checked against the map's `objects`.
std::vector<double> prior_weights(const Prior& prior, std::size_t objects);

// The pose priors of a Prior, checked against the map: empty, or one (optional) per object, each well formed.
void check_pose_priors(const Prior& prior, std::size_t objects);

}  // namespace sva
