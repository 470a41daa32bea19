#pragma once
// How an evaluation chooses each next reading (eval/active_trials.cpp runs it): at random, the paper's protocol,
// or planned by the touch planner over the test readings (active) or pressed anew by the simulator (active-sim).
#include <sva/dataset.hpp>
#include <sva/eval/trials.hpp>
#include <sva/touch_planner.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace sva::eval {

enum class Policy { random, active, active_sim };
const char* policy_name(Policy policy);
// "random", "active" or "active-sim"; sva::Error naming `what` otherwise.
Policy parse_policy(const std::string& text, const std::string& what);

// Presses a planned touch on the trial's object in its true pose: the converged reading (robot frame), or nullopt
// when the controller found no contact or did not converge. Deterministic for a seed; called from many threads.
using TouchSimulator =
    std::function<std::optional<Reading>(const Trial& trial, const CandidateTouch& touch, std::uint64_t seed)>;

struct ActiveSetup {
  Policy policy = Policy::active;
  std::size_t candidates = 100;  // sampled on the hypotheses' surfaces before every plan
  std::size_t hypotheses = 8;    // estimate top_k the planner reads
  // The second touch is planned over the first touch's contact estimate (TouchPlanner::contact_estimate) with
  // this many hypotheses per object; 0: it is taken at random, as the first.
  std::size_t contact_hypotheses = 6;
  // Candidates: true, the true object's unshown test contacts in its true pose (the surface a robot's camera
  // offers, not which object it is; the planned touch is then a test reading itself); false, `candidates`
  // sampled on the hypotheses' surfaces (the planned touch is then carried to the nearest test reading).
  bool candidates_on_object = true;
  // The plan's options; its `best` (3) is how many planned touches active-sim tries in turn before it falls back
  // to the random reading (active takes the best one).
  TouchPlanOptions plan = [] {
    TouchPlanOptions o;
    o.best = 3;
    return o;
  }();
  TouchSimulator simulate;  // active_sim only
};

// The trials of run_trials (same objects, poses, first reading), the readings chosen by `active`; each step
// records the plan's time. Everything but timings is independent of the thread count.

}  // namespace sva::eval
