// Active touch planning (sva/touch_planner.hpp): predicts, from the map's training contacts, what each hypothesis
// of an estimate would feel at a candidate touch and scores the touch by the expected information gain over the
// hypotheses under a likeness kernel. Backend-independent: it reads only the Estimate.
#include <sva/error.hpp>
#include <sva/touch_planner.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include <sva/base/finite.hpp>
#include <sva/base/float_environment.hpp>
#include <sva/base/portable_math.hpp>
#include <sva/base/rng.hpp>
#include "estimate/verify.hpp"
#include "map/map_access.hpp"
#include "planning/contact_classes.hpp"
#include "planning/planner_state.hpp"

namespace sva {

namespace {

// The median distance from a training contact to its nearest neighbour on the same object: how densely the map
// knows a surface, hence how near a touch must come to a known contact to be predicted from it.
double median_spacing(const SurfaceIndex& surface) {
  std::vector<double> d;
  std::vector<SurfaceNeighbour> nn;
  for (std::uint32_t o = 0; o < surface.objects(); ++o)
    for (const SurfacePoint& p : surface.points(o)) {
      surface.nearest(o, p.position, 2, &nn);
      if (nn.size() == 2) d.push_back(std::sqrt(nn[1].distance_sq));
    }
  if (d.empty()) return 2.5;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  const double m = d[d.size() / 2];
  return m > 0.0 ? m : 2.5;
}

}  // namespace

TouchPlanner::Impl::Impl(std::shared_ptr<const PairMap> m)
    : map(std::move(m)),
      surface(map->readings, map->objects.size()),
      model(surface_model_of(*map)),
      classes(planning::contact_classes(*map)) {
  shortest_pair_mm = map->distance.min_mm;
  longest_pair_mm = map->distance.max_mm;
  sigma_mm = 2.0 * median_spacing(surface);
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

bool finite_pose(const RigidPose& p) { return finite(p.T) && finite(p.R); }

// A hypothesis as the planner weighs it.
struct Weighed {
  std::uint32_t object = 0;
  RigidPose pose, inverse;
  double weight = 0.0;
};

bool same_mode(const PoseHypothesis& a, const PoseHypothesis& b) {
  if (a.object != b.object) return false;
  const glm::dmat3 d = a.pose.R - b.pose.R;
  return glm::length(a.pose.T - b.pose.T) < 1e-6 && glm::length(d[0]) + glm::length(d[1]) + glm::length(d[2]) < 1e-9;
}

// A hypothesis of the estimate before weighing: its mass, and whether it is its object's best mode.
struct Mode {
  const PoseHypothesis* h;
  double weight;
  bool best_of_object;
};

// The estimate's distinct hypotheses, then each object's best mode that is not among them (so that every object
// the belief reaches is represented), with their masses.
std::vector<Mode> modes_of(const Estimate& est, std::size_t objects) {
  std::vector<Mode> all;
  auto usable = [&](const PoseHypothesis& h) {
    return h.object < objects && std::isfinite(h.probability) && h.probability >= 0.0 && finite_pose(h.pose);
  };
  for (const PoseHypothesis& h : est.hypotheses)
    if (usable(h) && h.probability > 0.0) all.push_back({&h, h.probability, false});
  for (const PoseHypothesis& h : est.object_hypotheses) {
    if (!h.valid || !usable(h)) continue;
    auto same = std::find_if(all.begin(), all.end(), [&](const Mode& m) { return same_mode(*m.h, h); });
    if (same != all.end())
      same->best_of_object = true;
    else
      all.push_back({&h, h.probability, true});
  }
  return all;
}

// The modes weighed for planning: masses normalised, each object's best mode raised to at least object_floor
// (the belief is overconfident - every reading pairs with all earlier ones, so its evidence counts many times
// over, and a wrong object can hold nearly all the mass until the one telling touch - so the touches that could
// overturn it must still count), the strongest max_hypotheses kept, those below min_hypothesis_mass dropped.
std::vector<Weighed> weighed_hypotheses(const Estimate& est, const TouchPlanOptions& o, std::size_t objects) {
  std::vector<Mode> all = modes_of(est, objects);
  double total = 0.0;
  for (const Mode& m : all) total += m.weight;
  for (Mode& m : all) {
    m.weight = total > 0.0 ? m.weight / total : 0.0;
    if (m.best_of_object) m.weight = std::max(m.weight, o.object_floor);
  }
  std::stable_sort(all.begin(), all.end(), [](const Mode& a, const Mode& b) { return a.weight > b.weight; });
  if (all.size() > o.max_hypotheses) all.resize(o.max_hypotheses);
  total = 0.0;
  for (const Mode& m : all) total += m.weight;
  std::vector<Weighed> out;
  for (const Mode& m : all)
    if (m.weight > 0.0 && m.weight >= o.min_hypothesis_mass * total)
      out.push_back({m.h->object, m.h->pose, m.h->pose.inverse(), m.weight});
  double kept = 0.0;
  for (const Weighed& w : out) kept += w.weight;
  for (Weighed& w : out) w.weight /= kept;
  return out;
}

// What a hypothesis predicts at a candidate: a miss, or a contact at a training contact of its object, or on its
// mesh (then without classes).
struct Outcome {
  bool contact = false;
  glm::dvec3 position{0.0}, normal{0.0};  // robot frame
  const std::vector<ClassWeight>* classes = nullptr;
};

struct Resolved {
  double tolerance_mm, cos_normal, sigma_p, sigma_n, confusion, pair_min, pair_max;
};

// With the map's meshes: the point of the hypothesis' surface nearest to the candidate within the measurement
// model's reach, facing the sensor, as the verify stage will weigh the reading. Geometry only: the training
// contacts' classes are samples whose gaps differ between twins even where their surfaces agree, so they would
// call touches telling where they are not.
Outcome predict_on_mesh(const SurfaceModel& model, const Weighed& h, const glm::dvec3& q, const glm::dvec3& facing,
                        const Resolved& r) {
  const SurfaceModel::Nearest n = model.nearest(h.object, q, std::min(r.tolerance_mm, model.reach_mm()));
  if (!n.found || glm::dot(n.normal, facing) < r.cos_normal) return {};
  return {true, h.pose.apply(n.point), h.pose.rotate(n.normal), nullptr};
}

Outcome predict(const TouchPlanner::Impl& m, const Weighed& h, const CandidateTouch& c, const Resolved& r,
                std::vector<SurfaceNeighbour>& nn) {
  const glm::dvec3 q = h.inverse.apply(c.position), facing = -h.inverse.rotate(c.approach);
  if (m.model) return predict_on_mesh(*m.model, h, q, facing, r);
  m.surface.nearest(h.object, q, 8, &nn);
  const auto& points = m.surface.points(h.object);
  for (const SurfaceNeighbour& n : nn) {
    if (n.distance_sq > r.tolerance_mm * r.tolerance_mm) break;
    const SurfacePoint& p = points[n.index];
    if (glm::dot(p.normal, facing) < r.cos_normal) continue;
    return {true, h.pose.apply(p.position), h.pose.rotate(p.normal), &m.classes[p.reading]};
  }
  return {};
}

double likeness(const Outcome& a, const Outcome& b, const Resolved& r) {
  if (!a.contact && !b.contact) return 1.0;
  if (a.contact != b.contact) return r.confusion;
  const glm::dvec3 d = a.position - b.position;
  const double angle = pmath::acos(std::clamp(glm::dot(a.normal, b.normal), -1.0, 1.0));
  const double classes = a.classes && b.classes ? planning::class_overlap(*a.classes, *b.classes) : 1.0;
  const double alike = classes * pmath::exp(-0.5 * glm::dot(d, d) / (r.sigma_p * r.sigma_p)) *
                       pmath::exp(-0.5 * angle * angle / (r.sigma_n * r.sigma_n));
  return r.confusion + (1.0 - r.confusion) * alike;
}

// - sum_h w_h log2(sum_g w_g s(y_h, y_g)); the inner sum holds w_h s(y_h, y_h) = w_h > 0, so it is finite.
double information_gain(const std::vector<Weighed>& hyps, const std::vector<Outcome>& y, const Resolved& r) {
  double gain = 0.0;
  for (std::size_t h = 0; h < hyps.size(); ++h) {
    double agree = 0.0;
    for (std::size_t g = 0; g < hyps.size(); ++g) agree += hyps[g].weight * (g == h ? 1.0 : likeness(y[h], y[g], r));
    gain -= hyps[h].weight * pmath::log2(agree);
  }
  return std::max(gain, 0.0);
}

// The point-to-plane information of the visited touches about the strongest hypothesis' pose, inverted: what a
// further contact would add is 0.5 log2(1 + J^T A^-1 J). Off (empty) without visited normals or hypotheses.
struct PoseInformation {
  bool on = false;
  glm::dvec3 centre{0.0};
  double inverse[6][6] = {};
};

std::array<double, 6> pose_jacobian(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& centre) {
  const glm::dvec3 m = glm::cross(p - centre, n);
  return {n.x, n.y, n.z, m.x, m.y, m.z};
}

// Gauss-Jordan with partial pivoting on a symmetric positive definite 6 x 6 (regularised by the caller).
bool invert6(double a[6][6], double inv[6][6]) {
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) inv[i][j] = i == j ? 1.0 : 0.0;
  for (int c = 0; c < 6; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 6; ++r)
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    if (!(std::abs(a[pivot][c]) > 0.0)) return false;
    std::swap(a[c], a[pivot]);
    std::swap(inv[c], inv[pivot]);
    const double d = a[c][c];
    for (int j = 0; j < 6; ++j) a[c][j] /= d, inv[c][j] /= d;
    for (int r = 0; r < 6; ++r) {
      if (r == c) continue;
      const double f = a[r][c];
      for (int j = 0; j < 6; ++j) a[r][j] -= f * a[c][j], inv[r][j] -= f * inv[c][j];
    }
  }
  return true;
}

