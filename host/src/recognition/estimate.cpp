#include "recognition/estimate.hpp"

#include <sva/base/portable_math.hpp>
#include <sva/base/so3.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

#include "appearance/appearance_baseline.hpp"
#include "belief/belief_math.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/hypotheses.hpp"
#include "recognition/surface_check.hpp"

namespace sva {

namespace {

// Mass of each object relative to a bin at the maximum (weight 2^mass_bits):
// touched bins by their weights, untouched bins at the baseline offset 0. All
// integer up to the final conversion (each object's sum stays below 2^62).
// A prior (`weight`, per object, largest 1; empty: flat) scales each object's bins, as a per-object offset of
// log2(weight) added to every bin of the object would.
std::vector<double> object_mass(const BeliefSummary& s, const PoseSpace& space, std::span<const double> weight = {}) {
  const std::uint32_t bits = belief_math::mass_bits(space.bins_per_object());
  const std::uint64_t baseline = belief_math::sva_exp2_neg_units(s.max_offset, bits);
  std::vector<double> mass(space.objects());
  for (std::uint32_t o = 0; o < space.objects(); ++o) {
    assert(s.touched[o] <= space.bins_per_object());
    const std::uint64_t untouched = space.bins_per_object() - s.touched[o];
    mass[o] = static_cast<double>(s.touched_mass[o] + untouched * baseline);
    if (!weight.empty()) mass[o] *= weight[o];
  }
  return mass;
}

// Sub-bin refinement: along each axis of the pose grid, a parabola through the
// log-belief of the best bin and its two neighbours (untouched bins at the
// baseline, offset 0) puts the peak between bin centres, as peak interpolation
// does for histograms: near its maximum, the log-belief that many pairs
// concentrate is close to quadratic. An axis whose neighbour lies outside the
// grid keeps the centre; the planar angle wraps around.
// A pose prior adds its log2 weight to each of the three bins (a Gaussian in position is exactly quadratic, so
// along a translation axis the parabola stays exact).
RigidPose refine(const BeliefState& belief, const PoseSpace& space, std::uint64_t best, const PoseWeighting& prior) {
  const BinIndex c = space.unpack(best);
  const PoseSpaceSpec& spec = space.spec();
  const bool planar = space.planar();
  struct Axis {
    bool rotation;
    int k;
  };
  std::vector<Axis> axes;
  for (int k = 0; k < (planar ? 2 : 3); ++k) axes.push_back({false, k});
  for (int k = planar ? 2 : 0; k < 3; ++k) axes.push_back({true, k});
  // Neighbour keys of every axis (or none when the axis ends at the grid's edge).
  std::vector<std::uint64_t> keys{best};
  std::vector<bool> has(axes.size(), false);
  for (std::size_t a = 0; a < axes.size(); ++a) {
    const Axis ax = axes[a];
    const int bins = ax.rotation ? spec.rotation_bins : spec.translation_bins;
    const int i = ax.rotation ? c.r[ax.k] : c.t[ax.k];
    int lo = i - 1, hi = i + 1;
    if (ax.rotation && planar) {
      lo = (lo + bins) % bins;
      hi %= bins;
    } else if (lo < 0 || hi >= bins) {
      continue;
    }
    BinIndex m = c, p = c;
    (ax.rotation ? m.r[ax.k] : m.t[ax.k]) = lo;
    (ax.rotation ? p.r[ax.k] : p.t[ax.k]) = hi;
    keys.push_back(space.pack(m));
    keys.push_back(space.pack(p));
    has[a] = true;
  }
  const std::vector<std::uint64_t> off = belief.offsets(keys);
  auto bits = [&](std::size_t i) {
    return belief_math::units_to_bits(off[i]) + (prior.applies_to(c.object) ? prior.log2_weight(keys[i]) : 0.0);
  };
  glm::dvec3 t = space.translation_centre(c), r = space.rotation_centre(c);
  const double tw = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec.rotation_bins;
  const double oc = bits(0);
  std::size_t next = 1;
  for (std::size_t a = 0; a < axes.size(); ++a) {
    if (!has[a]) continue;
    const double om = bits(next), op = bits(next + 1);
    next += 2;
    const double curvature = om - 2.0 * oc + op;
    if (!(curvature < 0.0)) continue;  // flat: no better guess than the centre
    const double shift = std::clamp(0.5 * (om - op) / curvature, -0.5, 0.5);
    if (axes[a].rotation)
      r[axes[a].k] += rw * shift;
    else
      t[axes[a].k] += tw * shift;
  }
  RigidPose pose;
  pose.T = t;
  pose.R = so3::exp(r);
  return pose;
}

// Two bins of one object are the same mode when every grid index differs by at
// most one (the planar angle wraps around).
bool same_mode(const BinIndex& a, const BinIndex& b, const PoseSpace& space) {
  const int rb = space.spec().rotation_bins;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(a.t[k] - b.t[k]) > 1) return false;
    int dr = std::abs(a.r[k] - b.r[k]);
    if (space.planar() && k == 2) dr = std::min(dr, rb - dr);
    if (dr > 1) return false;
  }
  return true;
}

