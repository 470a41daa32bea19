// Batch recognition and the single-session Recognizer on top of it: each
// session is a Bayes filter (Method::sva) or an appearance-only posterior
// (Method::appearance); one backend serves all sessions.
#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <string>

#include "map/map_access.hpp"
#include "appearance/appearance_baseline.hpp"
#include "backends/vote_backend.hpp"
#include "backends/vote_backend_factory.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/describe_reading.hpp"
#include "recognition/engine.hpp"
#include "recognition/hypotheses.hpp"
#include "recognition/pose_refinement.hpp"
#include "recognition/session_file.hpp"
#include "votes/pose_space.hpp"

namespace sva {

namespace {
// Modes of the belief the fine pose starts from (the best bin's parabolic peak first).
constexpr std::size_t kRefineStarts = 4;

// A reading in the pose grid's frame (the workspace frame): the belief and the fine pose never see the robot frame.
ObservedReading to_grid(const PoseSpace& space, ObservedReading r) {
  const RigidPose to = space.workspace().inverse();
  r.position = to.apply(r.position);
  r.normal = to.rotate(r.normal);
  return r;
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
void add_hypotheses(const BayesFilter& filter, const PoseSpace& space, const std::vector<MapObject>& objects,
                    int radius, std::size_t top_k, std::span<const double> prior, const PoseWeighting& pose_prior,
                    const BeliefEstimate& b, Estimate* e) {
  const HypothesisSet set =
      hypotheses(filter.belief(), space, filter.belief().summarise(), top_k, radius, prior, pose_prior);
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

// Object probabilities times the prior's weights, renormalised; unchanged without a prior.
void weigh_by_prior(std::vector<double>& p, const std::vector<double>& prior_weight) {
  if (prior_weight.empty()) return;
  double z = 0.0;
  for (std::size_t o = 0; o < p.size(); ++o) z += p[o] *= prior_weight[o];
  for (double& x : p) x /= z;
}

// Before any reading there is no evidence: the object posterior is the prior (uniform without one), and no
// object, pose or hypothesis is reported, so that a caller cannot take a placeholder for an answer.
Estimate not_ready(std::size_t objects, const std::vector<double>& prior_weight) {
  Estimate e;
  e.object_probability.assign(objects, prior_weight.empty() ? 1.0 / static_cast<double>(objects) : 1.0);
  weigh_by_prior(e.object_probability, prior_weight);
  return e;
}

// A prior over objects as weights whose largest is 1 (empty: flat), checked against the map.
std::vector<double> prior_weights(const Prior& prior, std::size_t objects) {
  const std::vector<double>& p = prior.object_probability;
  if (p.empty()) return {};
  if (p.size() != objects)
    throw Error("prior: " + std::to_string(p.size()) + " object probabilities, but the map has " +
                std::to_string(objects) + " objects");
  double top = 0.0;
  for (std::size_t o = 0; o < p.size(); ++o) {
    if (!std::isfinite(p[o]) || p[o] < 0.0)
      throw Error("prior: object " + std::to_string(o) + " has probability " + std::to_string(p[o]) +
                  " (must be finite and >= 0)");
    top = std::max(top, p[o]);
  }
  if (!(top > 0.0)) throw Error("prior: every object probability is 0");
  std::vector<double> w(p.size());
  for (std::size_t o = 0; o < p.size(); ++o) w[o] = p[o] / top;
  return w;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// A rotation: finite, orthonormal to 1e-6 and proper.
bool is_rotation(const glm::dmat3& r) {
  const glm::dmat3 d = glm::transpose(r) * r - glm::dmat3(1.0);
  double worst = 0.0;
  for (int c = 0; c < 3; ++c) {
    if (!finite(r[c])) return false;
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(d[c][k]));
  }
  return worst < 1e-6 && glm::determinant(r) > 0.0;
}

// The pose priors of a Prior, checked against the map: empty, or one (optional) per object, each well formed.
void check_pose_priors(const Prior& prior, std::size_t objects) {
  const auto& p = prior.object_pose;
  if (p.empty()) return;
  if (p.size() != objects)
    throw Error("prior: " + std::to_string(p.size()) + " object pose priors, but the map has " +
                std::to_string(objects) + " objects (give one per object, empty where there is none)");
  for (std::size_t o = 0; o < p.size(); ++o) {
    if (!p[o]) continue;
    const std::string what = "prior: object " + std::to_string(o) + "'s pose prior: ";
    if (!finite(p[o]->position)) throw Error(what + "the position is not finite");
    if (!(p[o]->position_sigma_mm > 0.0) || !std::isfinite(p[o]->position_sigma_mm))
      throw Error(what + "position_sigma_mm = " + std::to_string(p[o]->position_sigma_mm) + " must be > 0");
    if (!p[o]->has_rotation) continue;
    if (!is_rotation(p[o]->rotation)) throw Error(what + "the rotation is not a rotation matrix");
    if (!(p[o]->rotation_sigma_rad > 0.0) || !std::isfinite(p[o]->rotation_sigma_rad))
      throw Error(what + "rotation_sigma_rad = " + std::to_string(p[o]->rotation_sigma_rad) + " must be > 0");
  }
}
}  // namespace

struct BatchRecognizer::Impl {
  struct Session {
    std::unique_ptr<BayesFilter> filter;
    std::vector<double> appearance_log_posterior;
    std::size_t readings = 0;
    std::uint64_t last_votes = 0;
    std::vector<double> prior_weight;  // per object, largest 1; empty: flat
    Prior prior;                       // as given (saved with the session)
    PoseWeighting pose_prior;          // the Gaussian pose priors (none: empty)
    std::vector<Reading> taken;        // the readings added, as given (saved with the session)
  };

  Engine engine;  // keeps the map, the device and the shared surface index alive
  const PairMap* pair_map = nullptr;
  RecognizerOptions options;
  PoseSpace space;
  std::unique_ptr<VoteBackend> backend;
  std::vector<Session> sessions;
  const SurfaceIndex* surface = nullptr;  // the fine pose's (the engine's), or none
  RefineSettings refine;
  // Every public call takes it: a recognizer may be shared between threads (and a const estimate() runs GPU
  // work that writes caches of the belief).
  mutable std::mutex mutex;

  Impl(const Engine& e, const PoseSpaceSpec& spec, const RecognizerOptions& o)
      : engine(e),
        pair_map(&MapAccess::pair_map(e.map())),
        options(o),
        space(spec, static_cast<std::uint32_t>(MapAccess::pair_map(e.map()).objects.size())) {}

  Session& at(std::size_t s) {
    if (s >= sessions.size())
      throw Error("session " + std::to_string(s) + " out of range (" + std::to_string(sessions.size()) + " sessions)");
    return sessions[s];
  }
};

namespace {
// The engine of a recognizer made from a map alone: its own, on the options' backend.
Engine own_engine(const Map& map, const RecognizerOptions& options) {
  if (map.empty()) throw Error("recognizer: the map is empty (not trained or not loaded)");
  EngineOptions eo;
  eo.backend = options.method == Method::sva ? options.backend : BackendKind::cpu;
  eo.vulkan_device = options.vulkan_device;
  return Engine(map, eo);
}
}  // namespace

BatchRecognizer::BatchRecognizer(const Map& map, const PoseSpaceSpec& pose_space, std::size_t sessions,
                                 const RecognizerOptions& options)
    : BatchRecognizer(own_engine(map, options), pose_space, sessions, options) {
  // Nothing else shares this engine: the recognizer's own backend keeps the device alive.
  impl_->engine.internal()->keep_backend.reset();
}

BatchRecognizer::BatchRecognizer(const Engine& engine, const PoseSpaceSpec& pose_space, std::size_t sessions,
                                 const RecognizerOptions& options) {
  const Map& map = engine.map();
  if (sessions == 0) throw Error("batch recognizer: need at least one session");
  if (pose_space.kind != map.pose_space().kind)
    throw Error(std::string("recognizer: the pose space is ") +
                (pose_space.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial") + " but map '" +
                map.scene_name() + "' was trained for a " +
                (map.pose_space().kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial") + " scene");
  if (options.hypothesis_radius_bins < 0 || options.hypothesis_radius_bins > 4)
    throw Error("recognizer option hypothesis_radius_bins = " + std::to_string(options.hypothesis_radius_bins) +
                " must be in [0, 4]");
  if (!(options.likelihood_cutoff >= 0.0f) || !std::isfinite(options.likelihood_cutoff))
    throw Error("recognizer option likelihood_cutoff = " + std::to_string(options.likelihood_cutoff) +
                " must be a finite number >= 0");
  impl_ = std::make_unique<Impl>(engine, pose_space, options);
  impl_->sessions.resize(sessions);
  if (options.method == Method::sva) {
    VoteSettings vs;
    vs.likelihood_cutoff = options.likelihood_cutoff;
    vs.threads = options.threads;
    // The engine's backend, already resolved (auto chose once, for every recognizer of the engine).
    impl_->backend =
        make_vote_backend(engine.backend(), *impl_->pair_map, impl_->space, vs, vulkan_options(*engine.internal()))
            .backend;
    FilterOptions fo;
    fo.eps = options.eps;
    fo.object_prune_probability = options.object_prune_probability;
    fo.max_pairs_per_update = options.max_pairs_per_update;
    fo.belief_budget_bins = options.belief_budget_bins;
    for (auto& s : impl_->sessions)
      s.filter = std::make_unique<BayesFilter>(*impl_->pair_map, impl_->space, fo, *impl_->backend);
    if (options.refine_pose) {
      impl_->surface = &engine.internal()->surface();
      impl_->refine = refine_settings(impl_->space);
    }
  } else {
    if (impl_->pair_map->baseline.n_objects != impl_->pair_map->objects.size())
      throw Error("recognizer: map '" + map.scene_name() + "' has no appearance baseline");
    for (auto& s : impl_->sessions) s.appearance_log_posterior.assign(impl_->pair_map->objects.size(), 0.0);
  }
}

BatchRecognizer::~BatchRecognizer() = default;
BatchRecognizer::BatchRecognizer(BatchRecognizer&&) noexcept = default;
BatchRecognizer& BatchRecognizer::operator=(BatchRecognizer&&) noexcept = default;

std::size_t BatchRecognizer::sessions() const { return impl_->sessions.size(); }

void BatchRecognizer::add_readings(std::span<const std::size_t> sessions, std::span<const Reading> readings) {
  const std::lock_guard lock(impl_->mutex);
  if (sessions.size() != readings.size())
    throw Error("batch recognizer: " + std::to_string(sessions.size()) + " sessions but " +
                std::to_string(readings.size()) + " readings");
  std::set<std::size_t> seen;
  std::vector<ObservedReading> observed;
  observed.reserve(readings.size());
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    Impl::Session& s = impl_->at(sessions[i]);
    if (!seen.insert(sessions[i]).second)
      throw Error("batch recognizer: session " + std::to_string(sessions[i]) + " appears twice in one update");
    observed.push_back(to_grid(
        impl_->space, describe_reading(*impl_->pair_map, readings[i],
                                       (impl_->sessions.size() > 1 ? "session " + std::to_string(sessions[i]) + ", "
                                                                   : std::string()) +
                                           "reading " + std::to_string(s.readings + 1))));
  }
  if (impl_->options.method == Method::sva) {
    std::vector<BayesFilter*> filters;
    for (std::size_t i : sessions) filters.push_back(impl_->sessions[i].filter.get());
    const std::vector<UpdateStats> stats = update_sessions(filters, observed);
    for (std::size_t i = 0; i < sessions.size(); ++i) impl_->sessions[sessions[i]].last_votes = stats[i].votes;
  } else {
    for (std::size_t i = 0; i < sessions.size(); ++i)
      impl_->pair_map->baseline.update(impl_->sessions[sessions[i]].appearance_log_posterior, observed[i].classes);
  }
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    ++impl_->sessions[sessions[i]].readings;
    impl_->sessions[sessions[i]].taken.push_back(readings[i]);
  }
}

Estimate BatchRecognizer::estimate(std::size_t session, std::size_t top_k) const {
  const std::lock_guard lock(impl_->mutex);
  const Impl::Session& s = impl_->at(session);
  const auto& objects = impl_->pair_map->objects;
  if (s.readings == 0) return not_ready(objects.size(), s.prior_weight);
  Estimate e;
  e.ready = true;
  e.readings = s.readings;
  e.votes = s.last_votes;
  if (!s.filter) {
    e.object_probability = AppearanceBaseline::posterior(s.appearance_log_posterior);
    weigh_by_prior(e.object_probability, s.prior_weight);
    for (std::uint32_t o = 1; o < e.object_probability.size(); ++o)
      if (e.object_probability[o] > e.object_probability[e.object]) e.object = o;
    e.object_name = objects[e.object].name;
    return e;
  }
  const BeliefEstimate b = s.filter->estimate(top_k, impl_->surface ? kRefineStarts : 1, s.prior_weight, s.pose_prior);
  e.object = b.object;
  e.object_name = objects[b.object].name;
  e.object_probability = b.object_probability;
  e.pose_valid = b.pose_valid;
  e.pose = b.pose;
  e.parabolic_pose = b.parabolic_pose;
  e.bin_pose = b.bin_pose;
  if (impl_->surface && b.pose_valid) {
    const RefinedPose r = refine_pose(*impl_->surface, b.object, s.filter->observed(), b.modes, impl_->refine);
    e.pose = r.pose;
    e.pose_refined = r.refined;
  }
  const PoseSpace& space = impl_->space;
  e.pose = space.to_robot(e.pose);
  e.parabolic_pose = space.to_robot(e.parabolic_pose);
  e.bin_pose = space.to_robot(e.bin_pose);
  for (const BinHypothesis& h : b.top) {
    Hypothesis out;
    out.object = h.object;
    out.object_name = objects[h.object].name;
    out.pose = space.to_robot(h.pose);
    out.probability = h.probability;
    e.top.push_back(out);
  }
  if (top_k > 0)
    add_hypotheses(*s.filter, impl_->space, objects, impl_->options.hypothesis_radius_bins, top_k, s.prior_weight,
                   s.pose_prior, b, &e);
  e.votes_outside = s.filter->last_update().votes_outside;
  e.votes_zero = s.filter->last_update().votes_zero;
  return e;
}

void BatchRecognizer::set_prior(std::size_t session, const Prior& prior) {
  const std::lock_guard lock(impl_->mutex);
  Impl::Session& s = impl_->at(session);
  check_pose_priors(prior, impl_->pair_map->objects.size());
  s.prior_weight = prior_weights(prior, impl_->pair_map->objects.size());
  s.prior = prior;
  s.pose_prior = PoseWeighting(prior.object_pose, impl_->space);
}

void BatchRecognizer::save_session(std::size_t session, const std::filesystem::path& file) const {
  const std::lock_guard lock(impl_->mutex);
  const Impl::Session& s = impl_->at(session);
  io::SessionFile f;
  f.scene_hash = impl_->pair_map->scene_hash;
  f.objects = static_cast<std::uint32_t>(impl_->pair_map->objects.size());
  f.scene_name = impl_->pair_map->scene_name;
  f.prior = s.prior;
  f.readings = s.taken;
  io::save_session_file(f, file);
}

void BatchRecognizer::restore_session(std::size_t session, const std::filesystem::path& file) {
  const io::SessionFile f = io::load_session_file(file);
  const PairMap& m = *impl_->pair_map;
  if (f.scene_hash != m.scene_hash || f.objects != m.objects.size())
    throw Error("session file " + file.string() + " was recorded with map '" + f.scene_name + "' (" +
                std::to_string(f.objects) + " objects), not with this recognizer's map '" + m.scene_name + "'");
  reset(session);
  // Replaying rebuilds the belief bit for bit; a prior or reading refused now (a damaged file) leaves the session
  // reset.
  try {
    set_prior(session, f.prior);
    for (const Reading& r : f.readings) add_readings(std::span(&session, 1), std::span(&r, 1));
  } catch (const Error& e) {
    reset(session);
    throw Error("session file " + file.string() + ": " + e.what());
  }
}

void BatchRecognizer::reset(std::size_t session) {
  const std::lock_guard lock(impl_->mutex);
  Impl::Session& s = impl_->at(session);
  s.prior_weight.clear();
  s.prior = {};
  s.pose_prior = {};
  s.taken.clear();  // keeps its capacity
  s.readings = 0;
  s.last_votes = 0;
  if (s.filter) s.filter->reset();
  std::fill(s.appearance_log_posterior.begin(), s.appearance_log_posterior.end(), 0.0);
}

std::size_t BatchRecognizer::readings(std::size_t session) const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->at(session).readings;
}

std::string BatchRecognizer::backend_description() const {
  const std::lock_guard lock(impl_->mutex);
  if (!impl_->backend) return "appearance";
  if (impl_->engine.backend() == BackendKind::vulkan) return "vulkan: " + impl_->backend->statistics().device;
  return impl_->backend->name();
}

BackendKind BatchRecognizer::backend() const { return impl_->engine.backend(); }
std::string BatchRecognizer::backend_fallback_reason() const { return impl_->engine.fallback_reason(); }

BatchRecognizer::Timing BatchRecognizer::last_backend_timing() const {
  const std::lock_guard lock(impl_->mutex);
  Timing t;
  if (impl_->backend) {
    const BackendStats st = impl_->backend->statistics();
    t.kernel_ms = st.last_kernel_ms;
    t.host_ms = st.last_host_ms;
    t.fold_ms = st.last_fold_ms;
  }
  return t;
}

BatchRecognizer::DeviceMemory BatchRecognizer::device_memory() const {
  const std::lock_guard lock(impl_->mutex);
  DeviceMemory m;
  if (impl_->backend) {
    const BackendStats st = impl_->backend->statistics();
    m.bytes = st.device_bytes;
    m.map_bytes = st.map_device_bytes;
  }
  return m;
}

// The single-session Recognizer is a batch of one.
struct Recognizer::Impl {
  BatchRecognizer batch;
};

Recognizer::Recognizer(const Map& map, const PoseSpaceSpec& pose_space, const RecognizerOptions& options)
    : impl_(std::make_unique<Impl>(Impl{BatchRecognizer(map, pose_space, 1, options)})) {}
Recognizer::Recognizer(const Engine& engine, const PoseSpaceSpec& pose_space, const RecognizerOptions& options)
    : impl_(std::make_unique<Impl>(Impl{BatchRecognizer(engine, pose_space, 1, options)})) {}
Recognizer::~Recognizer() = default;
Recognizer::Recognizer(Recognizer&&) noexcept = default;
Recognizer& Recognizer::operator=(Recognizer&&) noexcept = default;

void Recognizer::add_reading(const Reading& reading) {
  const std::size_t session = 0;
  impl_->batch.add_readings(std::span(&session, 1), std::span(&reading, 1));
}
Estimate Recognizer::estimate(std::size_t top_k) const { return impl_->batch.estimate(0, top_k); }
void Recognizer::set_prior(const Prior& prior) { impl_->batch.set_prior(0, prior); }
void Recognizer::save_session(const std::filesystem::path& file) const { impl_->batch.save_session(0, file); }
void Recognizer::restore_session(const std::filesystem::path& file) { impl_->batch.restore_session(0, file); }
void Recognizer::reset() { impl_->batch.reset(0); }
std::size_t Recognizer::reading_count() const { return impl_->batch.readings(0); }

}  // namespace sva
