#pragma once
// Evaluation trials as a batch-recognition sessions file (`sva recognize
// --write-sessions`, docs/batch-format.md): trial t's readings, with the true
// object and pose under "truth", so that `sva recognize` results can be scored.
#include <sva/batch_file.hpp>
#include <sva/dataset.hpp>
#include <sva/pose.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace sva::eval {

// Sessions "trial-0" .. "trial-(trials-1)" of max_readings readings each,
// drawn as TrialGenerator draws them (poses from `space`, seeded by `seed`).
std::vector<BatchSession> trial_sessions(const Dataset& test, const PoseSpaceSpec& space, std::uint64_t seed,
                                         std::size_t trials, std::size_t max_readings, const std::string& source);

}  // namespace sva::eval
