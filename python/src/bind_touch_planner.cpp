// sva.TouchPlanner and friends: choosing where to touch next (docs/api.md, "Choosing the next touch"). Options are
// keyword arguments named as TouchPlanOptions' fields; the engine checks their values (sva.Error naming them).
#include <sva/error.hpp>
#include <sva/touch_planner.hpp>

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstdio>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

template <class T>
T option(nb::handle value, const std::string& what, const std::string& key, const char* type) {
  T out{};
  if (!nb::try_cast(value, out))
    throw nb::type_error((what + ": option " + key + " expects " + type + ", got " +
                          nb::cast<std::string>(value.type().attr("__name__")))
                             .c_str());
  return out;
}

// An (n, 3) array-like, or any sequence of 3-vectors: each row through to_vec3.
std::vector<glm::dvec3> vec3_rows(nb::handle value, const std::string& what) {
  std::vector<glm::dvec3> out;
  if (!nb::hasattr(value, "__iter__"))
    throw nb::type_error((what + ": expected an (n, 3) array or a sequence of 3-vectors").c_str());
  for (nb::handle row : value) out.push_back(to_vec3(row, what.c_str()));
  return out;
}

const char* const kOptionNames =
    "best, max_hypotheses, min_hypothesis_mass, object_floor, contact_tolerance_mm, normal_tolerance_deg, "
    "position_sigma_mm, normal_sigma_deg, confusion, visited, visited_normals, pair_min_mm, pair_max_mm, pose_gain, "
    "pose_gain_confidence";

// TouchPlanOptions from keyword arguments (one per field; an unknown name is a TypeError listing the names).
TouchPlanOptions plan_options(const nb::kwargs& kwargs, const std::string& what) {
  TouchPlanOptions o;
  for (auto [k, v] : kwargs) {
    const std::string key = nb::cast<std::string>(k);
    auto number = [&](double& field) { field = keyword_value<double>(v, what, key, "a number"); };
    auto count = [&](std::size_t& field) { field = keyword_value<std::size_t>(v, what, key, "a non-negative int"); };
    if (key == "best")
      count(o.best);
    else if (key == "max_hypotheses")
      count(o.max_hypotheses);
    else if (key == "min_hypothesis_mass")
      number(o.min_hypothesis_mass);
    else if (key == "object_floor")
      number(o.object_floor);
    else if (key == "contact_tolerance_mm")
      number(o.contact_tolerance_mm);
    else if (key == "normal_tolerance_deg")
      number(o.normal_tolerance_deg);
    else if (key == "position_sigma_mm")
      number(o.position_sigma_mm);
    else if (key == "normal_sigma_deg")
      number(o.normal_sigma_deg);
    else if (key == "confusion")
      number(o.confusion);
    else if (key == "visited")
      o.visited = vec3_rows(v, what + ": visited");
    else if (key == "visited_normals")
      o.visited_normals = vec3_rows(v, what + ": visited_normals");
    else if (key == "pair_min_mm")
      number(o.pair_min_mm);
    else if (key == "pair_max_mm")
      number(o.pair_max_mm);
    else if (key == "pose_gain")
      o.pose_gain = keyword_value<bool>(v, what, key, "a bool");
    else if (key == "pose_gain_confidence")
      number(o.pose_gain_confidence);
    else
      throw nb::type_error((what + ": unknown option \"" + key + "\" (options: " + kOptionNames + ")").c_str());
  }
  return o;
}

void bind_candidate(nb::module_& m) {
  nb::class_<CandidateTouch>(m, "CandidateTouch",
                             "A touch the robot could make (robot frame): the sensor pressed at `position` (mm) "
                             "along `approach`; reachable=False: never scored nor chosen.")
      .def(
          "__init__",
          [](CandidateTouch* c, nb::handle position, nb::handle approach, bool reachable) {
            new (c) CandidateTouch{to_vec3(position, "CandidateTouch.position"),
                                   to_vec3(approach, "CandidateTouch.approach"), reachable};
          },
          "position"_a, "approach"_a = nb::make_tuple(0.0, 0.0, -1.0), "reachable"_a = true,
          nb::sig("def __init__(self, position: numpy.typing.ArrayLike, approach: numpy.typing.ArrayLike = (0.0, "
                  "0.0, -1.0), reachable: bool = True) -> None"))
      .def_prop_rw(
          "position", [](const CandidateTouch& c) { return vec3_copy(c.position); },
          [](CandidateTouch& c, nb::handle v) { c.position = to_vec3(v, "CandidateTouch.position"); },
          nb::rv_policy::automatic,
          nb::for_setter(nb::sig("def position(self, arg: numpy.typing.ArrayLike, /) -> None")),
          "mm, robot frame (a copy)")
      .def_prop_rw(
          "approach", [](const CandidateTouch& c) { return vec3_copy(c.approach); },
          [](CandidateTouch& c, nb::handle v) { c.approach = to_vec3(v, "CandidateTouch.approach"); },
          nb::rv_policy::automatic,
          nb::for_setter(nb::sig("def approach(self, arg: numpy.typing.ArrayLike, /) -> None")),
          "direction of the press (a copy); a surface felt there has outward normal near -approach")
      .def_rw("reachable", &CandidateTouch::reachable)
      .def("__repr__", [](const CandidateTouch& c) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "CandidateTouch(position=[%.2f, %.2f, %.2f], approach=[%.3f, %.3f, %.3f]%s)",
                      c.position.x, c.position.y, c.position.z, c.approach.x, c.approach.y, c.approach.z,
                      c.reachable ? "" : ", reachable=False");
        return std::string(buf);
      });
}

