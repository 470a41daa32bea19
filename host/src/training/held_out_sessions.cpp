#include "training/held_out_sessions.hpp"

#include <sva/base/parallel.hpp>
#include <sva/base/pool.hpp>
#include <sva/base/progress.hpp>
#include <sva/base/rng.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "backends/vote_backend_factory.hpp"
#include "estimate/pipeline.hpp"
#include "estimate/verify.hpp"
#include "reading/observed_reading.hpp"
#include "recognition/bayes_filter.hpp"
#include "training/session_sampling.hpp"
#include "votes/pose_space.hpp"

namespace sva {

namespace {

// The objects held out whole: a fifth of them (at least one) once there are three or more, so that the calibration
// map still tells two objects apart.
std::vector<bool> objects_held_out(std::size_t objects, util::Rng& rng) {
  std::vector<bool> out(objects, false);
  if (objects < 3) return out;
  const std::size_t count = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(0.2 * double(objects))));
  std::vector<std::size_t> order(objects);
  for (std::size_t i = 0; i < objects; ++i) order[i] = i;
  for (std::size_t k = 0; k < count; ++k) std::swap(order[k], order[k + rng.below(objects - k)]);
  for (std::size_t k = 0; k < count; ++k) out[order[k]] = true;
  return out;
}

// The converged readings of each object that the map can describe, as the filter sees them after moving with the
// session's pose: the reading in its object's own frame (the pose is applied per session).
std::vector<std::vector<Reading>> readings_by_object(const Dataset& data, const PairMap& map) {
  std::vector<std::vector<Reading>> by(data.scene.objects.size());
  for (const Sample& s : data.samples) {
    if (s.reading.status != ControllerStatus::converged || s.object >= by.size()) continue;
    try {
      (void)describe_reading(map, s.reading, "calibration reading");
    } catch (const Error&) {
      continue;  // nothing above the contact threshold: training skips such readings too
    }
    by[s.object].push_back(transform_reading(s.reading, s.object_pose.inverse()));
  }
  return by;
}

// A session's readings, as the evaluation's trials show them: distinct while they last, then drawn again.
std::vector<std::size_t> presentation_order(std::size_t pool, std::size_t count, util::Rng& rng) {
  std::vector<std::size_t> order(pool);
  for (std::size_t i = 0; i < pool; ++i) order[i] = i;
  const std::size_t distinct = std::min(count, pool);
  for (std::size_t k = 0; k < distinct; ++k) std::swap(order[k], order[k + rng.below(pool - k)]);
  order.resize(distinct);
  while (order.size() < count) order.push_back(rng.below(pool));
  return order;
}

}  // namespace

CalibrationSplit split_for_calibration(const Dataset& data, double fraction, std::uint64_t seed,
                                       bool hold_out_objects) {
  if (!(fraction > 0.0 && fraction < 1.0))
    throw Error("calibration: the held-out share of readings is " + std::to_string(fraction) +
                "; it must be in (0, 1)");
  util::Rng rng(seed, 0xca11b7a7e);
  std::vector<bool> unknown = objects_held_out(data.scene.objects.size(), rng);
  if (!hold_out_objects) unknown.assign(unknown.size(), false);
  CalibrationSplit split;
  split.map_part.scene = data.scene;
  split.map_part.scene.objects.clear();
  split.map_part.split = "calibration map";
  split.map_part.seed = data.seed;
  split.held_out.scene = data.scene;
  split.held_out.split = "calibration held out";
  split.held_out.seed = data.seed;
  for (std::size_t o = 0; o < data.scene.objects.size(); ++o) {
    split.map_object.push_back(unknown[o] ? -1 : static_cast<std::int32_t>(split.map_part.scene.objects.size()));
    if (!unknown[o]) split.map_part.scene.objects.push_back(data.scene.objects[o]);
  }
  for (std::size_t i = 0; i < data.samples.size(); ++i) {
    const Sample& s = data.samples[i];
    if (s.object >= split.map_object.size()) continue;  // training refuses such a dataset itself
    const std::int32_t m = split.map_object[s.object];
    // A reading is held out by its own draw, so the split does not depend on the order of other objects' readings.
    if (m < 0 || util::Rng(seed, 0x4e1d, i).uniform() < fraction) {
      split.held_out.samples.push_back(s);
    } else {
      Sample kept = s;
      kept.object = static_cast<std::uint32_t>(m);
      split.map_part.samples.push_back(kept);
    }
  }
  return split;
}