// The best object's distinct modes after the first: the best bins of that
// object, skipping neighbours of a mode already taken. Candidates come from the
// top bins over all objects (the same on every backend: ties to the smaller key).
// A pose prior orders the candidates by evidence plus prior.
std::vector<RigidPose> next_modes(const BeliefState& belief, const PoseSpace& space, std::uint64_t best,
                                  std::size_t count, const PoseWeighting& prior) {
  std::vector<RigidPose> out;
  if (count == 0) return out;
  const std::uint32_t object = PoseSpace::object_of(best);
  std::vector<BinIndex> taken{space.unpack(best)};
  for (const BinOffset& b : order_by_pose_prior(belief.best_bins(16 * (count + 1)), prior)) {
    if (out.size() >= count) break;
    if (PoseSpace::object_of(b.key) != object) continue;
    const BinIndex i = space.unpack(b.key);
    bool near = false;
    for (const BinIndex& t : taken) near = near || same_mode(i, t, space);
    if (near) continue;
    taken.push_back(i);
    out.push_back(space.centre(b.key));
  }
  return out;
}

}  // namespace

std::vector<RigidPose> object_modes(const BeliefState& belief, const PoseSpace& space, std::uint64_t best,
                                    std::size_t count) {
  std::vector<RigidPose> modes;
  if (count == 0) return modes;
  modes.push_back(refine(belief, space, best, {}));
  for (const RigidPose& m : next_modes(belief, space, best, count - 1, {})) modes.push_back(m);
  return modes;
}

std::vector<double> object_log2_mass(const BeliefSummary& s, const PoseSpace& space) {
  const std::uint32_t bits = belief_math::mass_bits(space.bins_per_object());
  const double max_bits = belief_math::units_to_bits(s.max_offset);
  std::vector<double> out(space.objects());
  for (std::uint32_t o = 0; o < space.objects(); ++o) {
    // The mass in bits relative to a bin at the maximum, as a sum of up to two terms in the log domain: the
    // touched bins (their band sum, or below the band the best bin alone) and the untouched bins at offset 0.
    double terms[2] = {0.0, 0.0};  // at least one is set: an object has touched or untouched bins
    int n = 0;
    if (s.touched_mass[o] > 0)
      terms[n++] = pmath::log2(static_cast<double>(s.touched_mass[o])) - bits;
    else if (s.touched[o] > 0)
      terms[n++] = belief_math::units_to_bits(s.best_offset[o]) - max_bits;
    const std::uint64_t untouched = space.bins_per_object() - s.touched[o];
    if (untouched > 0) terms[n++] = pmath::log2(static_cast<double>(untouched)) - max_bits;
    double top = terms[0];
    for (int i = 1; i < n; ++i) top = std::max(top, terms[i]);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) sum += pmath::exp2(terms[i] - top);
    out[o] = top + pmath::log2(sum);
  }
  return out;
}

EvidenceLevel evidence_level(const BeliefSummary& summary, std::size_t pairs_folded, const PoseSpace& space,
                             std::size_t readings) {
  EvidenceLevel e;
  e.readings = readings;
  e.object_log2_mass = object_log2_mass(summary, space);
  if (pairs_folded > 0)
    e.best_bits_per_pair = belief_math::units_to_bits(summary.max_offset) / static_cast<double>(pairs_folded);
  return e;
}

void set_surface_fit(const RefinedPose& fine, std::size_t readings, const RefineSettings& settings,
                     EvidenceLevel* level) {
  if (readings < settings.min_readings || readings == 0) return;
  const double outlier_cost = settings.scale_final_mm * settings.scale_final_mm / 6.0;
  level->fit_cost_share = fine.cost / (outlier_cost * static_cast<double>(readings));
  level->fine_pose_from = settings.min_readings;
}

