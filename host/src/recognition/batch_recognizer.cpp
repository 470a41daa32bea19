// The session table of batch recognition: each session is a Bayes filter (Method::sva) or an appearance-only
// posterior (Method::appearance); one backend serves all sessions, and one update carries every session that got
// a reading. The estimate runs as the stages of estimate/pipeline.hpp, a prior is checked in prior_checks.cpp.
#include <sva/base/float_environment.hpp>
#include <sva/base/parallel.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <set>
#include <string>

#include "backends/vote_backend.hpp"
#include "backends/vote_backend_factory.hpp"
#include "estimate/fine_pose.hpp"
#include "estimate/pipeline.hpp"
#include "estimate/pose_prior.hpp"
#include "estimate/report.hpp"
#include "map/map_access.hpp"
#include "map/pair_map.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/engine.hpp"
#include "recognition/engine_access.hpp"
#include "recognition/prior_checks.hpp"
#include "recognition/session_file.hpp"
#include "votes/pose_space.hpp"

namespace sva {

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
  const SurfaceIndex* surface = nullptr;        // the fine pose's (the engine's), or none
  const SurfaceModel* surface_model = nullptr;  // the verify stage's model of the map's meshes, or none
  RefineSettings refine;
  // Every public call takes it: a recognizer may be shared between threads (and a const estimate() runs GPU
  // work that writes caches of the belief).
  mutable std::mutex mutex;
  mutable EstimateTiming last_estimate_timing;  // of the last estimates() (under `mutex`)

  Impl(const Engine& e, const PoseSpaceSpec& spec, const RecognizerOptions& o)
      : engine(e),
        pair_map(&MapAccess::pair_map(e.map())),
        options(o),
        space(spec, static_cast<std::uint32_t>(MapAccess::pair_map(e.map()).objects.size())) {}

  EstimateRequest request(const Session& s, std::size_t top_k, unsigned threads, EstimateDepth depth) const;
  Estimate estimate_without_belief(const Session& s) const;
  Estimate finish(const Session& s, Estimate e) const;
  std::vector<ObservedReading> describe(std::span<const std::size_t> ids, std::span<const Reading> readings) const;
  // A device's reads of the sessions' beliefs ahead of their stage 1: each pass once for all of them (a round trip
  // each: the summaries, the best bins, then the bins read by key), so that each stage 1 reads what came back.
  void read_ahead(const std::vector<const Session*>& piped, std::size_t top_k, unsigned threads,
                  EstimateDepth depth) const;

  const Session& at(std::size_t s) const {
    if (s >= sessions.size())
      throw Error("session " + std::to_string(s) + " out of range (" + std::to_string(sessions.size()) + " sessions)");
    return sessions[s];
  }
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
  EngineAccess::impl(impl_->engine)->keep_backend.reset();
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
  if (!(options.unknown_prior > 0.0 && options.unknown_prior < 1.0))
    throw Error("recognizer option unknown_prior = " + std::to_string(options.unknown_prior) + " must be in (0, 1)");
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
    impl_->backend = make_vote_backend(engine.backend(), *impl_->pair_map, impl_->space, vs,
                                       vulkan_options(*EngineAccess::impl(engine)))
                         .backend;
    FilterOptions fo;
    fo.eps = options.eps;
    fo.object_prune_probability = options.object_prune_probability;
    fo.max_pairs_per_update = options.max_pairs_per_update;
    fo.belief_budget_bins = options.belief_budget_bins;
    std::vector<std::unique_ptr<BayesFilter>> filters =
        BayesFilter::make_sessions(*impl_->pair_map, impl_->space, fo, *impl_->backend, sessions);
    for (std::size_t i = 0; i < sessions; ++i) impl_->sessions[i].filter = std::move(filters[i]);
    // The fine pose's fit also tells p_unknown how well the best object's surface explains the contacts.
    if (options.refine_pose || options.surface_check ||
        (options.calibrate && !impl_->pair_map->calibration.unknown.empty())) {
      impl_->surface = &EngineAccess::impl(engine)->surface();
      impl_->surface_model = EngineAccess::impl(engine)->surface_model();
      impl_->refine = refine_settings(impl_->space, impl_->pair_map->fine_pose_from());
    }
    impl_->refine.threads = options.threads;  // the estimate's workers: its fits and its per-object work
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
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
  const std::lock_guard lock(impl_->mutex);
  if (sessions.size() != readings.size())
    throw Error("batch recognizer: " + std::to_string(sessions.size()) + " sessions but " +
                std::to_string(readings.size()) + " readings");
  std::set<std::size_t> seen;
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    impl_->at(sessions[i]);
    if (!seen.insert(sessions[i]).second)
      throw Error("batch recognizer: session " + std::to_string(sessions[i]) + " appears twice in one update");
  }
  const std::vector<ObservedReading> observed = impl_->describe(sessions, readings);
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

