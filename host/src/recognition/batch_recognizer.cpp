// Batch recognition and the single-session Recognizer on top of it: each
// session is a Bayes filter (Method::sva) or an appearance-only posterior
// (Method::appearance); one backend serves all sessions.
#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "appearance/appearance_baseline.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/describe_reading.hpp"
#include "recognition/hypotheses.hpp"
#include "recognition/pose_refinement.hpp"
#include "recognition/pose_space.hpp"
#include "recognition/vote_backend.hpp"
#include "recognition/vote_backend_factory.hpp"

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
                    int radius, std::size_t top_k, std::span<const double> prior, const BeliefEstimate& b,
                    Estimate* e) {
  const HypothesisSet set = hypotheses(filter.belief(), space, filter.belief().summarise(), top_k, radius, prior);
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
}  // namespace

struct BatchRecognizer::Impl {
  struct Session {
    std::unique_ptr<BayesFilter> filter;
    std::vector<double> appearance_log_posterior;
    std::size_t readings = 0;
    std::uint64_t last_votes = 0;
    std::vector<double> prior_weight;  // per object, largest 1; empty: flat
  };

  Map map;  // keeps the shared PairMap alive
  const PairMap* pair_map = nullptr;
  RecognizerOptions options;
  PoseSpace space;
  std::unique_ptr<VoteBackend> backend;
  BackendKind kind = BackendKind::cpu;
  std::string fallback_reason;
  std::vector<Session> sessions;
  // The fine pose: the objects' training contacts, indexed once per recognizer.
  std::unique_ptr<SurfaceIndex> surface;
  RefineSettings refine;

  Impl(const Map& m, const PoseSpaceSpec& spec, const RecognizerOptions& o)
      : map(m),
        pair_map(&m.internal()),
        options(o),
        space(spec, static_cast<std::uint32_t>(m.internal().objects.size())) {}

  Session& at(std::size_t s) {
    if (s >= sessions.size())
      throw Error("session " + std::to_string(s) + " out of range (" + std::to_string(sessions.size()) + " sessions)");
    return sessions[s];
  }
};

BatchRecognizer::BatchRecognizer(const Map& map, const PoseSpaceSpec& pose_space, std::size_t sessions,
                                 const RecognizerOptions& options) {
  if (map.empty()) throw Error("recognizer: the map is empty (not trained or not loaded)");
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
  impl_ = std::make_unique<Impl>(map, pose_space, options);
  impl_->sessions.resize(sessions);
  if (options.method == Method::sva) {
    VoteSettings vs;
    vs.likelihood_cutoff = options.likelihood_cutoff;
    vs.threads = options.threads;
    VulkanBackendOptions vo;
    vo.device = options.vulkan_device;
    VoteBackendChoice choice = make_vote_backend(options.backend, *impl_->pair_map, impl_->space, vs, vo);
    impl_->backend = std::move(choice.backend);
    impl_->kind = choice.kind;
    impl_->fallback_reason = std::move(choice.fallback_reason);
    FilterOptions fo;
    fo.eps = options.eps;
    fo.object_prune_probability = options.object_prune_probability;
    fo.max_pairs_per_update = options.max_pairs_per_update;
    for (auto& s : impl_->sessions)
      s.filter = std::make_unique<BayesFilter>(*impl_->pair_map, impl_->space, fo, *impl_->backend);
    if (options.refine_pose) {
      impl_->surface = std::make_unique<SurfaceIndex>(impl_->pair_map->readings, impl_->pair_map->objects.size());
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
  for (std::size_t i : sessions) ++impl_->sessions[i].readings;
}

Estimate BatchRecognizer::estimate(std::size_t session, std::size_t top_k) const {
  const Impl::Session& s = impl_->at(session);
  Estimate e;
  e.readings = s.readings;
  e.votes = s.last_votes;
  const auto& objects = impl_->pair_map->objects;
  if (!s.filter) {
    e.object_probability = AppearanceBaseline::posterior(s.appearance_log_posterior);
    if (!s.prior_weight.empty()) {
      double z = 0.0;
      for (std::size_t o = 0; o < e.object_probability.size(); ++o) z += e.object_probability[o] *= s.prior_weight[o];
      for (double& p : e.object_probability) p /= z;
    }
    for (std::uint32_t o = 1; o < e.object_probability.size(); ++o)
      if (e.object_probability[o] > e.object_probability[e.object]) e.object = o;
    e.object_name = objects[e.object].name;
    return e;
  }
  const BeliefEstimate b = s.filter->estimate(top_k, impl_->surface ? kRefineStarts : 1, s.prior_weight);
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
    add_hypotheses(*s.filter, impl_->space, objects, impl_->options.hypothesis_radius_bins, top_k, s.prior_weight, b,
                   &e);
  e.votes_outside = s.filter->last_update().votes_outside;
  e.votes_zero = s.filter->last_update().votes_zero;
  return e;
}

void BatchRecognizer::set_prior(std::size_t session, const Prior& prior) {
  Impl::Session& s = impl_->at(session);
  s.prior_weight = prior_weights(prior, impl_->pair_map->objects.size());
}

void BatchRecognizer::reset(std::size_t session) {
  Impl::Session& s = impl_->at(session);
  s.prior_weight.clear();
  s.readings = 0;
  s.last_votes = 0;
  if (s.filter) s.filter->reset();
  std::fill(s.appearance_log_posterior.begin(), s.appearance_log_posterior.end(), 0.0);
}

std::size_t BatchRecognizer::readings(std::size_t session) const { return impl_->at(session).readings; }

std::string BatchRecognizer::backend_description() const {
  if (!impl_->backend) return "appearance";
  if (impl_->kind == BackendKind::vulkan) return "vulkan: " + impl_->backend->statistics().device;
  return impl_->backend->name();
}

BackendKind BatchRecognizer::backend() const { return impl_->kind; }
std::string BatchRecognizer::backend_fallback_reason() const { return impl_->fallback_reason; }

BatchRecognizer::Timing BatchRecognizer::last_backend_timing() const {
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
Recognizer::~Recognizer() = default;
Recognizer::Recognizer(Recognizer&&) noexcept = default;
Recognizer& Recognizer::operator=(Recognizer&&) noexcept = default;

void Recognizer::add_reading(const Reading& reading) {
  const std::size_t session = 0;
  impl_->batch.add_readings(std::span(&session, 1), std::span(&reading, 1));
}
Estimate Recognizer::estimate(std::size_t top_k) const { return impl_->batch.estimate(0, top_k); }
void Recognizer::set_prior(const Prior& prior) { impl_->batch.set_prior(0, prior); }
void Recognizer::reset() { impl_->batch.reset(0); }
std::size_t Recognizer::readings() const { return impl_->batch.readings(0); }

}  // namespace sva
