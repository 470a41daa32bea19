#include "eval/active_trials.hpp"

#include "training/session_sampling.hpp"

#include <sva/base/interrupt.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/pool.hpp>
#include <sva/base/progress.hpp>
#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>
#include <vector>

namespace sva::eval {

namespace {

constexpr std::size_t kSimulated = std::numeric_limits<std::size_t>::max();  // a step's sample when pressed anew

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The test readings a trial has shown and where the next one comes from.
class TrialReadings {
 public:
  TrialReadings(const TrialGenerator& gen, const Trial& trial) : gen_(gen), trial_(trial) {}

  // The random policy's choice: the first reading of the trial's random order not shown yet (past them all, the
  // order's own draw for step k), so an adaptive trial starts exactly as the random one does.
  std::size_t random_next(std::size_t k) const {
    for (std::size_t s : trial_.samples)
      if (!shown(s)) return s;
    return trial_.samples[k];
  }
  // The unshown test reading of the true object nearest to `p` (robot frame) in the true pose; all of them once
  // every one was shown. Ties go to the lower sample index.
  std::size_t nearest(const glm::dvec3& p) const {
    const auto& pool = gen_.samples_of(trial_.object);
    const bool all_shown = std::all_of(pool.begin(), pool.end(), [&](std::size_t s) { return shown(s); });
    std::size_t best = pool.front();
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t s : pool) {
      if (!all_shown && shown(s)) continue;
      const glm::dvec3 d = trial_.pose.apply(gen_.object_frame(s).position) - p;
      const double dd = glm::dot(d, d);
      if (dd < best_d) best = s, best_d = dd;
    }
    return best;
  }
  Reading reading(std::size_t sample) const { return transform_reading(gen_.object_frame(sample), trial_.pose); }
  // The object's surface as a robot's camera would offer it: the unshown test contacts of the true object in its
  // true pose, pressed along their inward normals (candidate touches; which object it is stays unknown).
  std::vector<CandidateTouch> surface_candidates() const {
    std::vector<CandidateTouch> out;
    for (std::size_t s : gen_.samples_of(trial_.object))
      if (!shown(s)) {
        const Reading& r = gen_.object_frame(s);
        out.push_back({trial_.pose.apply(r.position), -trial_.pose.rotate(r.normal), true});
      }
    return out;
  }
  void show(std::size_t sample) { shown_.push_back(sample); }

 private:
  bool shown(std::size_t s) const { return std::find(shown_.begin(), shown_.end(), s) != shown_.end(); }
  const TrialGenerator& gen_;
  const Trial& trial_;
  std::vector<std::size_t> shown_;
};

struct Choice {
  Reading reading;
  std::size_t sample = kSimulated;
  double plan_ms = 0.0;
};

struct Chooser {
  const TouchPlanner& planner;
  const ActiveSetup& active;
  std::uint64_t seed;

  Choice random(const TrialReadings& tr, std::size_t k) const {
    const std::size_t s = tr.random_next(k);
    return {tr.reading(s), s, 0.0};
  }