PoseInformation pose_information(const Estimate& est, const std::vector<Weighed>& hyps, const TouchPlanOptions& o) {
  PoseInformation info;
  if (!o.pose_gain || hyps.empty() || o.visited.empty() || o.visited_normals.size() != o.visited.size()) return info;
  const std::uint32_t object = hyps.front().object;
  if (object >= est.object_probability.size() || !(est.object_probability[object] >= o.pose_gain_confidence))
    return info;
  info.centre = hyps.front().pose.T;
  double a[6][6] = {};
  for (std::size_t v = 0; v < o.visited.size(); ++v) {
    const auto j = pose_jacobian(o.visited[v], o.visited_normals[v], info.centre);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) a[r][c] += j[r] * j[c];
  }
  // A direction no visited touch constrains would make the gain infinite: a ridge of a thousandth of the mean
  // eigenvalue bounds it (about 5 bits) while keeping the ranking of the others.
  double trace = 0.0;
  for (int r = 0; r < 6; ++r) trace += a[r][r];
  for (int r = 0; r < 6; ++r) a[r][r] += 1e-3 * trace / 6.0 + 1e-12;
  info.on = invert6(a, info.inverse);
  return info;
}

// The bits a contact at `y` (the strongest hypothesis' prediction) would add to its fine pose.
double pose_bits(const PoseInformation& info, const Outcome& y) {
  if (!info.on || !y.contact) return 0.0;
  const auto j = pose_jacobian(y.position, y.normal, info.centre);
  double q = 0.0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) q += j[r] * info.inverse[r][c] * j[c];
  return 0.5 * pmath::log2(1.0 + std::max(q, 0.0));
}