namespace {

// One worker's session: its backend (the votes' scratch) and its filter (a belief), reset between sessions.
struct HeldOutWorker {
  std::unique_ptr<VoteBackend> backend;
  std::unique_ptr<BayesFilter> filter;
};

// Session t of the held-out sessions: its object, pose and readings from its own seeded draw, so that it does not
// depend on which worker runs it or when.
CalibrationSession run_session(std::size_t t, const std::vector<std::uint32_t>& objects, bool is_known,
                               const std::vector<std::vector<Reading>>& pool, const CalibrationSplit& split,
                               BayesFilter& filter, const SurfaceIndex& surface, const SurfaceModel* model,
                               const RefineSettings& refine, const HeldOutSessionOptions& options) {
  const PairMap& map = filter.map();
  const std::uint32_t object = objects[t % objects.size()];
  util::Rng rng(options.seed, 0x5e55, t);
  const RigidPose pose = random_pose(rng, map.pose_space);
  const std::vector<Reading>& readings = pool[object];
  CalibrationSession s;
  s.known = is_known;
  s.object = is_known ? static_cast<std::uint32_t>(split.map_object[object]) : object;
  filter.reset();
  for (std::size_t i : presentation_order(readings.size(), options.readings, rng)) {
    const Reading r = transform_reading(readings[i], pose);
    filter.add(to_grid(filter.space(), describe_reading(map, r, "calibration reading")));
    s.steps.push_back(
        estimate_evidence({filter.belief(), filter.space(), filter.observed()}, surface, refine, true, model));
  }
  return s;
}

}  // namespace

std::vector<CalibrationSession> run_held_out_sessions(const PairMap& map, const CalibrationSplit& split,
                                                      const HeldOutSessionOptions& options) {
  const std::vector<std::vector<Reading>> pool = readings_by_object(split.held_out, map);
  std::vector<std::uint32_t> known, unknown;  // full-scene ids with held-out readings
  for (std::uint32_t o = 0; o < pool.size(); ++o) {
    if (pool[o].empty()) continue;
    (split.map_object[o] >= 0 ? known : unknown).push_back(o);
  }
  if (known.empty()) throw Error("calibration: no known object has held-out readings");
  const PoseSpace space(map.pose_space, static_cast<std::uint32_t>(map.objects.size()));
  const SurfaceIndex surface(map.readings, map.objects.size());
  const std::unique_ptr<SurfaceModel> model = surface_model_of(map);
  RefineSettings refine = refine_settings(space, options.fine_pose_from);
  refine.threads = 1;  // the sessions side by side use the workers (below); the fits' answers do not depend on it
  const std::size_t total = options.known_sessions + (unknown.empty() ? 0 : options.unknown_sessions);
  // The sessions run side by side, one per worker, each on one thread: a 12-reading session on every worker spent a
  // quarter of 2 cores waiting (2026-11-29: 28.6 s on 2 threads against 42.7 s on 1, paper3d), and sessions are
  // independent, so this costs a belief per worker and changes no result.
  util::Pool<HeldOutWorker> workers([&] {
    auto w = std::make_unique<HeldOutWorker>();
    VoteSettings vs;
    vs.threads = 1;
    w->backend = make_vote_backend(BackendKind::cpu, map, space, vs).backend;
    w->filter = std::make_unique<BayesFilter>(map, space, FilterOptions{}, *w->backend);
    return w;
  });
  std::unique_ptr<util::Progress> progress;
  if (options.progress) progress = std::make_unique<util::Progress>("calibration: held-out sessions", total);
  std::vector<CalibrationSession> sessions(total);
  util::parallel_for(
      total,
      [&](std::size_t t) {
        const bool is_known = t < options.known_sessions;
        std::unique_ptr<HeldOutWorker> w = workers.take();
        sessions[t] = run_session(t, is_known ? known : unknown, is_known, pool, split, *w->filter, surface,
                                  model.get(), refine, options);
        workers.give_back(std::move(w));
        if (progress) progress->advance();
      },
      options.threads);
  if (progress) progress->finish();
  return sessions;
}

}  // namespace sva