// Each session's reading described (descriptor, appearance classes, grid frame) on the workers: one after another they
// were 3 ms of every 64-session step's critical path at 10 paper3d readings. The first bad reading in the sessions'
// order is the one refused, whatever the thread count.
std::vector<ObservedReading> BatchRecognizer::Impl::describe(std::span<const std::size_t> ids,
                                                             std::span<const Reading> readings) const {
  std::vector<ObservedReading> observed(ids.size());
  std::vector<std::exception_ptr> failed(ids.size());
  util::parallel_for(
      ids.size(),
      [&](std::size_t i) {
        try {
          const std::string where = (sessions.size() > 1 ? "session " + std::to_string(ids[i]) + ", " : std::string()) +
                                    "reading " + std::to_string(sessions[ids[i]].readings + 1);
          observed[i] = to_grid(space, describe_reading(*pair_map, readings[i], where));
        } catch (const Error&) {
          failed[i] = std::current_exception();
        }
      },
      options.threads);
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  return observed;
}

EstimateRequest BatchRecognizer::Impl::request(const Session& s, std::size_t top_k, unsigned threads,
                                               EstimateDepth depth) const {
  RefineSettings r = refine;
  r.threads = threads;
  return at_depth(EstimateRequest{.top_k = top_k,
                                  .hypothesis_radius_bins = options.hypothesis_radius_bins,
                                  .object_weight = s.prior_weight,
                                  .pose_weighting = s.pose_prior,
                                  .surface = surface,
                                  .refine = r,
                                  .refine_pose = options.refine_pose,
                                  .surface_check = options.surface_check,
                                  .surface_model = surface_model,
                                  .calibration = options.calibrate ? &pair_map->calibration : nullptr,
                                  .unknown_prior = options.unknown_prior},
                  depth);
}

// The estimate of a session that needs no pipeline: no reading yet, or the appearance-only method. Without evidence
// "none of these" stays at its prior.
Estimate BatchRecognizer::Impl::estimate_without_belief(const Session& s) const {
  const double no_evidence_unknown = options.calibrate ? options.unknown_prior : 0.0;
  Estimate e = s.readings == 0 ? not_ready_estimate(pair_map->objects.size(), s.prior_weight)
                               : appearance_estimate(s.appearance_log_posterior, pair_map->objects, s.prior_weight);
  e.p_unknown = no_evidence_unknown;
  return finish(s, std::move(e));
}

Estimate BatchRecognizer::Impl::finish(const Session& s, Estimate e) const {
  if (s.filter && s.readings > 0) {
    e.votes_outside = s.filter->last_update().votes_outside;
    e.votes_zero = s.filter->last_update().votes_zero;
  }
  e.readings = s.readings;
  e.votes = s.last_votes;
  return e;
}

void BatchRecognizer::Impl::read_ahead(const std::vector<const Session*>& piped, std::size_t top_k, unsigned threads,
                                       EstimateDepth depth) const {
  std::vector<const BeliefState*> beliefs;
  std::vector<KeyChoice> choices;  // for the next update to choose each session's keys on a device
  std::size_t best_bins = 0;
  for (const Session* s : piped) {
    beliefs.push_back(&s->filter->belief());
    const std::size_t readings = s->filter->observed().size();
    best_bins = std::max(best_bins, estimate_best_bins(request(*s, top_k, threads, depth), readings));
    choices.push_back(estimate_key_choice(request(*s, top_k, threads, depth), readings + 1));
  }
  backend->read_ahead(beliefs, best_bins, choices);
  std::vector<std::vector<std::uint64_t>> keys(piped.size());
  util::parallel_for(
      piped.size(),
      [&](std::size_t k) {
        const Session& s = *piped[k];
        keys[k] = estimate_keys({s.filter->belief(), s.filter->space(), s.filter->observed()},
                                request(s, top_k, threads, depth));
      },
      options.threads);
  backend->look_up_ahead(beliefs, keys);
}

// One session's estimate is a batch's of one (which gives it every worker).
Estimate BatchRecognizer::estimate(std::size_t session, std::size_t top_k, EstimateDepth depth) const {
  return estimates(std::span(&session, 1), top_k, depth).front();
}

