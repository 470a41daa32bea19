#include <sva/base/interrupt.hpp>
#include <sva/eval/trial_sessions.hpp>

#include <sva/eval/trials.hpp>

#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>
#include "recognition/batch_sessions.hpp"

namespace sva::eval {

std::vector<BatchSession> trial_sessions(const Dataset& test, const PoseSpaceSpec& space, std::uint64_t seed,
                                         std::size_t trials, std::size_t max_readings, const std::string& source) {
  const TrialGenerator gen(test, space, seed, max_readings, source);
  std::vector<BatchSession> sessions;
  for (std::size_t t = 0; t < trials; ++t) {
    util::throw_if_interrupted();
    Trial trial = gen.make(t);
    nlohmann::json truth = batch::pose_value(trial.pose);
    truth["object"] = test.scene.objects[trial.object].name;
    sessions.push_back({"trial-" + std::to_string(t), std::move(trial.readings), io::dump_json(truth)});
  }
  return sessions;
}

}  // namespace sva::eval
