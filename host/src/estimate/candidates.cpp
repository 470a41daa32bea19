#include "estimate/candidates.hpp"

#include <sva/base/portable_math.hpp>
#include <sva/base/so3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "belief/belief_math.hpp"
#include "belief/object_mass.hpp"
#include "votes/neighbourhood_steps.hpp"

namespace sva {

namespace {

// Sub-bin refinement: along each axis of the pose grid, a parabola through the
// log-belief of the best bin and its two neighbours (untouched bins at the
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
    for (const BinIndex& t : taken) near = near || within_steps(i, t, space, 1);  // one mode: every index within 1
    if (near) continue;
    taken.push_back(i);
    out.push_back(space.centre(b.key));
  }
  return out;
}

// Up to `count` distinct modes of the object of bin `best` (its best bin), best first, as Candidates::modes
// (without a pose prior): the fit's starts for a leading object other than the best one.
std::vector<RigidPose> object_modes(const BeliefState& belief, const PoseSpace& space, std::uint64_t best,
                                    std::size_t count) {
  std::vector<RigidPose> modes;
  if (count == 0) return modes;
  modes.push_back(refine(belief, space, best, {}));
  for (const RigidPose& m : next_modes(belief, space, best, count - 1, {})) modes.push_back(m);
  return modes;
}

// What the calibration reads of a belief's reductions (its reading count is the calibrate stage's to set).
EvidenceLevel evidence_level(const BeliefSummary& summary, std::size_t pairs_folded, const PoseSpace& space) {
  EvidenceLevel e;
  e.object_log2_mass = object_log2_mass(summary, space);
  if (pairs_folded > 0)
    e.best_bits_per_pair = belief_math::units_to_bits(summary.max_offset) / static_cast<double>(pairs_folded);
  return e;
}

// The request's pose priors, or none.
const PoseWeighting& pose_prior_of(const CandidateRequest& r) {
  static const PoseWeighting none;
  return r.pose_weighting ? *r.pose_weighting : none;
}

// The leading touched objects by log-evidence (ties to the smaller id): an order no temperature changes.
std::vector<std::uint32_t> leading_objects(const EvidenceLevel& level, const BeliefSummary& s, std::size_t count) {
  std::vector<std::uint32_t> order(level.object_log2_mass.size());
  std::iota(order.begin(), order.end(), 0u);
  const std::vector<double>& l = level.object_log2_mass;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return l[x] > l[y]; });
  std::vector<std::uint32_t> out;
  for (std::uint32_t o : order) {
    if (out.size() >= count) break;
    if (s.touched[o] > 0) out.push_back(o);
  }
  return out;
}

// The leading objects with their fit starts. The best object reuses its modes when no pose prior ordered them
// (they are then its own); the others start from their own best bins.
std::vector<LeadingObject> leading_with_starts(const BeliefState& belief, const PoseSpace& space, const Candidates& c,
                                               const CandidateRequest& r) {
  const std::vector<std::uint32_t> order = leading_objects(c.level, c.summary, r.leading);
  if (order.size() < 2) return {};
  const bool modes_are_own = !r.pose_weighting || r.pose_weighting->empty();
  std::vector<LeadingObject> out;
  for (std::uint32_t o : order) {
    LeadingObject l;
    l.object = o;
    l.best_key = c.summary.best_key[o];
    const bool own = modes_are_own && o == c.object && c.pose_valid && !c.modes.empty();
    l.starts = own ? c.modes : object_modes(belief, space, l.best_key, c.modes.empty() ? 1 : c.modes.size());
    out.push_back(std::move(l));
  }
  return out;
}

// The best object of `c` by the tempered posterior (untempered: by the integer masses, ties to the smaller id, as
// Eq 5 does), with its best bin, parabolic peak and modes.
void best_object(const BeliefState& belief, const PoseSpace& space, const std::vector<double>& mass,
                 const CandidateRequest& r, Candidates* c) {
  const PoseWeighting& prior = pose_prior_of(r);
  const BeliefSummary& s = c->summary;
  const bool tempered = r.temperature != 1.0;
  c->object_probability = tempered ? tempered_posterior(c->level.object_log2_mass, r.temperature, r.object_weight)
                                   : c->raw_object_probability;
  const std::vector<double>& score = tempered ? c->object_probability : mass;
  c->object = 0;
  for (std::uint32_t o = 1; o < mass.size(); ++o)
    if (score[o] > score[c->object]) c->object = o;
  if (s.touched[c->object] == 0) return;
  c->pose_valid = true;
  c->best_key = prior.applies_to(c->object) ? best_bin_under_prior(belief, s, c->object, prior) : s.best_key[c->object];
  c->bin_pose = space.centre(c->best_key);
  c->parabolic_pose = refine(belief, space, c->best_key, prior);
  c->pose = c->parabolic_pose;
  if (r.modes > 0) {
    c->modes.push_back(c->parabolic_pose);
    for (const RigidPose& m : next_modes(belief, space, c->best_key, r.modes - 1, prior)) c->modes.push_back(m);
  }
}

}  // namespace