void check_options(const TouchPlanOptions& o) {
  auto bad = [](const std::string& what) { throw Error("touch planner options: " + what); };
  if (o.best == 0) bad("best must be at least 1, got 0");
  if (o.max_hypotheses == 0) bad("max_hypotheses must be at least 1, got 0");
  auto check = [&](const char* name, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi))
      bad(std::string(name) + " must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
          std::to_string(v));
  };
  check("min_hypothesis_mass", o.min_hypothesis_mass, 0.0, 1.0);
  check("contact_tolerance_mm", o.contact_tolerance_mm, 0.0, 1e6);
  check("normal_tolerance_deg", o.normal_tolerance_deg, 0.0, 180.0);
  check("position_sigma_mm", o.position_sigma_mm, 0.0, 1e6);
  check("normal_sigma_deg", o.normal_sigma_deg, 1e-3, 1e6);
  check("confusion", o.confusion, 0.0, 1.0);
  check("object_floor", o.object_floor, 0.0, 1.0);
  check("pose_gain_confidence", o.pose_gain_confidence, 0.0, 1.0);
  check("pair_min_mm", o.pair_min_mm, -1.0, 1e6);
  check("pair_max_mm", o.pair_max_mm, -1.0, 1e6);
  for (const glm::dvec3& v : o.visited)
    if (!finite(v)) bad("a visited touch holds a NaN or infinite coordinate");
  for (const glm::dvec3& n : o.visited_normals)
    if (!finite(n)) bad("a visited touch's normal holds a NaN or infinite coordinate");
  if (!o.visited_normals.empty() && o.visited_normals.size() != o.visited.size())
    bad(std::to_string(o.visited_normals.size()) + " visited normals for " + std::to_string(o.visited.size()) +
        " visited touches");
}

