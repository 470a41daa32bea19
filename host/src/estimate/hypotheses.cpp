#include "estimate/hypotheses.hpp"

#include <sva/base/parallel.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/base/so3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include "belief/belief_math.hpp"
#include "belief/object_mass.hpp"
#include "estimate/pose_prior.hpp"
#include "votes/neighbourhood_steps.hpp"

namespace sva {

namespace {

// Every bin within `radius` grid steps (Chebyshev) of `centre` that lies in the grid, `centre` first, then the
// steps in order along (tx, ty, tz, rx, ry, rz), rz fastest (belief_hoods.comp lists them the same way). Each axis's
// steps are cut to the grid first (the planar angle goes round instead), so the loops visit only bins inside it: the
// same bins in the same order as testing every step, without the test per bin (a light estimate lists some 700 bins
// for each of its modes and each touched object).
std::vector<BinIndex> neighbourhood(const PoseSpace& space, const BinIndex& centre, int radius) {
  const PoseSpaceSpec& spec = space.spec();
  const bool planar = space.planar();
  int lo[6], hi[6];
  for (std::uint32_t a = 0; a < 6; ++a) {
    lo[a] = hood_step_lo(space, a, radius), hi[a] = hood_step_hi(space, a, radius);
    if (planar && a == 5) continue;  // round the circle
    const int at = a < 3 ? centre.t[a] : centre.r[a - 3];
    const int bins = a < 3 ? spec.translation_bins : spec.rotation_bins;
    lo[a] = std::max(lo[a], -at);
    hi[a] = std::min(hi[a], bins - 1 - at);
  }
  std::vector<BinIndex> out;
  out.reserve(neighbourhood_steps(space, radius));
  out.push_back(centre);
  const int rb = spec.rotation_bins;
  BinIndex n = centre;
  for (int dx = lo[0]; dx <= hi[0]; ++dx) {
    n.t[0] = centre.t[0] + dx;
    for (int dy = lo[1]; dy <= hi[1]; ++dy) {
      n.t[1] = centre.t[1] + dy;
      for (int dz = lo[2]; dz <= hi[2]; ++dz) {
        n.t[2] = centre.t[2] + dz;
        for (int ex = lo[3]; ex <= hi[3]; ++ex) {
          n.r[0] = centre.r[0] + ex;
          for (int ey = lo[4]; ey <= hi[4]; ++ey) {
            n.r[1] = centre.r[1] + ey;
            const bool at_centre = dx == 0 && dy == 0 && dz == 0 && ex == 0 && ey == 0;
            for (int ez = lo[5]; ez <= hi[5]; ++ez) {
              if (at_centre && ez == 0) continue;
              n.r[2] = planar ? (centre.r[2] + ez + rb) % rb : centre.r[2] + ez;
              out.push_back(n);
            }
          }
        }
      }
    }
  }
  return out;
}

// The keys of `bins`, in order.
std::vector<std::uint64_t> keys_of(const PoseSpace& space, const std::vector<BinIndex>& bins) {
  std::vector<std::uint64_t> keys;
  keys.reserve(bins.size());
  for (const BinIndex& b : bins) keys.push_back(space.pack(b));
  return keys;
}

// A mode's neighbourhood: its bins (the centre first), their keys and offsets, and the pose prior's log2 weight
// at each (empty: no prior).
struct Hood {
  std::vector<BinIndex> bins;
  std::vector<std::uint64_t> keys, offsets;
  std::vector<double> prior_bits;
  double prior_of(std::size_t i) const { return prior_bits.empty() ? 0.0 : prior_bits[i]; }
};

// The parabolic peak of the log-belief around a bin, per grid axis (as the estimate's parabolic_pose: an axis
// whose neighbour lies outside the grid, or whose parabola is not concave, keeps the centre).
RigidPose parabolic_peak(const PoseSpace& space, const BinIndex& c, const Hood& off) {
  const PoseSpaceSpec& spec = space.spec();
  const bool planar = space.planar();
  glm::dvec3 t = space.translation_centre(c), r = space.rotation_centre(c);
  const double tw = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec.rotation_bins;
  const double oc = belief_math::units_to_bits(off.offsets.front()) + off.prior_of(0);
  auto bits = [&](const BinIndex& b) {
    const auto i =
        static_cast<std::size_t>(std::find(off.keys.begin(), off.keys.end(), space.pack(b)) - off.keys.begin());
    return belief_math::units_to_bits(off.offsets[i]) + off.prior_of(i);
  };
  for (int a = 0; a < 6; ++a) {
    const bool rotation = a >= 3;
    const int k = a % 3;
    if (planar && ((!rotation && k == 2) || (rotation && k != 2))) continue;
    const int bins = rotation ? spec.rotation_bins : spec.translation_bins;
    const int i = rotation ? c.r[k] : c.t[k];
    int lo = i - 1, hi = i + 1;
    if (rotation && planar) {
      lo = (lo + bins) % bins;
      hi %= bins;
    } else if (lo < 0 || hi >= bins) {
      continue;
    }
    BinIndex m = c, p = c;
    (rotation ? m.r[k] : m.t[k]) = lo;
    (rotation ? p.r[k] : p.t[k]) = hi;
    const double om = bits(m), op = bits(p);
    const double curvature = om - 2.0 * oc + op;
    if (!(curvature < 0.0)) continue;
    const double shift = std::clamp(0.5 * (om - op) / curvature, -0.5, 0.5);
    (rotation ? r[k] : t[k]) += (rotation ? rw : tw) * shift;
  }
  RigidPose pose;
  pose.T = t;
  pose.R = so3::exp(r);
  return pose;
}

// The small rotations log(R_bin R_centre^T) of a neighbourhood's rotation bins, each computed once: few distinct
// rotation bins (3^3 at radius 1) recur across its translations. A bin's slot is its step from the centre along each
// rotation axis (the planar angle round the circle), so the value is the same function of the bin as before.
class SmallRotations {
 public:
  SmallRotations(const PoseSpace& space, const BinIndex& centre, int radius) : space_(space), centre_(centre) {
    std::size_t size = 1;
    for (int k = 0; k < 3; ++k) {
      lo_[k] = hood_step_lo(space, 3 + k, radius);
      hi_[k] = hood_step_hi(space, 3 + k, radius);
      size *= static_cast<std::size_t>(hi_[k] - lo_[k] + 1);
    }
    r0t_ = glm::transpose(so3::exp(space.rotation_centre(centre)));
    values_.resize(size);
    known_.assign(size, false);
  }

