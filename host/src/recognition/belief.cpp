#include "recognition/belief.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include "recognition/rotation.hpp"

namespace sva {

Belief::Belief(const PoseSpace& space, double eps) : space_(&space), eps_(eps) {
  if (!std::isfinite(eps) || !(eps > 0.0) || eps >= 1.0)
    throw Error("recognizer option eps = " + std::to_string(eps) + " must be in (0, 1)");
}

void Belief::reset() {
  offset_.clear();
  pairs_ = 0;
}

bool Belief::fold(const PairVotes& votes) {
  assert(votes.keys.size() == votes.mass.size());
  std::int64_t total = 0;
  for (std::int64_t m : votes.mass) total += m;  // <= 2^56 by the vote clamp
  if (total <= 0) return false;
  const double inv = 1.0 / (static_cast<double>(total) * eps_);
  for (std::size_t i = 0; i < votes.keys.size(); ++i) {
    if (votes.mass[i] <= 0) continue;
    const double add = std::log1p(static_cast<double>(votes.mass[i]) * inv);
    assert(std::isfinite(add) && add > 0.0);
    offset_.add(votes.keys[i], add);
  }
  ++pairs_;
  return true;
}

double Belief::offset(std::uint64_t key) const { return offset_.get(key); }

Belief::Sorted Belief::sorted() const {
  Sorted s;
  offset_.sorted(&s.keys, &s.offsets);
  for (double o : s.offsets) s.max_offset = std::max(s.max_offset, o);
  return s;
}

std::vector<double> Belief::object_log_mass(const Sorted& s) const {
  // mass_o / exp(M) = (untouched_o) exp(-M) + sum_touched exp(off - M), summed in key order.
  const std::uint32_t n = space_->objects();
  std::vector<double> touched_sum(n, 0.0);
  std::vector<double> touched_count(n, 0.0);
  for (std::size_t i = 0; i < s.keys.size(); ++i) {
    const std::uint32_t o = PoseSpace::object_of(s.keys[i]);
    touched_sum[o] += std::exp(s.offsets[i] - s.max_offset);
    touched_count[o] += 1.0;
  }
  std::vector<double> out(n);
  for (std::uint32_t o = 0; o < n; ++o) {
    const double untouched = space_->bins_per_object() - touched_count[o];
    // log(untouched * exp(-M) + touched_sum), stable for large M.
    const double a = std::log(std::max(untouched, 0.0)) - s.max_offset;
    const double b = touched_sum[o] > 0.0 ? std::log(touched_sum[o]) : -INFINITY;
    const double hi = std::max(a, b);
    out[o] = hi + std::log(std::exp(a - hi) + std::exp(b - hi));
  }
  return out;
}

std::vector<double> Belief::object_probability() const {
  const Sorted s = sorted();
  const std::vector<double> lm = object_log_mass(s);
  const double hi = *std::max_element(lm.begin(), lm.end());
  std::vector<double> p(lm.size());
  double z = 0.0;
  for (std::size_t o = 0; o < lm.size(); ++o) z += p[o] = std::exp(lm[o] - hi);
  for (double& v : p) v /= z;
  return p;
}

double Belief::offset_in(const Sorted& s, const BinIndex& b) const {
  const std::uint64_t key = space_->pack(b);
  auto it = std::lower_bound(s.keys.begin(), s.keys.end(), key);
  return (it != s.keys.end() && *it == key) ? s.offsets[static_cast<std::size_t>(it - s.keys.begin())] : 0.0;
}

// Sub-bin refinement: along each axis of the pose grid, a parabola through the
// log-belief of the best bin and its two neighbours (untouched bins at the
// baseline, offset 0) puts the peak between bin centres, as peak interpolation
// does for histograms: near its maximum, the log-belief that many pairs
// concentrate is close to quadratic. An axis whose neighbour lies outside the
// grid keeps the centre; the planar angle wraps around.
double Belief::axis_shift(const Sorted& s, const BinIndex& c, bool rotation, int k) const {
  const int bins = rotation ? space_->spec().rotation_bins : space_->spec().translation_bins;
  const bool wraps = rotation && space_->planar();
  const int i = rotation ? c.r[k] : c.t[k];
  int lo = i - 1, hi = i + 1;
  if (wraps) {
    lo = (lo + bins) % bins;
    hi %= bins;
  } else if (lo < 0 || hi >= bins) {
    return 0.0;
  }
  BinIndex m = c, p = c;
  (rotation ? m.r[k] : m.t[k]) = lo;
  (rotation ? p.r[k] : p.t[k]) = hi;
  const double om = offset_in(s, m), oc = offset_in(s, c), op = offset_in(s, p);
  const double curvature = om - 2.0 * oc + op;
  if (!(curvature < 0.0)) return 0.0;  // flat: no better guess than the centre
  return std::clamp(0.5 * (om - op) / curvature, -0.5, 0.5);
}

RigidPose Belief::refine(const Sorted& s, std::uint64_t best) const {
  const BinIndex c = space_->unpack(best);
  const PoseSpaceSpec& spec = space_->spec();
  const bool planar = space_->planar();
  glm::dvec3 t = space_->translation_centre(c), r = space_->rotation_centre(c);
  const double tw = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec.rotation_bins;
  for (int k = 0; k < (planar ? 2 : 3); ++k) t[k] += tw * axis_shift(s, c, false, k);
  for (int k = planar ? 2 : 0; k < 3; ++k) r[k] += rw * axis_shift(s, c, true, k);
  RigidPose pose;
  pose.T = t;
  pose.R = rotation::exp(r);
  return pose;
}

BeliefEstimate Belief::estimate(std::size_t top_k) const {
  BeliefEstimate e;
  const Sorted s = sorted();
  const std::vector<double> lm = object_log_mass(s);
  const double hi = *std::max_element(lm.begin(), lm.end());
  e.object_probability.resize(lm.size());
  double z = 0.0;
  for (std::size_t o = 0; o < lm.size(); ++o) z += e.object_probability[o] = std::exp(lm[o] - hi);
  for (double& v : e.object_probability) v /= z;
  // log Z relative to exp(M): the normaliser of bin probabilities.
  const double log_z = hi + std::log(z);
  e.object = 0;
  for (std::uint32_t o = 1; o < e.object_probability.size(); ++o)
    if (e.object_probability[o] > e.object_probability[e.object]) e.object = o;

  // Best bin of the chosen object; ties go to the smaller key (keys are sorted).
  std::size_t best = s.keys.size();
  for (std::size_t i = 0; i < s.keys.size(); ++i) {
    if (PoseSpace::object_of(s.keys[i]) != e.object) continue;
    if (best == s.keys.size() || s.offsets[i] > s.offsets[best]) best = i;
  }
  if (best < s.keys.size()) {
    e.pose_valid = true;
    e.best_key = s.keys[best];
    e.bin_pose = space_->centre(e.best_key);
    e.pose = refine(s, e.best_key);
  }

  // Top-k bins over all objects: largest offset first, ties to the smaller key.
  std::vector<std::size_t> order(s.keys.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const std::size_t k = std::min(top_k, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](std::size_t a, std::size_t b) {
                      if (s.offsets[a] != s.offsets[b]) return s.offsets[a] > s.offsets[b];
                      return s.keys[a] < s.keys[b];
                    });
  for (std::size_t i = 0; i < k; ++i) {
    BinHypothesis h;
    h.key = s.keys[order[i]];
    h.object = PoseSpace::object_of(h.key);
    h.pose = space_->centre(h.key);
    h.probability = std::exp(s.offsets[order[i]] - s.max_offset - log_z);
    e.top.push_back(h);
  }
  return e;
}

}  // namespace sva