Resolved resolve(const TouchPlanner::Impl& m, const TouchPlanOptions& o) {
  Resolved r{};
  r.tolerance_mm = o.contact_tolerance_mm > 0.0 ? o.contact_tolerance_mm : std::numeric_limits<double>::infinity();
  r.cos_normal = pmath::cos(o.normal_tolerance_deg * kDeg);
  r.sigma_p = o.position_sigma_mm > 0.0 ? o.position_sigma_mm : m.sigma_mm;
  r.sigma_n = o.normal_sigma_deg * kDeg;
  r.confusion = o.confusion;
  r.pair_min = o.pair_min_mm < 0.0 ? m.shortest_pair_mm : o.pair_min_mm;
  r.pair_max = o.pair_max_mm < 0.0 ? m.longest_pair_mm : o.pair_max_mm;
  return r;
}

bool usable(const CandidateTouch& c) {
  return c.reachable && finite(c.position) && finite(c.approach) && glm::dot(c.approach, c.approach) > 0.0;
}

// The share of the visited touches a candidate would pair with (1 when none was visited).
double pairing_share(const CandidateTouch& c, const TouchPlanOptions& o, const Resolved& r) {
  if (o.visited.empty()) return 1.0;
  std::size_t pairs = 0;
  for (const glm::dvec3& v : o.visited) {
    const double d = glm::length(c.position - v);
    pairs += d >= r.pair_min && d <= r.pair_max;
  }
  return static_cast<double>(pairs) / static_cast<double>(o.visited.size());
}

// The candidates to score: the reachable ones that pair with a visited touch, or all reachable ones when none does
// (a plan never comes back empty for want of pairs).
std::vector<std::size_t> eligible(std::span<const CandidateTouch> cands, const TouchPlanOptions& o, const Resolved& r,
                                  TouchPlan& plan) {
  std::vector<std::size_t> reachable, pairing;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (!usable(cands[i])) continue;
    reachable.push_back(i);
    if (pairing_share(cands[i], o, r) > 0.0) pairing.push_back(i);
  }
  plan.reachable = reachable.size();
  plan.pairing = pairing.size();
  if (pairing.empty() && !reachable.empty()) {
    plan.note = "no reachable candidate pairs with a touch already made: scored them all";
    return reachable;
  }
  return pairing;
}

}  // namespace

