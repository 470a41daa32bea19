#include "eval/surface_errors.hpp"

#include <sva/base/parallel.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>

#include "eval/metrics.hpp"

#ifdef SVA_HAVE_SIM
#include <sva/sim/mesh.hpp>
#endif

namespace sva::eval {

namespace {

// One model per mesh, size and centring: symmetry search and sampling once per object in a process, however many
// evaluations (sva demo runs two) and trials read it.
std::shared_ptr<const SurfaceModel> build_model(const SceneObject& object) {
#ifdef SVA_HAVE_SIM
  std::error_code ec;
  if (object.mesh.empty() || !std::filesystem::is_regular_file(object.mesh, ec)) return nullptr;
  const sim::Mesh mesh = sim::load_object_mesh(object);
  ObjectSurface surface{mesh.positions, mesh.triangles};
  const std::string what = object.mesh.string() + " (object \"" + object.name + "\")";
  auto model = std::make_shared<SurfaceModel>();
  model->surface = std::make_unique<SurfaceDistance>(surface, what);
  model->symmetry = find_symmetries(surface, *model->surface, SymmetrySearch{});
  model->points = model->surface->sample(500, 2);
  model->adds_points.assign(model->points.begin(), model->points.begin() + 200);
  model->symmetries = symmetry_rotations(model->symmetry);
  return model;
#else
  (void)object;
  return nullptr;
#endif
}

}  // namespace

std::shared_ptr<const SurfaceModel> surface_model(const SceneObject& object) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const SurfaceModel>> cache;
  char key_tail[64];
  std::snprintf(key_tail, sizeof key_tail, "|%.17g|%d", object.size_mm, object.center ? 1 : 0);
  const std::string key = object.mesh.string() + key_tail;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  auto model = build_model(object);
  cache.emplace(key, model);
  return model;
}

std::optional<MeshSymmetry> object_symmetry(const SceneObject& object) {
  const auto model = surface_model(object);
  if (!model) return std::nullopt;
  return model->symmetry;
}

std::vector<std::string> symmetry_warnings(const Scene& scene) {
  std::vector<std::string> out;
  for (const SceneObject& o : scene.objects)
    if (const auto found = object_symmetry(o))
      if (std::string w = symmetry_disagreement(o, *found); !w.empty()) out.push_back(std::move(w));
  return out;
}

void add_surface_errors(EvalResult& result, const Scene& scene, unsigned threads) {
  std::vector<std::shared_ptr<const SurfaceModel>> models;
  for (const SceneObject& o : scene.objects) models.push_back(surface_model(o));
  util::parallel_for(
      result.trials.size(),
      [&](std::size_t t) {
        TrialResult& trial = result.trials[t];
        const SurfaceModel* m = trial.object < models.size() ? models[trial.object].get() : nullptr;
        if (!m) return;
        for (StepResult& s : trial.steps) {
          if (!s.has_pose_error()) continue;
          s.mssd_mm = mssd(trial.pose, s.estimate, m->points, m->symmetries, m->symmetry.centre);
          s.adds_mm = adds(trial.pose, s.estimate, m->adds_points, *m->surface);
        }
      },
      threads);
}

}  // namespace sva::eval