double total_mass(const BeliefSummary& summary, const PoseSpace& space, std::span<const double> object_weight) {
  double z = 0.0;
  for (double m : object_mass(summary, space, object_weight)) z += m;
  return z;
}

std::vector<double> object_probability(const BeliefSummary& summary, const PoseSpace& space) {
  std::vector<double> p = object_mass(summary, space);
  double z = 0.0;
  for (double m : p) z += m;
  assert(z > 0.0);  // a bin at the maximum weighs 2^mass_bits >= 1
  for (double& v : p) v /= z;
  return p;
}

std::vector<BinOffset> order_by_pose_prior(std::vector<BinOffset> bins, const PoseWeighting& prior) {
  if (prior.empty()) return bins;
  std::vector<std::pair<double, BinOffset>> scored;
  for (const BinOffset& b : bins)
    scored.push_back({belief_math::units_to_bits(b.offset) + prior.log2_weight(b.key), b});
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = 0; i < bins.size(); ++i) bins[i] = scored[i].second;
  return bins;
}

std::uint64_t best_bin_under_prior(const BeliefState& belief, const BeliefSummary& s, std::uint32_t object,
                                   const PoseWeighting& prior) {
  std::uint64_t best = s.best_key[object];
  double score = belief_math::units_to_bits(s.best_offset[object]) + prior.log2_weight(best);
  for (const BinOffset& b : belief.best_bins(kPosePriorCandidates)) {
    if (PoseSpace::object_of(b.key) != object) continue;
    const double v = belief_math::units_to_bits(b.offset) + prior.log2_weight(b.key);
    if (v > score || (v == score && b.key < best)) best = b.key, score = v;
  }
  return best;
}

PoseWeighting::PoseWeighting(std::vector<std::optional<PosePrior>> per_object, const PoseSpace& space)
    : per_object_(std::move(per_object)), space_(&space) {
  bool any = false;
  for (const auto& p : per_object_) any = any || p.has_value();
  if (!any) per_object_.clear();
}

double PoseWeighting::log2_weight(std::uint32_t object, const RigidPose& grid_pose) const {
  if (!applies_to(object)) return 0.0;
  const PosePrior& p = *per_object_[object];
  const RigidPose pose = space_->to_robot(grid_pose);
  const glm::dvec3 d = pose.T - p.position;
  double nats = 0.5 * glm::dot(d, d) / (p.position_sigma_mm * p.position_sigma_mm);
  if (p.has_rotation) {
    const double a = so3::angle(glm::transpose(p.rotation) * pose.R);
    nats += 0.5 * a * a / (p.rotation_sigma_rad * p.rotation_sigma_rad);
  }
  return -nats / std::numbers::ln2;
}

double PoseWeighting::log2_weight(std::uint64_t key) const {
  const std::uint32_t object = PoseSpace::object_of(key);
  return applies_to(object) ? log2_weight(object, space_->centre(key)) : 0.0;
}

BeliefEstimate estimate(const BeliefState& belief, const PoseSpace& space, std::size_t top_k, std::size_t modes,
                        std::span<const double> object_weight, const PoseWeighting& pose_weighting,
                        double temperature) {
  BeliefEstimate e;
  e.summary = belief.summarise();
  const BeliefSummary& s = e.summary;
  const std::vector<double> mass = object_mass(s, space, object_weight);
  double z = 0.0;
  for (double m : mass) z += m;
  e.raw_object_probability.resize(mass.size());
  for (std::size_t o = 0; o < mass.size(); ++o) e.raw_object_probability[o] = mass[o] / z;
  e.level = evidence_level(s, belief.pairs_folded(), space, 0);
  // Untempered, the integer masses decide (ties to the smaller id), as Eq 5 does.
  const bool tempered = temperature != 1.0;
  e.object_probability =
      tempered ? tempered_posterior(e.level.object_log2_mass, temperature, object_weight) : e.raw_object_probability;
  const std::vector<double>& score = tempered ? e.object_probability : mass;
  e.object = 0;
  for (std::uint32_t o = 1; o < mass.size(); ++o)
    if (score[o] > score[e.object]) e.object = o;
  if (s.touched[e.object] > 0) {
    e.pose_valid = true;
    e.best_key = pose_weighting.applies_to(e.object) ? best_bin_under_prior(belief, s, e.object, pose_weighting)
                                                     : s.best_key[e.object];
    e.bin_pose = space.centre(e.best_key);
    e.parabolic_pose = refine(belief, space, e.best_key, pose_weighting);
    e.pose = e.parabolic_pose;
    if (modes > 0) {
      e.modes.push_back(e.parabolic_pose);
      for (const RigidPose& m : next_modes(belief, space, e.best_key, modes - 1, pose_weighting)) e.modes.push_back(m);
    }
  }
  // A bin's probability: its weight 2^(offset - M) at mass_bits over the total.
  const double scale = std::ldexp(1.0, static_cast<int>(belief_math::mass_bits(space.bins_per_object()))) / z;
  for (const BinOffset& b : belief.best_bins(top_k)) {
    BinHypothesis h;
    h.key = b.key;
    h.object = PoseSpace::object_of(b.key);
    h.pose = space.centre(b.key);
    h.probability = pmath::exp2(-belief_math::units_to_bits(s.max_offset - b.offset)) * scale;
    if (!object_weight.empty()) h.probability *= object_weight[h.object];
    e.top.push_back(h);
  }
  return e;
}

