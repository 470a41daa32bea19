#include "recognition/estimate.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <span>

#include "recognition/belief_math.hpp"
#include "recognition/rotation.hpp"

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

double units_to_bits(std::uint64_t units) { return static_cast<double>(units) / belief_math::kUnitsPerBit; }

// Sub-bin refinement: along each axis of the pose grid, a parabola through the
// log-belief of the best bin and its two neighbours (untouched bins at the
// baseline, offset 0) puts the peak between bin centres, as peak interpolation
// does for histograms: near its maximum, the log-belief that many pairs
// concentrate is close to quadratic. An axis whose neighbour lies outside the
// grid keeps the centre; the planar angle wraps around.
RigidPose refine(const BeliefState& belief, const PoseSpace& space, std::uint64_t best) {
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
  glm::dvec3 t = space.translation_centre(c), r = space.rotation_centre(c);
  const double tw = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec.rotation_bins;
  const double oc = units_to_bits(off[0]);
  std::size_t next = 1;
  for (std::size_t a = 0; a < axes.size(); ++a) {
    if (!has[a]) continue;
    const double om = units_to_bits(off[next]), op = units_to_bits(off[next + 1]);
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
  pose.R = rotation::exp(r);
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
std::vector<RigidPose> next_modes(const BeliefState& belief, const PoseSpace& space, std::uint64_t best,
                                  std::size_t count) {
  std::vector<RigidPose> out;
  if (count == 0) return out;
  const std::uint32_t object = PoseSpace::object_of(best);
  std::vector<BinIndex> taken{space.unpack(best)};
  for (const BinOffset& b : belief.best_bins(16 * (count + 1))) {
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

BeliefEstimate estimate(const BeliefState& belief, const PoseSpace& space, std::size_t top_k, std::size_t modes,
                        std::span<const double> object_weight) {
  BeliefEstimate e;
  const BeliefSummary s = belief.summarise();
  const std::vector<double> mass = object_mass(s, space, object_weight);
  double z = 0.0;
  for (double m : mass) z += m;
  e.object_probability.resize(mass.size());
  for (std::size_t o = 0; o < mass.size(); ++o) e.object_probability[o] = mass[o] / z;
  e.object = 0;
  for (std::uint32_t o = 1; o < mass.size(); ++o)
    if (mass[o] > mass[e.object]) e.object = o;
  if (s.touched[e.object] > 0) {
    e.pose_valid = true;
    e.best_key = s.best_key[e.object];
    e.bin_pose = space.centre(e.best_key);
    e.parabolic_pose = refine(belief, space, e.best_key);
    e.pose = e.parabolic_pose;
    if (modes > 0) {
      e.modes.push_back(e.parabolic_pose);
      for (const RigidPose& m : next_modes(belief, space, e.best_key, modes - 1)) e.modes.push_back(m);
    }
  }
  // A bin's probability: its weight 2^(offset - M) at mass_bits over the total.
  const double scale = std::ldexp(1.0, static_cast<int>(belief_math::mass_bits(space.bins_per_object()))) / z;
  for (const BinOffset& b : belief.best_bins(top_k)) {
    BinHypothesis h;
    h.key = b.key;
    h.object = PoseSpace::object_of(b.key);
    h.pose = space.centre(b.key);
    h.probability = std::exp2(-units_to_bits(s.max_offset - b.offset)) * scale;
    if (!object_weight.empty()) h.probability *= object_weight[h.object];
    e.top.push_back(h);
  }
  return e;
}

}  // namespace sva