std::vector<Estimate> BatchRecognizer::estimates(std::span<const std::size_t> sessions, std::size_t top_k,
                                                 EstimateDepth depth) const {
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
  const std::lock_guard lock(impl_->mutex);
  std::vector<Estimate> out(sessions.size());
  std::vector<std::size_t> piped;  // positions of the sessions that run the pipeline (readings and a belief)
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    const Impl::Session& s = impl_->at(sessions[i]);
    if (s.readings == 0 || !s.filter) {
      out[i] = impl_->estimate_without_belief(s);
    } else {
      s.filter->require_complete();
      piped.push_back(i);
    }
  }
  impl_->last_estimate_timing = EstimateTiming{};  // this call's, even when no session runs the stages
  if (piped.empty()) return out;
  // Each session's estimate on its share of the workers, the sessions across them: a session's fits are few, and
  // its own split of them left most workers idle in a batch. Stage 1 reads the belief: a device's read ahead for all
  // sessions (a few submissions), then each session's stage 1 from what came back, on the workers as the CPU
  // reference's (a read the read-ahead missed takes its turn on the device's queue). The same answers for any
  // thread count.
  const auto& objects = impl_->pair_map->objects;
  const bool device = impl_->engine.backend() == BackendKind::vulkan;
  // Fewer sessions than workers (a robot's one session): each session's own stages split the rest.
  const unsigned workers = impl_->options.threads ? impl_->options.threads : util::default_threads();
  const unsigned inner = static_cast<unsigned>(std::max<std::size_t>(1, workers / piped.size()));
  const auto ahead_start = std::chrono::steady_clock::now();
  if (device) {
    std::vector<const Impl::Session*> ahead;
    for (std::size_t i : piped) ahead.push_back(&impl_->sessions[sessions[i]]);
    impl_->read_ahead(ahead, top_k, inner, depth);
  }
  std::vector<EstimateStageTimes> took(piped.size());
  took.front().belief_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ahead_start).count();
  util::parallel_for(
      piped.size(),
      [&](std::size_t k) {
        const Impl::Session& s = impl_->sessions[sessions[piped[k]]];
        EstimateRequest request = impl_->request(s, top_k, inner, depth);
        request.times = &took[k];
        const auto start = std::chrono::steady_clock::now();
        util::SpanLap span;
        const Candidates candidates =
            estimate_candidates({s.filter->belief(), s.filter->space(), s.filter->observed()}, request);
        took[k].belief_ms +=
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        took[k].belief_span_ms += span.lap_ms();
        out[piped[k]] =
            impl_->finish(s, estimate_from(candidates, s.filter->observed(), s.filter->space(), objects, request));
      },
      impl_->options.threads);
  EstimateTiming& sum = impl_->last_estimate_timing;
  sum.sessions = piped.size();
  for (const EstimateStageTimes& t : took) {
    sum.belief_ms += t.belief_ms, sum.fit_ms += t.fit_ms, sum.verify_ms += t.verify_ms;
    sum.posterior_ms += t.posterior_ms;
    sum.belief_span_ms += t.belief_span_ms, sum.fit_span_ms += t.fit_span_ms;
    sum.verify_span_ms += t.verify_span_ms, sum.posterior_span_ms += t.posterior_span_ms;
  }
  return out;
}

BatchRecognizer::EstimateTiming BatchRecognizer::last_estimate_timing() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->last_estimate_timing;
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
  const util::StandardFloats floats;  // float_environment.hpp: the same bits whatever the caller's thread holds
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

void BatchRecognizer::reset(std::size_t session) { reset(std::span(&session, 1)); }

void BatchRecognizer::reset(std::span<const std::size_t> sessions) {
  const std::lock_guard lock(impl_->mutex);
  for (std::size_t session : sessions) impl_->at(session);  // every id checked before any session changes
  std::vector<BayesFilter*> filters;
  for (std::size_t session : sessions) {
    Impl::Session& s = impl_->sessions[session];
    s.prior_weight.clear();
    s.prior = {};
    s.pose_prior = {};
    s.taken.clear();  // keeps its capacity
    s.readings = 0;
    s.last_votes = 0;
    if (s.filter) filters.push_back(s.filter.get());
    std::fill(s.appearance_log_posterior.begin(), s.appearance_log_posterior.end(), 0.0);
  }
  BayesFilter::reset_all(filters);
}

std::size_t BatchRecognizer::readings(std::size_t session) const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->at(session).readings;
}

std::uint64_t BatchRecognizer::belief_bytes(std::size_t session) const {
  const std::lock_guard lock(impl_->mutex);
  const Impl::Session& s = impl_->at(session);
  return s.filter ? s.filter->belief().table_bytes() : 0;
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
    t.belief_growth_ms = st.last_belief_growth_ms;
    t.record_ms = st.last_record_ms;
    t.wait_ms = st.last_wait_ms;
    t.device_span_ms = st.last_device_span_ms;
    t.kernel_ms_by_pipeline = st.last_kernel_by_pipeline;
  }
  return t;
}

std::uint64_t BatchRecognizer::device_submissions() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->backend ? impl_->backend->statistics().device_submissions : 0;
}

std::uint64_t BatchRecognizer::device_allocations() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->backend ? impl_->backend->statistics().device_allocations : 0;
}

BatchRecognizer::Work BatchRecognizer::last_update_work() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->backend ? impl_->backend->statistics().last_work : Work{};
}

BatchRecognizer::DeviceMemory BatchRecognizer::device_memory() const {
  const std::lock_guard lock(impl_->mutex);
  DeviceMemory m;
  if (impl_->backend) {
    const BackendStats st = impl_->backend->statistics();
    m.bytes = st.device_bytes;
    m.map_bytes = st.map_device_bytes;
    m.held_bytes = st.device_held_bytes;
  }
  return m;
}

}  // namespace sva