  const glm::dvec3& of(const BinIndex& b) {
    const int bins = space_.spec().rotation_bins;
    std::size_t slot = 0;
    for (int k = 0; k < 3; ++k) {
      int d = b.r[k] - centre_.r[k];
      if (space_.planar() && k == 2) {
        d = ((d % bins) + bins) % bins;
        if (d > hi_[k]) d -= bins;
      }
      slot = slot * static_cast<std::size_t>(hi_[k] - lo_[k] + 1) + static_cast<std::size_t>(d - lo_[k]);
    }
    if (!known_[slot]) {
      values_[slot] = so3::log(so3::exp(space_.rotation_centre(b)) * r0t_);
      known_[slot] = true;
    }
    return values_[slot];
  }

 private:
  const PoseSpace& space_;
  BinIndex centre_;
  int lo_[3], hi_[3];
  glm::dmat3 r0t_;
  std::vector<glm::dvec3> values_;
  std::vector<bool> known_;
};

// Mass and covariance of the bins around a mode (its hood's entries `kept`, the centre first): each bin weighs its
// posterior probability; a bin's coordinates are its translation from the mode's bin and the small rotation
// log(R_bin R_mode^T).
// The mass is counted as the object posterior's is (estimate.cpp: integer weights at mass_bits, over the same
// total `z`), so the modes' masses add up within their object's probability; the spread weighs bins by their
// posterior relative to the mode's own bin (never 0, however far the mode is below the maximum).
void moments(const PoseSpace& space, const Hood& hood, std::span<const std::uint32_t> kept, int radius,
             std::uint64_t max_offset, std::uint32_t mass_bits, double z, ModeHypothesis* h) {
  const PoseSpaceSpec& spec = space.spec();
  const BinIndex& centre = hood.bins.front();
  const glm::dvec3 t0 = space.translation_centre(centre);
  SmallRotations small_rotation(space, centre, std::max(radius, 1));
  const bool prior = !hood.prior_bits.empty();
  std::vector<std::array<double, 6>> x(kept.size());
  std::vector<double> w(kept.size());
  double sum = 0.0;
  std::uint64_t mass = 0;
  double prior_mass = 0.0;  // with a pose prior: each bin's integer weight times the prior's there
  const double centre_bits = belief_math::units_to_bits(hood.offsets.front()) + hood.prior_of(0);
  std::array<double, 6> mean{};
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const std::size_t i = kept[j];
    const std::uint64_t offset = hood.offsets[i];
    const std::uint64_t m = belief_math::sva_exp2_neg_units(max_offset - offset, mass_bits);
    mass += m;
    if (prior) prior_mass += static_cast<double>(m) * pmath::exp2(hood.prior_bits[i]);
    w[j] = pmath::exp2(belief_math::units_to_bits(offset) + hood.prior_of(i) - centre_bits);
    // A bin whose weight relative to the mode's own underflows to 0 adds exactly +-0 to the sums below, which start
    // at +0 and are never -0: it is left out, the same bits (most of a neighbourhood at 100 paper3d readings).
    if (w[j] == 0.0) continue;
    const glm::dvec3 dt = space.translation_centre(hood.bins[i]) - t0;
    const glm::dvec3& dr = small_rotation.of(hood.bins[i]);
    x[j] = {dt.x, dt.y, dt.z, dr.x, dr.y, dr.z};
    sum += w[j];
    for (int a = 0; a < 6; ++a) mean[a] += w[j] * x[j][a];
  }
  h->probability = (prior ? prior_mass : static_cast<double>(mass)) / z;
  for (double& m : mean) m /= sum;
  // The weighted sums of (x_a - m_a)(x_b - m_b), each divided by the weights' sum once at the end, the upper
  // triangle mirrored: a covariance that is symmetric bit for bit (as a ROS message or a Cholesky factor expects),
  // without a division per term (36 a bin were three quarters of this function's time, and the transposed terms'
  // roundings differed). Every row's six sums are independent, so they run side by side in SIMD lanes; the lower
  // triangle's are made and dropped, which costs less than a loop of varying length.
  std::array<double, 36> spread{};
  for (std::size_t j = 0; j < kept.size(); ++j) {
    if (w[j] == 0.0) continue;  // +-0 to every term, as above
    std::array<double, 6> d;
    for (int b = 0; b < 6; ++b) d[b] = x[j][b] - mean[b];
    for (int a = 0; a < 6; ++a) {
      const double u = w[j] * d[a];
      for (int b = 0; b < 6; ++b) spread[a * 6 + b] += u * d[b];
    }
  }
  for (int a = 0; a < 6; ++a)
    for (int b = a; b < 6; ++b) h->covariance[a * 6 + b] = h->covariance[b * 6 + a] = spread[a * 6 + b] / sum;
  // A bin is a box, not a point: its uniform spread adds width^2 / 12 per free axis.
  const double tw = (spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins;
  const double rw = 2.0 * std::numbers::pi / spec.rotation_bins;
  for (int a = 0; a < 6; ++a) {
    const bool fixed = space.planar() && (a == 2 || a == 3 || a == 4);
    if (fixed)
      for (int b = 0; b < 6; ++b) h->covariance[a * 6 + b] = h->covariance[b * 6 + a] = 0.0;
    else
      h->covariance[a * 6 + a] += (a < 3 ? tw * tw : rw * rw) / 12.0;
  }
}

// The neighbourhoods of `centres` with their offsets: built on the workers (a hundred objects' best modes are most
// of a large map's estimate), then one read of all their offsets (one device round trip on a GPU backend).
std::vector<Hood> read_hoods(const BeliefState& belief, const PoseSpace& space, const std::vector<BinIndex>& centres,
                             int radius, const PoseWeighting& pose_weighting, unsigned threads) {
  std::vector<Hood> hoods(centres.size());
  util::parallel_for(
      centres.size(),
      [&](std::size_t m) {
        Hood& h = hoods[m];
        h.bins = neighbourhood(space, centres[m], std::max(radius, 1));
        h.keys = keys_of(space, h.bins);
        if (pose_weighting.applies_to(centres[m].object)) {
          h.prior_bits.reserve(h.keys.size());
          for (std::uint64_t k : h.keys) h.prior_bits.push_back(pose_weighting.log2_weight(k));
        }
      },
      threads);
  std::size_t total = 0;
  for (const Hood& h : hoods) total += h.keys.size();
  std::vector<std::uint64_t> keys;
  keys.reserve(total);
  for (const Hood& h : hoods) keys.insert(keys.end(), h.keys.begin(), h.keys.end());
  const std::vector<std::uint64_t> values = belief.offsets(keys);
  std::size_t next = 0;
  for (Hood& h : hoods) {
    h.offsets.assign(values.begin() + static_cast<std::ptrdiff_t>(next),
                     values.begin() + static_cast<std::ptrdiff_t>(next + h.keys.size()));
    next += h.keys.size();
  }
  return hoods;
}

// The hypotheses' centres: up to `count` distinct modes, greedy non-maximum suppression over the best bins (ties to
// the smaller key, as on every backend), then every touched object's best bin; *modes is how many are modes.
std::vector<BinIndex> centres_of(const BeliefState& belief, const PoseSpace& space, const BeliefSummary& summary,
                                 std::size_t count, int radius, const PoseWeighting& pose_weighting,
                                 std::size_t* modes) {
  std::vector<BinIndex> centres;
  // Candidates: the best bin alone for one mode; else as many as the fine pose's mode search reads (a request
  // beyond the bins near the maximum costs a pass over the whole belief).
  for (const BinOffset& b :
       order_by_pose_prior(belief.best_bins(mode_candidates(count, !pose_weighting.empty())), pose_weighting)) {
    if (centres.size() >= count) break;
    const BinIndex i = space.unpack(b.key);
    bool suppressed = false;
    for (const BinIndex& c : centres) suppressed = suppressed || within_steps(i, c, space, radius);
    if (!suppressed) centres.push_back(i);
  }
  *modes = centres.size();
  for (std::uint32_t o = 0; o < space.objects(); ++o)
    if (summary.touched[o] > 0)
      centres.push_back(space.unpack(pose_weighting.applies_to(o)
                                         ? best_bin_under_prior(belief, summary, o, pose_weighting)
                                         : summary.best_key[o]));
  return centres;
}

}  // namespace

std::size_t mode_candidates(std::size_t count, bool pose_prior) {
  return count <= 1 && !pose_prior ? count : 16 * (count + 1);
}

std::vector<std::uint64_t> hypothesis_keys(const BeliefState& belief, const PoseSpace& space,
                                           const BeliefSummary& summary, std::size_t count, int radius,
                                           const PoseWeighting& pose_weighting) {
  if (summary.max_offset == 0 && belief.touched() == 0) return {};
  std::size_t modes = 0;
  std::vector<std::uint64_t> keys;
  for (const BinIndex& c : centres_of(belief, space, summary, count, radius, pose_weighting, &modes)) {
    const std::vector<std::uint64_t> hood = keys_of(space, neighbourhood(space, c, std::max(radius, 1)));
    keys.insert(keys.end(), hood.begin(), hood.end());
  }
  return keys;
}

HypothesisSet hypotheses(const BeliefState& belief, const PoseSpace& space, const BeliefSummary& summary,
                         std::size_t count, int radius, std::span<const double> object_weight,
                         const PoseWeighting& pose_weighting, unsigned threads) {
  HypothesisSet set;
  set.per_object.resize(space.objects());
  set.per_object_valid.assign(space.objects(), false);
  if (summary.max_offset == 0 && belief.touched() == 0) return set;
  std::size_t modes = 0;
  const std::vector<BinIndex> centres = centres_of(belief, space, summary, count, radius, pose_weighting, &modes);
  for (std::uint32_t o = 0; o < space.objects(); ++o) set.per_object_valid[o] = summary.touched[o] > 0;
  const std::vector<Hood> hoods = read_hoods(belief, space, centres, radius, pose_weighting, threads);
  const double z = total_mass(summary, space, object_weight);
  const std::uint32_t mass_bits = belief_math::mass_bits(space.bins_per_object());
  // Neighbourhoods of two modes may overlap (modes radius + 1 steps apart): a bin counts for the stronger mode
  // only, so the modes' masses never sum past the object's. The modes claim in order, each object's best mode claims
  // nothing; then every centre's peak, mass and spread run on the workers (the modes' in turn were a quarter of the
  // stage's critical path at 30 paper3d readings on 16 workers).
  std::vector<std::vector<std::uint32_t>> kept(centres.size());
  std::vector<std::uint64_t> claimed;  // the claimed keys, sorted (a neighbourhood lists each bin once)
  const auto keep = [&](std::size_t m, std::vector<std::uint64_t>* claim) {
    // The parabola needed the 1-neighbourhood; at radius 0 the mass and spread take the bin alone. The centre
    // lies beyond every stronger mode's radius: never claimed.
    std::vector<std::uint32_t>& k = kept[m];
    k.reserve(hoods[m].bins.size());
    for (std::size_t i = 0; i < hoods[m].bins.size() && (radius > 0 || i == 0); ++i)
      if (!claim || !std::binary_search(claim->begin(), claim->end(), hoods[m].keys[i]))
        k.push_back(static_cast<std::uint32_t>(i));
    if (!claim) return;
    const std::size_t before = claim->size();
    for (std::uint32_t i : k) claim->push_back(hoods[m].keys[i]);
    std::sort(claim->begin() + static_cast<std::ptrdiff_t>(before), claim->end());
    std::inplace_merge(claim->begin(), claim->begin() + static_cast<std::ptrdiff_t>(before), claim->end());
  };
  for (std::size_t m = 0; m < modes; ++m) keep(m, &claimed);
  std::vector<ModeHypothesis> all(centres.size());
  util::parallel_for(
      centres.size(),
      [&](std::size_t m) {
        if (m >= modes) keep(m, nullptr);
        ModeHypothesis& h = all[m];
        h.object = centres[m].object;
        h.key = space.pack(centres[m]);
        h.pose = parabolic_peak(space, centres[m], hoods[m]);
        moments(space, hoods[m], kept[m], radius, summary.max_offset, mass_bits, z, &h);
        if (!object_weight.empty()) h.probability *= object_weight[h.object];
      },
      threads);
  set.modes.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(modes));
  for (std::size_t m = modes; m < all.size(); ++m) set.per_object[all[m].object] = all[m];
  return set;
}

std::array<double, 36> covariance_to_robot(const std::array<double, 36>& grid, const glm::dmat3& workspace) {
  // C_robot = B C B^T with B = diag(R, R); glm is column-major: R[col][row].
  auto b = [&](int i, int j) {
    if ((i < 3) != (j < 3)) return 0.0;
    return workspace[j % 3][i % 3];
  };
  std::array<double, 36> tmp{}, out{};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k) tmp[i * 6 + j] += b(i, k) * grid[k * 6 + j];
  // The upper triangle, mirrored: a symmetric input stays symmetric bit for bit (the two orders of a sum round
  // differently).
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) {
      for (int k = 0; k < 6; ++k) out[i * 6 + j] += tmp[i * 6 + k] * b(j, k);
      out[j * 6 + i] = out[i * 6 + j];
    }
  return out;
}

}  // namespace sva