  // Step k's reading after the estimate `belief` of the readings so far (at `visited`; the first one `first`).
  // Before two readings pair the belief holds no pose, so the second touch is planned over the first touch's
  // contact estimate (its appearance alone).
  Choice choose(const Trial& trial, const TrialReadings& tr, const Estimate& belief, std::size_t k,
                const Reading& first, const std::vector<glm::dvec3>& visited,
                const std::vector<glm::dvec3>& normals) const {
    if (k == 0) return random(tr, k);
    const auto start = std::chrono::steady_clock::now();
    const std::uint64_t draw = util::Rng(seed, trial.index, k).below(std::uint64_t{1} << 62);
    TouchPlanOptions o = active.plan;
    o.visited = visited;
    o.visited_normals = normals;
    const bool from_contact = k == 1 && active.contact_hypotheses > 0;
    const Estimate est = from_contact ? planner.contact_estimate(first, active.contact_hypotheses, draw) : belief;
    if (from_contact) o.max_hypotheses = std::max(o.max_hypotheses, est.hypotheses.size());
    const std::vector<CandidateTouch> cands = active.candidates_on_object
                                                  ? tr.surface_candidates()
                                                  : planner.sample_candidates(est, active.candidates, draw, o);
    const TouchPlan plan = planner.plan(est, cands, o);
    const double plan_ms = ms_since(start);
    Choice c = random(tr, k);
    c.plan_ms = plan_ms;
    if (plan.best.empty() || !(plan.best.front().score > 0.0)) return c;
    if (active.policy == Policy::active) {
      const std::size_t s = tr.nearest(plan.best.front().touch.position);
      return {tr.reading(s), s, plan_ms};
    }
    for (const TouchScore& t : plan.best)
      if (std::optional<Reading> r = active.simulate(trial, t.touch, draw)) return {*r, kSimulated, plan_ms};
    return c;  // no planned touch converged on the mesh
  }
};

void run_active_trial(const Trial& trial, const TrialGenerator& gen, const Chooser& chooser, Session& session,
                      const Dataset& test, const TrialSetup& setup, TrialResult& out) {
  const SceneObject& object = test.scene.objects[trial.object];
  TrialReadings tr(gen, trial);
  std::vector<glm::dvec3> visited, normals;
  Reading first;
  Estimate est;
  session.reset();
  for (std::size_t k = 0; k < setup.max_readings; ++k) {
    util::throw_if_interrupted();
    const Choice c = chooser.choose(trial, tr, est, k, first, visited, normals);
    const auto start = std::chrono::steady_clock::now();
    try {
      session.add_reading(c.reading);
      est = session.estimate_top(chooser.active.hypotheses);
    } catch (const Interrupted&) {
      throw;
    } catch (const Error& e) {
      const std::string what = c.sample == kSimulated ? "a simulated touch" : "sample " + std::to_string(c.sample);
      throw Error(setup.source + ": trial " + std::to_string(trial.index) + ", reading " + std::to_string(k + 1) +
                  " (" + what + "): " + e.what());
    }
    record_step(out.steps[k], est, trial, object, ms_since(start), setup);
    out.steps[k].plan_ms = c.plan_ms;
    out.samples[k] = c.sample;
    if (c.sample != kSimulated) tr.show(c.sample);
    if (k == 0) first = c.reading;
    visited.push_back(c.reading.position);
    normals.push_back(c.reading.normal);
  }
}

}  // namespace

const char* policy_name(Policy policy) {
  switch (policy) {
    case Policy::active:
      return "active";
    case Policy::active_sim:
      return "active-sim";
    case Policy::random:
      break;
  }
  return "random";
}

Policy parse_policy(const std::string& text, const std::string& what) {
  for (Policy p : {Policy::random, Policy::active, Policy::active_sim})
    if (text == policy_name(p)) return p;
  throw Error(what + " expects random, active or active-sim, got \"" + text + "\"");
}

EvalResult run_trials_active(const Dataset& test, const TrialSetup& setup, const SessionFactory& make_session,
                             const TouchPlanner& planner, const ActiveSetup& active) {
  if (active.policy == Policy::active_sim && !active.simulate)
    throw Error("the active-sim policy needs a touch simulator (the scene's meshes)");
  if (active.candidates == 0) throw Error("the active policies need at least 1 candidate touch per plan, got 0");
  EvalResult result = empty_result(test, setup);
  result.policy = policy_name(active.policy);
  const TrialGenerator generator(test, setup.pose_space, setup.seed, setup.max_readings, setup.source);
  const Chooser chooser{planner, active, setup.seed};
  util::Pool<Session> pool(make_session);
  std::optional<util::Progress> progress;
  if (setup.progress) progress.emplace("eval " + setup.method + " " + result.policy, setup.trials);
  util::parallel_for(
      setup.trials,
      [&](std::size_t t) {
        const Trial trial = generator.make(t);
        start_trial(result.trials[t], trial, setup);
        auto session = pool.take();
        run_active_trial(trial, generator, chooser, *session, test, setup, result.trials[t]);
        pool.give_back(std::move(session));
        if (progress) progress->advance();
      },
      setup.threads);
  if (progress) progress->finish();
  return result;
}

}  // namespace sva::eval