namespace {

// Modes of the belief the fine pose starts from (the best bin's parabolic peak first).
constexpr std::size_t kRefineStarts = 4;

// Object probabilities times the prior's weights, renormalised; unchanged without a prior.
void weigh_by_prior(std::vector<double>& p, std::span<const double> prior_weight) {
  if (prior_weight.empty()) return;
  double z = 0.0;
  for (std::size_t o = 0; o < p.size(); ++o) z += p[o] *= prior_weight[o];
  for (double& x : p) x /= z;
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

// The distinct hypotheses, in the robot frame. The best object's best mode carries the estimate's own pose (the
// fine pose when refined), so hypotheses[0] and Estimate::pose agree.
void add_hypotheses(const BayesFilter& filter, const std::vector<MapObject>& objects, const EstimateRequest& r,
                    const BeliefEstimate& b, Estimate* e) {
  const PoseSpace& space = filter.space();
  const HypothesisSet set = hypotheses(filter.belief(), space, b.summary, r.top_k, r.hypothesis_radius_bins,
                                       r.object_weight, r.pose_weighting, r.refine.threads);
  for (const ModeHypothesis& m : set.modes) {
    e->hypotheses.push_back(public_hypothesis(m, space, objects));
    if (b.pose_valid && m.key == b.best_key) e->hypotheses.back().pose = e->pose;
  }
  for (std::uint32_t o = 0; o < set.per_object.size(); ++o) {
    PoseHypothesis h;
    h.object = o;
    h.object_name = objects[o].name;
    if (set.per_object_valid[o]) h = public_hypothesis(set.per_object[o], space, objects);
    if (b.pose_valid && o == b.object) h.pose = e->pose;
    e->object_hypotheses.push_back(h);
  }
}

// The poses and the best bins of `e` (grid frame, from the belief) carried into the robot frame.
void poses_to_robot(const PoseSpace& space, const std::vector<MapObject>& objects, const BeliefEstimate& b,
                    Estimate* e) {
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
void temper_hypotheses(const BeliefEstimate& b, Estimate* e) {
  auto scaled = [&](std::uint32_t o, double p, bool best_of_object) {
    const double raw = b.raw_object_probability[o], cal = b.object_probability[o];
    if (raw > 0.0) return std::min(p * (cal / raw), 1.0);
    return best_of_object ? cal : 0.0;
  };
  std::vector<bool> seen(b.object_probability.size(), false);
  for (PoseHypothesis& h : e->hypotheses) {
    h.probability = scaled(h.object, h.probability, !seen[h.object]);
    seen[h.object] = true;
  }
  for (PoseHypothesis& h : e->object_hypotheses) h.probability = h.valid ? scaled(h.object, h.probability, true) : 0.0;
  for (Hypothesis& h : e->top) h.probability = scaled(h.object, h.probability, false);
}

}  // namespace

ObservedReading to_grid(const PoseSpace& space, ObservedReading r) {
  const RigidPose to = space.workspace().inverse();
  r.position = to.apply(r.position);
  r.normal = to.rotate(r.normal);
  return r;
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

namespace {

// The surface check's posterior (tempered log-evidence plus the surfaces' fits) and, when it names another object
// than the belief's best, that object's best bin and poses in `b`.
void follow_surface_check(const SurfaceCheck& check, const EvidenceLevel& level, double temperature,
                          double surface_weight, std::span<const double> object_weight, const PoseSpace& space,
                          BeliefEstimate* b) {
  b->object_probability =
      tempered_posterior(level.object_log2_mass, temperature, object_weight, check.log2_fit, surface_weight);
  std::uint32_t best = b->object;
  for (std::uint32_t o = 0; o < b->object_probability.size(); ++o)
    if (b->object_probability[o] > b->object_probability[best]) best = o;
  const CheckedObject* c = check.find(best);
  if (best == b->object || !c) return;  // an object the check did not fit rises only through its prior: kept as is
  b->object = best;
  b->best_key = c->best_key;
  b->bin_pose = space.centre(c->best_key);
  b->parabolic_pose = c->parabolic_pose;
  b->pose = c->parabolic_pose;
  b->modes = {c->parabolic_pose};
}

}  // namespace

Estimate filter_estimate(const BayesFilter& filter, const std::vector<MapObject>& objects, const EstimateRequest& r) {
  const double temperature = r.calibration ? r.calibration->temperature(filter.readings()) : 1.0;
  BeliefEstimate b =
      filter.estimate(r.top_k, r.surface ? kRefineStarts : 1, r.object_weight, r.pose_weighting, temperature);
  EvidenceLevel level = b.level;
  level.readings = filter.readings();
  SurfaceCheck check;
  std::optional<RefinedPose> belief_fine;  // the fine pose of the belief's own best object, from its own modes
  if (r.surface && b.pose_valid) {
    if (r.surface_check) check = check_surfaces(filter, b, *r.surface, r.refine, r.pose_weighting.empty());
    // With a pose prior the estimate's modes are ordered by it, and the check fitted the object from its own.
    const CheckedObject* own = r.pose_weighting.empty() ? check.find(b.object) : nullptr;
    belief_fine = own ? own->fine : refine_pose(*r.surface, b.object, filter.observed(), b.modes, r.refine);
    // "None of these" reads the fit of the belief's own best object, as the calibration's sessions do.
    set_surface_fit(*belief_fine, filter.readings(), r.refine, &level);
  }
  const std::uint32_t belief_best = b.object;
  if (!check.log2_fit.empty()) {
    level.surface_log2_fit = check.log2_fit;
    // Uncalibrated, the check's bits count as they are, each reading once.
    const double weight = r.calibration ? r.calibration->surface_weight : 1.0;
    follow_surface_check(check, level, temperature, weight, r.object_weight, filter.space(), &b);
  }
  // The top label last: it keeps the top object, so the poses above stand.
  const bool relabel = r.calibration && filter.readings() >= 2;
  if (relabel) r.calibration->recalibrate_top(level, &b.object_probability);
  Estimate e;
  e.ready = true;
  e.object = b.object;
  e.object_name = objects[b.object].name;
  e.object_probability = b.object_probability;
  e.pose_valid = b.pose_valid;
  e.pose = b.pose;
  e.parabolic_pose = b.parabolic_pose;
  e.bin_pose = b.bin_pose;
  if (belief_fine && r.refine_pose) {
    // The belief's own best keeps its fine pose; an object the check named brings the check's.
    const CheckedObject* named = b.object != belief_best ? check.find(b.object) : nullptr;
    const RefinedPose& fine = named ? named->fine : *belief_fine;
    e.pose = fine.pose;
    e.pose_refined = fine.refined;
  }
  poses_to_robot(filter.space(), objects, b, &e);
  if (r.top_k > 0) add_hypotheses(filter, objects, r, b, &e);
  if (temperature != 1.0 || !check.log2_fit.empty() || relabel) temper_hypotheses(b, &e);
  e.p_unknown = r.calibration ? r.calibration->p_unknown(level, r.unknown_prior) : 0.0;
  e.votes_outside = filter.last_update().votes_outside;
  e.votes_zero = filter.last_update().votes_zero;
  return e;
}

EvidenceLevel calibration_evidence(const BayesFilter& filter, const SurfaceIndex& surface,
                                   const RefineSettings& settings, bool surface_check) {
  const bool fit = filter.readings() >= settings.min_readings;
  const BeliefEstimate b = filter.estimate(0, fit ? kRefineStarts : 1);
  EvidenceLevel level = b.level;
  level.readings = filter.readings();
  if (!fit || !b.pose_valid) return level;
  const SurfaceCheck check = surface_check ? check_surfaces(filter, b, surface, settings, true) : SurfaceCheck{};
  const CheckedObject* own = check.find(b.object);
  set_surface_fit(own ? own->fine : refine_pose(surface, b.object, filter.observed(), b.modes, settings),
                  filter.readings(), settings, &level);
  level.surface_log2_fit = check.log2_fit;
  return level;
}

}  // namespace sva