std::size_t best_bins_asked(const CandidateRequest& r) {
  std::size_t k = r.top_k;
  // next_modes' candidates for the best object's modes after the first, and for a leading object's (as many).
  if (r.modes > 1) k = std::max(k, 16 * r.modes);
  const bool prior = r.pose_weighting && !r.pose_weighting->empty();
  if (r.hypotheses && r.top_k > 0) k = std::max(k, mode_candidates(r.top_k, prior));
  if (prior) k = std::max(k, kPosePriorCandidates);
  return k;
}

KeyChoice key_choice(const CandidateRequest& r) {
  KeyChoice c;
  const bool prior = r.pose_weighting && !r.pose_weighting->empty();
  const std::size_t count = r.hypotheses ? r.top_k : 0;  // as keys_read
  c.mode_best = static_cast<std::uint32_t>(mode_candidates(count, prior));
  // With a prior, the objects' best bins under it come from the kPosePriorCandidates best bins too; a device sorts
  // the candidates in one invocation, so a longer list is the host's to choose.
  c.prior_best = prior ? static_cast<std::uint32_t>(kPosePriorCandidates) : 0u;
  c.best = std::max(c.mode_best, c.prior_best);
  if (prior && c.best > kPriorMostCandidates) return c;
  c.on = true;
  c.modes = static_cast<std::uint32_t>(count);
  c.suppress = r.hypothesis_radius_bins;
  c.radius = std::max(r.hypothesis_radius_bins, 1);
  if (prior) c.prior = r.pose_weighting->device_terms();
  return c;
}

std::vector<std::uint64_t> keys_read(const BeliefState& belief, const PoseSpace& space, const CandidateRequest& r) {
  const std::size_t count = r.hypotheses ? r.top_k : 0;  // without hypotheses: the objects' best bins alone
  return hypothesis_keys(belief, space, belief.summarise(), count, r.hypothesis_radius_bins, pose_prior_of(r));
}

Candidates find_candidates(const BeliefState& belief, const PoseSpace& space, const CandidateRequest& r) {
  Candidates c;
  c.summary = belief.summarise();
  // The most best bins this stage reads, asked first: every later request (the top bins, the modes' candidates) is a
  // prefix of what the belief then keeps, so its shards are passed once, whatever order the requests come in (a
  // light estimate asked for its 3 top bins before the hypotheses' 64, and the CPU reference's shards twice).
  belief.best_bins(best_bins_asked(r));
  const BeliefSummary& s = c.summary;
  const std::vector<double> mass = object_mass(s, space, r.object_weight);
  double z = 0.0;
  for (double m : mass) z += m;
  c.raw_object_probability.resize(mass.size());
  for (std::size_t o = 0; o < mass.size(); ++o) c.raw_object_probability[o] = mass[o] / z;
  c.level = evidence_level(s, belief.pairs_folded(), space);
  best_object(belief, space, mass, r, &c);
  // A bin's probability: its weight 2^(offset - M) at mass_bits over the total.
  const double scale = std::ldexp(1.0, static_cast<int>(belief_math::mass_bits(space.bins_per_object()))) / z;
  for (const BinOffset& b : belief.best_bins(r.top_k)) {
    BinHypothesis h;
    h.key = b.key;
    h.object = PoseSpace::object_of(b.key);
    h.pose = space.centre(b.key);
    h.probability = pmath::exp2(-belief_math::units_to_bits(s.max_offset - b.offset)) * scale;
    if (!r.object_weight.empty()) h.probability *= r.object_weight[h.object];
    c.top.push_back(h);
  }
  if (r.leading > 0) c.leading = leading_with_starts(belief, space, c, r);
  if (r.hypotheses && r.top_k > 0)
    c.hypotheses =
        hypotheses(belief, space, s, r.top_k, r.hypothesis_radius_bins, r.object_weight, pose_prior_of(r), r.threads);
  return c;
}

}  // namespace sva
