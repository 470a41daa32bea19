#pragma once
// Runs recognition trials and records, after every reading, whether the
// object is right and how far the pose is off. The recognizer is reached
// through `Session`, so the runner can be tested with a scripted session and
// the same loop serves the CPU and Vulkan backends and both methods.
#include <sva/dataset.hpp>
#include <sva/recognizer.hpp>
#include <sva/scene.hpp>

#include <functional>
#include <memory>
#include <span>
#include <string>

#include <sva/eval/results.hpp>
#include "recognition/lockstep.hpp"

namespace sva::eval {

// One recognition session: readings in, estimate out. reset() must make it
// behave exactly like a fresh one (sessions are reused across trials).
class Session {
 public:
  virtual ~Session() = default;
  virtual void add_reading(const Reading& reading) = 0;
  virtual Estimate estimate() const = 0;
  // The estimate with up to top_k distinct hypotheses (what the touch planner reads); estimate() by default.
  virtual Estimate estimate_top(std::size_t top_k) const {
    (void)top_k;
    return estimate();
  }
  virtual void reset() = 0;
};
using SessionFactory = std::function<std::unique_ptr<Session>()>;

// Many sessions stepped together (recognition/lockstep.hpp): one call adds the
// next reading of each listed session (one backend update, one GPU
// submission); the runner reads each trial's estimate after every update.
class SessionBatch : public LockstepSessions {
 public:
  // The estimates of `sessions` (the i-th is sessions[i]'s): the estimate after every update of a batched eval.
  virtual std::vector<Estimate> estimates(std::span<const std::size_t> sessions) const = 0;
};

struct TrialSetup {
  std::size_t trials = 0;        // >= 1; trial t uses object t mod objects
  std::size_t max_readings = 0;  // >= 1
  std::uint64_t seed = 1;
  PoseSpaceSpec pose_space;  // where the random object poses come from
  unsigned threads = 0;      // trials run in parallel; 0 = util::default_threads()
  bool progress = true;
  std::string source = "test set";     // names the test set in errors
  std::string scene, backend, method;  // copied into the result
  std::string estimate = "full";       // likewise: the sessions' estimate depth
  // Per object of the test set: its id in the map, or -1 when the map does not hold it (--unknown-objects);
  // empty: the same objects in the same order.
  std::vector<std::int32_t> map_object;
  bool keep_evidence = false;  // EvalOptions::keep_evidence
};

// Runs setup.trials trials on the test set. Each trial's randomness comes from
// util::Rng(seed, trial) and each trial writes only its own result, so
// everything but the timings is independent of the thread count.
EvalResult run_trials(const Dataset& test, const TrialSetup& setup, const SessionFactory& make_session);

// The same trials run in lock step (run_lockstep), batch.size() at a time: step
// k adds the k-th reading of every trial of the group in one call. Results equal
// run_trials' (but for timings: a step's time is the batch update's time
// divided by the number of trials in it).
EvalResult run_trials_batched(const Dataset& test, const TrialSetup& setup, SessionBatch& batch);

// The parts the runners share (host/eval/src/eval/active_trials.cpp steps trials its own way).
struct Trial;
// The result with its trials sized, the setup's names copied; sva::Error for 0 trials or readings.
EvalResult empty_result(const Dataset& test, const TrialSetup& setup);
// The map's id of a test-set object (TrialSetup::map_object), or -1 when the map does not hold it.
std::int32_t map_object_of(const TrialSetup& setup, std::uint32_t object);
// Copies the trial's object, pose and samples into its result and sizes its steps.
void start_trial(TrialResult& out, const Trial& trial, const TrialSetup& setup);
// Records the estimate after one more reading against the trial's truth (the true object's id in the map by
// setup.map_object; its evidence when setup.keep_evidence).
void record_step(StepResult& s, const Estimate& est, const Trial& trial, const SceneObject& object, double update_ms,
                 const TrialSetup& setup);

}  // namespace sva::eval
