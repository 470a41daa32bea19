#pragma once
// Choosing where to touch next (active touch planning, docs/api.md "Choosing the next touch"). After each reading
// the recognizer holds a belief over objects and poses; the map knows every object's surface as its training
// contacts (position, normal, appearance class), and a map trained with meshes (format 9) the surfaces themselves.
// For a candidate touch the planner predicts what each hypothesis of the estimate would feel there - from the map
// alone, which a real robot has: the meshes' nearest point and normal when the map carries them (the verify stage's
// measurement model), else the nearest training contact and its classes - and scores the touch by how well the
// outcome would tell the hypotheses apart.
//
//   sva::TouchPlanner planner(map);                       // once per map (k-d trees, classes of the contacts)
//   sva::Estimate est = recognizer.estimate(8);           // the hypotheses to tell apart
//   auto candidates = planner.sample_candidates(est, 100, seed);   // or the robot's reachable touches
//   sva::TouchPlan plan = sva::plan_next_touch(planner, est, candidates);
//   if (!plan.best.empty()) move_to(plan.best[0].touch);
//
// It reads only the Estimate's hypotheses, so it is the same for every backend (CPU reference and Vulkan).
#include <sva/map.hpp>
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/recognizer.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace sva {

// A touch the robot could make (robot frame): the sensor is brought to `position` pressing along `approach`, so
// a surface felt there faces the sensor with outward normal near -approach.
struct CandidateTouch {
  glm::dvec3 position{0.0};             // mm
  glm::dvec3 approach{0.0, 0.0, -1.0};  // unit direction of the press (need not be normalised; not zero)
  bool reachable = true;                // false: the robot cannot make it; scored never, chosen never
};

struct TouchPlanOptions {
  std::size_t best = 1;               // how many candidates to return (the best k), >= 1
  std::size_t max_hypotheses = 16;    // the strongest hypotheses considered, >= 1
  double min_hypothesis_mass = 1e-4;  // hypotheses below this share of the considered mass are left out
  // Each object's best mode (Estimate::object_hypotheses) weighs at least this share, however little mass the
  // belief gives it: the belief is overconfident (every reading pairs with all earlier ones, so its evidence counts
  // many times over) and a wrong object may hold nearly all of it until the one touch that tells them apart.
  double object_floor = 0.02;
  // What a hypothesis feels at a candidate: the training contact of its object (in the hypothesis' pose) nearest
  // to the candidate among those whose outward normal lies within normal_tolerance_deg of -approach - the surface
  // a guarded move along the approach meets - or a miss when none lies within contact_tolerance_mm (0: no limit,
  // the default: in `sva eval` every planned touch ends on the true object).
  double contact_tolerance_mm = 0.0;
  double normal_tolerance_deg = 60.0;
  // How alike two predicted contacts are (1 alike, 0 told apart): the overlap of their appearance classes
  // (Bhattacharyya) times Gaussian kernels on their distance (sigma: position_sigma_mm, 0 = twice the median
  // spacing of the map's training contacts) and on the angle between their normals (normal_sigma_deg).
  double position_sigma_mm = 0.0;
  double normal_sigma_deg = 20.0;
  double confusion = 0.02;  // floor of every likeness: what any outcome may be mistaken for (sensor errors)
  // Touches already made (robot frame). A reading's evidence is its pairs with the earlier readings, and the map
  // pairs only contacts [pair_min_mm, pair_max_mm] apart (its distance bins): a candidate that pairs with none of
  // the visited touches is skipped while any candidate pairs with one, and every score is scaled by the share of
  // the visited touches the candidate pairs with. pair_min_mm, pair_max_mm < 0: the map's range. No visited
  // touches: no scaling.
  std::vector<glm::dvec3> visited;
  double pair_min_mm = -1.0;
  double pair_max_mm = -1.0;
  // The fine pose (docs/recognition.md) aligns the readings to the surface, point to plane: a touch adds to its score
  // the information (bits) its predicted contact - normal and lever arm - would give the strongest hypothesis' pose
  // beyond what the visited touches give, 0.5 log2(1 + J^T A^-1 J) with J = (n, (p - T) x n) and A the sum of the
  // visited touches' J J^T, times that hypothesis' weight - once its object holds pose_gain_confidence of the
  // posterior (Estimate::object_probability; before, telling the objects apart comes first). Needs visited_normals
  // (the outward surface normal felt at each visited touch, as many as visited); off when they are missing or
  // pose_gain is false.
  std::vector<glm::dvec3> visited_normals;
  bool pose_gain = true;
  double pose_gain_confidence = 0.95;
};

struct TouchScore {
  std::size_t candidate = 0;  // index into the candidates given
  CandidateTouch touch;
  double score = 0.0;                // expected information gain over the hypotheses (bits, >= 0; see plan())
  double contact_probability = 0.0;  // mass of the hypotheses that predict contact there
};

struct TouchPlan {
  std::vector<TouchScore> best;  // at most options.best, highest score first (ties: lower index first);
                                 // empty when no candidate is reachable
  std::size_t hypotheses = 0;    // the hypotheses scored over (0: no pose yet, every score is 0)
  std::size_t reachable = 0;     // candidates reachable (and finite)
  std::size_t pairing = 0;       // of them, those that pair with a visited touch (all when none was visited)
  std::string note;              // why the plan is empty or uninformative, "" otherwise
};

// The map's surfaces as the planner reads them: one k-d tree of training contacts per object and each contact's
// appearance classes (recovered from the pair entries it takes part in). Immutable and cheap to share: any number
// of threads may plan with one planner at once. Build once per map (paper3d: tens of milliseconds).
class TouchPlanner {
 public:
  explicit TouchPlanner(const Map& map);
  ~TouchPlanner();
  TouchPlanner(TouchPlanner&&) noexcept;
  TouchPlanner& operator=(TouchPlanner&&) noexcept;

  // Scores every reachable candidate: for each hypothesis h (mass w_h, renormalised over those considered) the
  // predicted outcome y_h (contact or not; if contact, where, the normal and the appearance classes), and the
  // likeness s(y_h, y_g) in [confusion, 1] of two outcomes (1 for two misses). The score is the expected
  // information gain under the kernel model p(y_h | g) proportional to s(y_h, y_g):
  //   score = - sum_h w_h log2( sum_g w_g s(y_h, y_g) ),
  // 0 when every hypothesis predicts the same, the entropy of the masses when every outcome tells all apart.
  // Candidates with a non-finite position or a zero or non-finite approach count as unreachable. Deterministic;
  // never throws on a candidate set (empty, one, all unreachable: an empty or all-zero plan with a note).
  TouchPlan plan(const Estimate& estimate, std::span<const CandidateTouch> candidates,
                 const TouchPlanOptions& options = {}) const;

  // `count` candidates on the hypotheses' surfaces: training contacts of the hypotheses' objects, carried by
  // their poses to the robot frame, pressed along -normal; each drawn hypothesis by mass (options' hypotheses),
  // then a contact uniformly. Deterministic for a seed. Empty when the estimate has no pose hypothesis.
  std::vector<CandidateTouch> sample_candidates(const Estimate& estimate, std::size_t count, std::uint64_t seed,
                                                const TouchPlanOptions& options = {}) const;

  // An estimate from the first touch alone, to plan the second: until two touches pair, the recognizer's estimate
  // holds no pose, but the first touch's appearance already says which objects, and where on them, it could have
  // been. For each object, `per_object` of its training contacts drawn by how alike their appearance classes are
  // to the touch's (Bhattacharyya), each aligned to the touch - the contact onto the touched position, its normal
  // onto the touch's - and turned about the normal by a random angle. An object's probability is its contacts' mean
  // likeness, normalised (uniform, with no guesses, when no contact looks alike: then every candidate scores 0); its
  // hypotheses share it equally (object_hypotheses: the first of each). pose_valid stays false: these poses are
  // guesses to plan over, not evidence. Plan with max_hypotheses >= objects x per_object to weigh them all.
  // Deterministic for a seed; sva::Error naming the fault when the touch cannot be described (not converged, an
  // image of the wrong size, a NaN) or per_object is 0.
  Estimate contact_estimate(const Reading& touch, std::size_t per_object, std::uint64_t seed) const;

  // The position sigma used when options leave it at 0 (mm): twice the median spacing of the training contacts.
  double default_position_sigma_mm() const;
  // The map's pair distance range (mm): the default pair_min_mm and pair_max_mm.
  double shortest_pair_mm() const;
  double longest_pair_mm() const;

  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

// planner.plan(estimate, candidates, options): the best options.best candidates with their scores.
TouchPlan plan_next_touch(const TouchPlanner& planner, const Estimate& estimate,
                          std::span<const CandidateTouch> candidates, const TouchPlanOptions& options = {});

}  // namespace sva