TouchPlanner::TouchPlanner(const Map& map) {
  if (map.empty()) throw Error("touch planner: the map is empty");
  impl_ = std::make_shared<const Impl>(MapAccess::shared(map));
}
TouchPlanner::~TouchPlanner() = default;
TouchPlanner::TouchPlanner(TouchPlanner&&) noexcept = default;
TouchPlanner& TouchPlanner::operator=(TouchPlanner&&) noexcept = default;

double TouchPlanner::default_position_sigma_mm() const { return impl_->sigma_mm; }
double TouchPlanner::shortest_pair_mm() const { return impl_->shortest_pair_mm; }
double TouchPlanner::longest_pair_mm() const { return impl_->longest_pair_mm; }

TouchPlan TouchPlanner::plan(const Estimate& estimate, std::span<const CandidateTouch> candidates,
                             const TouchPlanOptions& options) const {
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
  check_options(options);
  const Resolved r = resolve(*impl_, options);
  TouchPlan plan;
  const std::vector<Weighed> hyps = weighed_hypotheses(estimate, options, impl_->surface.objects());
  plan.hypotheses = hyps.size();
  const std::vector<std::size_t> scored = eligible(candidates, options, r, plan);
  if (plan.reachable == 0) {
    plan.note = candidates.empty() ? "no candidate touches were given" : "no candidate touch is reachable";
    return plan;
  }
  if (hyps.empty()) plan.note = "the estimate has no pose hypothesis yet: every candidate scores 0";
  std::vector<TouchScore> scores;
  std::vector<Outcome> y(hyps.size());
  std::vector<SurfaceNeighbour> nn;
  const PoseInformation pose = pose_information(estimate, hyps, options);
  for (std::size_t i : scored) {
    CandidateTouch c = candidates[i];
    c.approach = glm::normalize(c.approach);
    TouchScore s{i, candidates[i], 0.0, 0.0};
    for (std::size_t h = 0; h < hyps.size(); ++h) {
      y[h] = predict(*impl_, hyps[h], c, r, nn);
      if (y[h].contact) s.contact_probability += hyps[h].weight;
    }
    s.score = hyps.size() > 1 ? information_gain(hyps, y, r) * pairing_share(c, options, r) : 0.0;
    if (!hyps.empty()) s.score += hyps.front().weight * pose_bits(pose, y.front());
    scores.push_back(s);
  }
  const std::size_t k = std::min(options.best, scores.size());
  std::partial_sort(scores.begin(), scores.begin() + static_cast<std::ptrdiff_t>(k), scores.end(),
                    [](const TouchScore& a, const TouchScore& b) {
                      return a.score > b.score || (a.score == b.score && a.candidate < b.candidate);
                    });
  scores.resize(k);
  plan.best = std::move(scores);
  return plan;
}

std::vector<CandidateTouch> TouchPlanner::sample_candidates(const Estimate& estimate, std::size_t count,
                                                            std::uint64_t seed, const TouchPlanOptions& options) const {
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
  check_options(options);
  const std::vector<Weighed> hyps = weighed_hypotheses(estimate, options, impl_->surface.objects());
  std::vector<CandidateTouch> out;
  if (hyps.empty()) return out;
  util::Rng rng(seed, 0x70c4);
  for (std::size_t i = 0; i < count; ++i) {
    // A hypothesis by mass (the last one takes the rounding's remainder), then one of its object's contacts.
    double u = rng.uniform();
    std::size_t h = 0;
    while (h + 1 < hyps.size() && u >= hyps[h].weight) u -= hyps[h++].weight;
    const auto& points = impl_->surface.points(hyps[h].object);
    if (points.empty()) continue;
    const SurfacePoint& p = points[rng.below(points.size())];
    out.push_back({hyps[h].pose.apply(p.position), -hyps[h].pose.rotate(p.normal), true});
  }
  return out;
}

TouchPlan plan_next_touch(const TouchPlanner& planner, const Estimate& estimate,
                          std::span<const CandidateTouch> candidates, const TouchPlanOptions& options) {
  return planner.plan(estimate, candidates, options);
}

}  // namespace sva
