#include "eval/trial_runner.hpp"

#include <sva/base/finite.hpp>
#include <sva/base/interrupt.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/pool.hpp>
#include <sva/base/progress.hpp>
#include <sva/error.hpp>
#include <sva/eval/trials.hpp>

#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <vector>

#include "eval/metrics.hpp"

namespace sva::eval {

// What one step of a trial shows: the estimate against the truth.
void record_step(StepResult& s, const Estimate& est, const Trial& trial, const SceneObject& object, double update_ms,
                 const TrialSetup& setup) {
  const std::int32_t map_object = map_object_of(setup, trial.object);
  s.update_ms = update_ms;
  s.votes = est.votes;
  s.votes_zero = est.votes_zero;
  s.estimated_object = est.object;
  const bool known = map_object >= 0;
  const auto truth = static_cast<std::uint32_t>(map_object);
  s.correct = known && est.object == truth;
  s.true_object_probability = known && truth < est.object_probability.size() ? est.object_probability[truth] : 0.0;
  s.top_probability = est.object < est.object_probability.size() ? est.object_probability[est.object] : 0.0;
  s.p_unknown = est.p_unknown;
  if (setup.keep_evidence) s.evidence = est.evidence;
  s.pose_valid = est.pose_valid;
  if (s.pose_valid && !(finite(est.pose.T) && std::isfinite(est.pose.R[0][0] + est.pose.R[1][1] + est.pose.R[2][2])))
    throw std::logic_error("eval: the recognizer returned a non-finite pose in trial " + std::to_string(trial.index));
  if (s.pose_valid) s.estimate = est.pose;
  if (s.has_pose_error()) {
    const PoseError e = pose_error(trial.pose, est.pose, object.symmetry, object.inertial_radius_mm);
    s.translation_error_mm = e.translation_mm;
    s.angular_error_rad = e.angular_rad;
    s.inertial_error_mm = e.inertial_mm;
  }
}

EvalResult empty_result(const Dataset& test, const TrialSetup& setup) {
  if (setup.trials == 0) throw Error("the number of trials must be at least 1, got 0");
  if (setup.max_readings == 0) throw Error("the number of readings per trial must be at least 1, got 0");
  EvalResult result;
  result.scene = setup.scene.empty() ? test.scene.name : setup.scene;
  result.backend = setup.backend;
  result.method = setup.method;
  result.estimate = setup.estimate;
  result.seed = setup.seed;
  result.max_readings = setup.max_readings;
  for (const auto& o : test.scene.objects) {
    result.objects.push_back(o.name);
    result.families.push_back(o.family);
  }
  result.map_objects = result.objects;  // run_evaluation names the map's when they differ
  result.trials.resize(setup.trials);
  return result;
}

std::int32_t map_object_of(const TrialSetup& setup, std::uint32_t object) {
  return setup.map_object.empty() ? static_cast<std::int32_t>(object) : setup.map_object[object];
}

void start_trial(TrialResult& out, const Trial& trial, const TrialSetup& setup) {
  out.index = trial.index;
  out.object = trial.object;
  out.map_object = map_object_of(setup, trial.object);
  out.known = out.map_object >= 0;
  out.pose = trial.pose;
  out.samples = trial.samples;
  out.steps.resize(trial.readings.size());
}

EvalResult run_trials(const Dataset& test, const TrialSetup& setup, const SessionFactory& make_session) {
  EvalResult result = empty_result(test, setup);
  const TrialGenerator generator(test, setup.pose_space, setup.seed, setup.max_readings, setup.source);

  util::Pool<Session> pool(make_session);
  std::optional<util::Progress> progress;
  if (setup.progress) progress.emplace("eval " + setup.method, setup.trials);

  util::parallel_for(
      setup.trials,
      [&](std::size_t t) {
        const Trial trial = generator.make(t);
        const SceneObject& object = test.scene.objects[trial.object];
        TrialResult& out = result.trials[t];
        start_trial(out, trial, setup);

        auto session = pool.take();
        session->reset();
        for (std::size_t k = 0; k < trial.readings.size(); ++k) {
          util::throw_if_interrupted();
          const auto start = std::chrono::steady_clock::now();
          Estimate est;
          try {
            session->add_reading(trial.readings[k]);
            est = session->estimate();
          } catch (const Interrupted&) {
            throw;
          } catch (const Error& e) {
            throw Error(setup.source + ": trial " + std::to_string(t) + ", reading " + std::to_string(k + 1) +
                        " (sample " + std::to_string(trial.samples[k]) + "): " + e.what());
          }
          const auto stop = std::chrono::steady_clock::now();
          record_step(out.steps[k], est, trial, object, std::chrono::duration<double, std::milli>(stop - start).count(),
                      setup);
        }
        pool.give_back(std::move(session));
        if (progress) progress->advance();
      },
      setup.threads);
  if (progress) progress->finish();
  return result;
}

EvalResult run_trials_batched(const Dataset& test, const TrialSetup& setup, SessionBatch& batch) {
  EvalResult result = empty_result(test, setup);
  const TrialGenerator generator(test, setup.pose_space, setup.seed, setup.max_readings, setup.source);
  std::optional<util::Progress> progress;
  // Progress in readings (trials x readings): a batch steps all its trials together.
  if (setup.progress)
    progress.emplace("eval " + setup.method + " readings (batches of " + std::to_string(batch.size()) + " trials)",
                     setup.trials * setup.max_readings);
  std::vector<Trial> trials;
  LockstepHooks hooks;
  hooks.progress = progress ? &*progress : nullptr;
  hooks.group = [&](std::size_t first, std::size_t count) {
    trials.clear();
    std::vector<std::span<const Reading>> readings;
    for (std::size_t i = 0; i < count; ++i) {
      trials.push_back(generator.make(first + i));
      start_trial(result.trials[first + i], trials.back(), setup);
    }
    for (const Trial& t : trials) readings.emplace_back(t.readings);
    return readings;
  };
  // A step's time is the batch update's time shared by the trials in it.
  hooks.on_step = [&](const LockstepStep& s) {
    const std::vector<Estimate> estimates = batch.estimates(s.sessions);
    for (std::size_t k = 0; k < s.sessions.size(); ++k) {
      const std::size_t i = s.sessions[k];
      const Trial& trial = trials[i];
      record_step(result.trials[s.first + i].steps[s.step], estimates[k], trial, test.scene.objects[trial.object],
                  s.update_ms / static_cast<double>(s.sessions.size()), setup);
    }
  };
  hooks.on_error = [&](const Error& e, const LockstepStep& s) {
    return Error(setup.source + ": trials " + std::to_string(s.first) + "-" + std::to_string(s.first + s.count - 1) +
                 ", reading " + std::to_string(s.step + 1) + ": " + e.what());
  };
  run_lockstep(batch, setup.trials, hooks);
  if (progress) progress->finish();
  return result;
}

}  // namespace sva::eval