void bind_plan(nb::module_& m) {
  nb::class_<TouchScore>(m, "TouchScore", "A scored candidate: its index in the list given, the touch, its score.")
      .def_ro("candidate", &TouchScore::candidate, "index into the candidates given")
      .def_ro("touch", &TouchScore::touch)
      .def_ro("score", &TouchScore::score, "expected information gain over the hypotheses (bits, >= 0)")
      .def_ro("contact_probability", &TouchScore::contact_probability,
              "mass of the hypotheses that predict contact there")
      .def("__repr__", [](const TouchScore& s) {
        return "TouchScore(candidate=" + std::to_string(s.candidate) + ", score=" + std::to_string(s.score) + ")";
      });
  nb::class_<TouchPlan>(m, "TouchPlan", "The best candidates, highest score first, and why a plan is empty.")
      .def_ro("best", &TouchPlan::best, "at most `best` TouchScores, highest first (ties: lower index first)")
      .def_ro("hypotheses", &TouchPlan::hypotheses, "hypotheses scored over (0: no pose yet, every score is 0)")
      .def_ro("reachable", &TouchPlan::reachable, "candidates reachable (and finite)")
      .def_ro("pairing", &TouchPlan::pairing, "of them, those that pair with a visited touch")
      .def_ro("note", &TouchPlan::note, "why the plan is empty or uninformative, '' otherwise")
      .def("__repr__", [](const TouchPlan& p) {
        return "TouchPlan(best=" + std::to_string(p.best.size()) +
               " candidates, hypotheses=" + std::to_string(p.hypotheses) +
               (p.note.empty() ? "" : ", note='" + p.note + "'") + ")";
      });
}

TouchPlan plan_over(const TouchPlanner& planner, const Estimate& est, const std::vector<CandidateTouch>& candidates,
                    const nb::kwargs& kwargs, const std::string& what) {
  const TouchPlanOptions o = plan_options(kwargs, what);
  EngineScope scope;
  return planner.plan(est, candidates, o);
}

void bind_planner(nb::module_& m) {
  nb::class_<TouchPlanner>(m, "TouchPlanner",
                           "The map's surfaces as the planner reads them (k-d trees of training contacts and their "
                           "appearance classes). Build once per map; immutable, shareable across threads.")
      .def(
          "__init__",
          [](TouchPlanner* p, const Map& map) {
            EngineScope scope;
            new (p) TouchPlanner(map);
          },
          "map"_a, "Keeps what it needs of the map: the Map object may be dropped afterwards.")
      .def(
          "plan",
          [](const TouchPlanner& p, const Estimate& est, const std::vector<CandidateTouch>& candidates,
             const nb::kwargs& kwargs) { return plan_over(p, est, candidates, kwargs, "TouchPlanner.plan"); },
          "estimate"_a, "candidates"_a, "options"_a,
          "Scores every reachable candidate by the expected information gain over the estimate's hypotheses; "
          "options are TouchPlanOptions' fields as keywords (best=1, visited=..., visited_normals=..., ...).")
      .def(
          "sample_candidates",
          [](const TouchPlanner& p, const Estimate& est, std::size_t count, std::uint64_t seed,
             const nb::kwargs& kwargs) {
            const TouchPlanOptions o = plan_options(kwargs, "TouchPlanner.sample_candidates");
            EngineScope scope;
            return p.sample_candidates(est, count, seed, o);
          },
          "estimate"_a, "count"_a, "seed"_a = 0, "options"_a,
          "`count` candidates on the hypotheses' surfaces (training contacts carried by their poses, pressed along "
          "-normal); deterministic for a seed; [] when the estimate has no pose hypothesis.")
      .def(
          "contact_estimate",
          [](const TouchPlanner& p, const Reading& touch, std::size_t per_object, std::uint64_t seed) {
            EngineScope scope;
            return p.contact_estimate(touch, per_object, seed);
          },
          "touch"_a, "per_object"_a = 6, "seed"_a = 0,
          "An Estimate from the first touch's appearance alone (guessed poses, pose_valid False), to plan the second "
          "touch before any pair has voted; plan with max_hypotheses=len(estimate.hypotheses).")
      .def_prop_ro("default_position_sigma_mm", &TouchPlanner::default_position_sigma_mm)
      .def_prop_ro("shortest_pair_mm", &TouchPlanner::shortest_pair_mm)
      .def_prop_ro("longest_pair_mm", &TouchPlanner::longest_pair_mm);
  m.def(
      "plan_next_touch",
      [](const TouchPlanner& p, const Estimate& est, const std::vector<CandidateTouch>& candidates,
         const nb::kwargs& kwargs) { return plan_over(p, est, candidates, kwargs, "sva.plan_next_touch"); },
      "planner"_a, "estimate"_a, "candidates"_a, "options"_a, "planner.plan(estimate, candidates, **options).");
}

}  // namespace

void bind_touch_planner(nb::module_& m) {
  bind_candidate(m);
  bind_plan(m);
  bind_planner(m);
}

}  // namespace sva::python
