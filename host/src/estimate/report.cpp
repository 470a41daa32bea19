#include "estimate/report.hpp"

#include <algorithm>

#include "appearance/appearance_baseline.hpp"

namespace sva {

namespace {

// Object probabilities times the prior's weights, renormalised; unchanged without a prior.
void weigh_by_prior(std::vector<double>& p, std::span<const double> prior_weight) {
  if (prior_weight.empty()) return;
  double z = 0.0;
  for (std::size_t o = 0; o < p.size(); ++o) z += p[o] *= prior_weight[o];
  for (double& x : p) x /= z;
}

// The chosen object's bin and poses (grid frame): the candidates' best object, or the leading object the calibrated
// posterior named, from its fit.
struct Chosen {
  std::uint32_t object = 0;
  bool pose_valid = false;
  std::uint64_t best_key = 0;
  RigidPose pose, parabolic_pose, bin_pose;
  const RefinedPose* fine = nullptr;
};

Chosen choose(const Candidates& c, const Fits& fits, const CalibratedPosterior& p, const PoseSpace& space) {
  Chosen ch{c.object, c.pose_valid, c.best_key, c.pose, c.parabolic_pose, c.bin_pose, nullptr};
  if (fits.best) ch.fine = &*fits.best;
  const FittedObject* named = p.object != c.object ? fits.find(p.object) : nullptr;
  if (!named) return ch;
  ch.object = named->object;
  ch.best_key = named->best_key;
  ch.bin_pose = space.centre(named->best_key);
  ch.parabolic_pose = named->parabolic_pose;
  ch.pose = named->parabolic_pose;
  ch.fine = &named->fine;
  return ch;
}

PoseHypothesis public_hypothesis(const ModeHypothesis& m, const PoseSpace& space,
                                 const std::vector<MapObject>& objects) {
  PoseHypothesis h;
  h.object = m.object;
  h.object_name = objects[m.object].name;
  h.pose = space.to_robot(m.pose);
  h.probability = m.probability;
  h.covariance = covariance_to_robot(m.covariance, space.workspace().R);
  h.valid = true;
  return h;
}

// The distinct hypotheses, in the robot frame. The chosen object's chosen mode carries the estimate's own pose (the
// fine pose when refined), so hypotheses[0] and Estimate::pose agree.
void add_hypotheses(const HypothesisSet& set, const PoseSpace& space, const std::vector<MapObject>& objects,
                    const Chosen& chosen, Estimate* e) {
  for (const ModeHypothesis& m : set.modes) {
    e->hypotheses.push_back(public_hypothesis(m, space, objects));
    if (chosen.pose_valid && m.key == chosen.best_key) e->hypotheses.back().pose = e->pose;
  }
  for (std::uint32_t o = 0; o < set.per_object.size(); ++o) {
    PoseHypothesis h;
    h.object = o;
    h.object_name = objects[o].name;
    if (set.per_object_valid[o]) h = public_hypothesis(set.per_object[o], space, objects);
    if (chosen.pose_valid && o == chosen.object) h.pose = e->pose;
    e->object_hypotheses.push_back(h);
  }
}

// The poses and the best bins of `e` (grid frame, from the belief) carried into the robot frame.
void poses_to_robot(const PoseSpace& space, const std::vector<MapObject>& objects, const Candidates& b, Estimate* e) {
  e->pose = space.to_robot(e->pose);
  e->parabolic_pose = space.to_robot(e->parabolic_pose);
  e->bin_pose = space.to_robot(e->bin_pose);
  for (const BinHypothesis& h : b.top) {
    Hypothesis out;
    out.object = h.object;
    out.object_name = objects[h.object].name;
    out.pose = space.to_robot(h.pose);
    out.probability = h.probability;
    e->top.push_back(out);
  }
}

// The bins and modes carry shares of their object's untempered mass; tempering moves each object's total, so each
// share is scaled to its object's tempered probability. An object whose untempered mass underflowed has lost its
// shares: its best mode takes the whole of its tempered probability, its other modes none.
void temper_hypotheses(const Candidates& b, const CalibratedPosterior& p, Estimate* e) {
  auto scaled = [&](std::uint32_t o, double share, bool best_of_object) {
    const double raw = b.raw_object_probability[o], cal = p.object_probability[o];
    if (raw > 0.0) return std::min(share * (cal / raw), 1.0);
    return best_of_object ? cal : 0.0;
  };
  std::vector<bool> seen(p.object_probability.size(), false);
  for (PoseHypothesis& h : e->hypotheses) {
    h.probability = scaled(h.object, h.probability, !seen[h.object]);
    seen[h.object] = true;
  }
  for (PoseHypothesis& h : e->object_hypotheses) h.probability = h.valid ? scaled(h.object, h.probability, true) : 0.0;
  for (Hypothesis& h : e->top) h.probability = scaled(h.object, h.probability, false);
}

}  // namespace

Estimate report(const Candidates& c, const Fits& fits, const CalibratedPosterior& p, const PoseSpace& space,
                const std::vector<MapObject>& objects, const ReportOptions& options) {
  const Chosen chosen = choose(c, fits, p, space);
  Estimate e;
  e.ready = true;
  e.object = chosen.object;
  e.object_name = objects[chosen.object].name;
  e.object_probability = p.object_probability;
  e.pose_valid = chosen.pose_valid;
  e.pose = chosen.pose;
  e.parabolic_pose = chosen.parabolic_pose;
  e.bin_pose = chosen.bin_pose;
  if (chosen.fine && options.fine_pose) {
    e.pose = chosen.fine->pose;
    e.pose_refined = chosen.fine->refined;
  }
  poses_to_robot(space, objects, c, &e);
  if (options.hypotheses) add_hypotheses(c.hypotheses, space, objects, chosen, &e);
  if (p.reweighed) temper_hypotheses(c, p, &e);
  e.p_unknown = p.p_unknown;
  return e;
}

Estimate not_ready_estimate(std::size_t objects, std::span<const double> object_weight) {
  Estimate e;
  e.object_probability.assign(objects, object_weight.empty() ? 1.0 / static_cast<double>(objects) : 1.0);
  weigh_by_prior(e.object_probability, object_weight);
  return e;
}

Estimate appearance_estimate(const std::vector<double>& log_posterior, const std::vector<MapObject>& objects,
                             std::span<const double> object_weight) {
  Estimate e;
  e.ready = true;
  e.object_probability = AppearanceBaseline::posterior(log_posterior);
  weigh_by_prior(e.object_probability, object_weight);
  for (std::uint32_t o = 1; o < e.object_probability.size(); ++o)
    if (e.object_probability[o] > e.object_probability[e.object]) e.object = o;
  e.object_name = objects[e.object].name;
  return e;
}

}  // namespace sva
