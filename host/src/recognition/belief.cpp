#include "recognition/belief.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
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
    // Refinement: weights exp(offset - M) over the neighbourhood (untouched
    // neighbours at the baseline). Rotations are averaged as small offsets
    // from the best bin's rotation, so the mean never straddles |r| = pi.
    const BinIndex centre = space_->unpack(e.best_key);
    const glm::dmat3 Rc = rotation::exp(space_->rotation_centre(centre));
    const glm::dmat3 RcT = glm::transpose(Rc);
    double wsum = 0.0;
    glm::dvec3 tsum(0.0), rsum(0.0);
    space_->for_each_neighbour(e.best_key, [&](std::uint64_t key) {
      auto it = std::lower_bound(s.keys.begin(), s.keys.end(), key);
      const double off = (it != s.keys.end() && *it == key) ? s.offsets[static_cast<std::size_t>(it - s.keys.begin())] : 0.0;
      const double w = std::exp(off - s.max_offset);
      const BinIndex b = space_->unpack(key);
      wsum += w;
      tsum += w * space_->translation_centre(b);
      rsum += w * rotation::log(RcT * rotation::exp(space_->rotation_centre(b)));
    });
    e.pose.T = tsum / wsum;
    e.pose.R = Rc * rotation::exp(rsum / wsum);
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
