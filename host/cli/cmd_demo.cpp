// sva demo: the main job, as separate stages: simulate the default scene into
// a cache (reused when the scene and seed match), draw previews, train the map
// (cached with the data), evaluate SVA and the appearance-only baseline, print
// the table and write the figure.
#include <sva/dataset.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>
#include <sva/scene.hpp>

#include <sva/eval/dataset_export.hpp>
#include <sva/eval/demo_cache.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/figure.hpp>
#include <sva/eval/mesh_symmetry.hpp>
#include <sva/eval/report.hpp>
#include <sva/io/text_file.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <map>

#include "args.hpp"

#if __has_include(<sva/sim/simulate.hpp>)
#include <sva/sim/mesh.hpp>
#include <sva/sim/simulate.hpp>
#define SVA_HAVE_SIM 1
#endif

namespace sva::cli {

namespace {

struct DemoConfig {
  std::filesystem::path work;
  std::string scene_name;
  std::uint64_t seed = 1;
  int train = -1, test = -1;
  unsigned threads = 0;
  std::size_t trials = 0;  // 0: two repetitions over the objects
  std::size_t max_readings = 20;
  BackendKind backend = BackendKind::automatic;
};

struct DemoData {
  Dataset train, test;
  std::filesystem::path train_file, test_file;
  bool reused = false;
};

DemoData stage_simulate(const DemoConfig& cfg, const Scene& scene) {
  const eval::DemoCache cache(cfg.work, scene);
  DemoData out;
  out.train_file = cache.train_file;
  out.test_file = cache.test_file;
  eval::CachedDatasets cached = eval::find_cached_datasets(cache, scene, cfg.seed, cfg.train, cfg.test);
  if (cached.train) {
    std::printf("[simulate] reusing cached datasets in %s\n", cache.dir.c_str());
    out.train = std::move(*cached.train);
    out.test = std::move(*cached.test);
    out.reused = true;
    return out;
  }
  if (!cached.why_not.empty())
    std::printf("[simulate] not reusing the cache in %s (%s): simulating again\n", cache.dir.c_str(),
                cached.why_not.c_str());
#ifdef SVA_HAVE_SIM
  sim::SimulateOptions opt;
  opt.seed = cfg.seed;
  opt.train_per_object = cfg.train;
  opt.test_per_object = cfg.test;
  opt.threads = cfg.threads;
  auto t0 = std::chrono::steady_clock::now();
  sim::SimulatedData data = sim::simulate(scene, opt);
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::error_code ec;
  std::filesystem::create_directories(cache.dir, ec);
  if (ec) throw Error(cache.dir.string() + ": cannot create directory: " + ec.message());
  save_dataset(data.train, out.train_file);
  save_dataset(data.test, out.test_file);
  const std::size_t n = data.train.samples.size() + data.test.samples.size();
  std::printf("[simulate] %zu readings in %.1f s (%.0f readings/s) -> %s\n", n, secs,
              secs > 0 ? static_cast<double>(n) / secs : 0.0, cache.dir.c_str());
  out.train = std::move(data.train);
  out.test = std::move(data.test);
  return out;
#else
  throw Error("sva demo: no cached datasets in " + cache.dir.string() + " and this build has no simulator");
#endif
}

void stage_preview(const DemoConfig& cfg, const DemoData& data) {
#ifdef SVA_HAVE_SIM
  for (const Dataset* d : {&data.train, &data.test}) {
    auto png = cfg.work / ("preview_" + d->scene.name + "_" + d->split + ".png");
    io::write_preview(*d, png);
    std::printf("[preview]  %s\n", png.c_str());
  }
#else
  (void)cfg;
  (void)data;
#endif
}

// The map is cached beside the data it was trained on: reused only when the datasets were reused and the map was
// trained from their scene.
Map stage_train(const DemoConfig& cfg, const DemoData& data) {
  const eval::DemoCache cache(cfg.work, data.train.scene);
  const auto& file = cache.map_file;
  if (data.reused) {
    std::string why_not;
    if (std::optional<Map> m = eval::find_cached_map(cache, data.train.scene, &why_not)) {
      std::printf("[train]    reusing cached map %s (%zu entries)\n", file.c_str(), m->entries());
      return *m;
    }
    if (!why_not.empty()) std::printf("[train]    not reusing the cached map (%s): training again\n", why_not.c_str());
  }
  TrainOptions o;
  o.threads = cfg.threads;
  o.progress = true;
#ifdef SVA_HAVE_SIM
  o.surfaces = sim::object_surfaces(data.train.scene);  // the built-in scenes' meshes: the verify stage's model
#endif
  TrainReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  Map m = Map::train(data.train, o, &rep);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.save(file);
  std::printf("[train]    %zu readings, %u classes, %zu map entries (%.1f MB) in %.1f s -> %s\n", rep.readings_used,
              m.classes(), m.entries(), static_cast<double>(m.bytes()) / 1e6, secs, file.c_str());
  return m;
}

// Which device ran SVA, and its time per update next to the CPU reference's on
// the same few trials (a few: the CPU reference is the slow one on a GPU).
void print_speed(const Map& map, const DemoData& data, const eval::EvalOptions& o, const eval::EvalResult& sva) {
  if (!sva.backend_fallback_reason.empty())
    std::printf("[speed]    backend auto chose the CPU reference: %s\n", sva.backend_fallback_reason.c_str());
  const eval::SpeedComparison s = eval::compare_with_cpu_reference(map, data.test, o, sva, 4);
  if (!s.update_ms || !s.cpu_update_ms) return;
  std::printf("[speed]    SVA ran on %s: %.2f ms per update (median over the first %zu trials)\n", s.device.c_str(),
              *s.update_ms, s.trials);
  if (sva.backend == eval::backend_name(BackendKind::cpu)) return;
  std::printf("[speed]    %s on the same trials: %.2f ms per update; %s runs %.2fx as fast\n", s.cpu_device.c_str(),
              *s.cpu_update_ms, sva.backend.c_str(), *s.update_ms > 0 ? *s.cpu_update_ms / *s.update_ms : 0.0);
}

// The headline pose error: MSSD, which counts a symmetric copy of the truth as right (the angle counts it as a
// 180 degree error when the scene does not declare the symmetry); docs/pose-errors.md.
void print_headline(const eval::Curve& c) {
  std::string line;
  for (const eval::CurvePoint& p : c.points) {
    if (p.readings != 5 && p.readings != 10 && p.readings != c.points.size()) continue;
    if (!p.mssd_mm.median) continue;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%zu readings %.2f mm (p90 %.2f)", line.empty() ? "" : ", ", p.readings,
                  *p.mssd_mm.median, p.mssd_mm.p90.value_or(0.0));
    line += buf;
  }
  if (!line.empty())
    std::printf("[evaluate] pose error (MSSD, symmetry-aware; median over posed trials): %s\n", line.c_str());
}

// SVA and the appearance-only baseline on the same trials, like the paper's figures.
void stage_evaluate(const DemoConfig& cfg, const Map& map, const DemoData& data) {
  std::vector<eval::Curve> curves;
  for (Method method : {Method::appearance, Method::sva}) {
    eval::EvalOptions o;
    o.trials = cfg.trials ? cfg.trials : 2 * data.test.scene.objects.size();
    o.max_readings = cfg.max_readings;
    o.seed = cfg.seed;
    o.threads = cfg.threads;
    o.recognizer.method = method;
    o.recognizer.backend = cfg.backend;
    o.map_name = "the demo map";
    o.data_name = data.test_file.string();
    const auto t0 = std::chrono::steady_clock::now();
    const eval::EvalResult r = eval::run_evaluation(map, data.test, o);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const eval::Curve c = eval::summarize(r);
    const auto eval_file = cfg.work / ("eval_" + std::string(eval::method_name(method)) + ".json");
    io::write_text_file(eval_file, eval::to_json(r, c));
    std::printf("[evaluate] %s: %zu trials x %zu readings in %.1f s (%s backend) -> %s\n", eval::method_name(method),
                o.trials, o.max_readings, secs, r.backend.c_str(), eval_file.c_str());
    std::fputs(eval::format_table(c).c_str(), stdout);
    if (method == Method::sva) {
      print_headline(c);
      print_speed(map, data, o, r);
    }
    curves.push_back(c);
  }
  const auto png = cfg.work / "eval.png";
  eval::write_figure(curves, png);
  std::printf("[evaluate] figure (accuracy and pose errors against readings): %s\n", png.c_str());
}

void stage_summary(const DemoData& data) {
  std::printf("[summary]  scene %s, %zu objects, seed %llu\n", data.train.scene.name.c_str(),
              data.train.scene.objects.size(), static_cast<unsigned long long>(data.train.seed));
  std::printf("  %-14s %14s %14s %12s\n", "object", "train conv.", "test conv.", "mean iters");
  std::map<std::uint32_t, std::array<std::size_t, 4>> per;  // train total, train conv, test total, test conv
  std::map<std::uint32_t, double> iters;
  for (const Dataset* d : {&data.train, &data.test})
    for (const auto& s : d->samples) {
      auto& p = per[s.object];
      std::size_t off = d == &data.train ? 0 : 2;
      p[off]++;
      p[off + 1] += s.reading.status == ControllerStatus::converged;
      iters[s.object] += s.reading.iterations;
    }
  for (std::uint32_t o = 0; o < data.train.scene.objects.size(); ++o) {
    auto p = per[o];
    char a[32], b[32];
    std::snprintf(a, sizeof a, "%zu/%zu", p[1], p[0]);
    std::snprintf(b, sizeof b, "%zu/%zu", p[3], p[2]);
    double n = static_cast<double>(p[0] + p[2]);
    std::printf("  %-14s %14s %14s %12.1f\n", data.train.scene.objects[o].name.c_str(), a, b,
                n > 0 ? iters[o] / n : 0.0);
  }
  std::printf("  datasets: %s, %s\n", data.train_file.c_str(), data.test_file.c_str());
}

}  // namespace

int cmd_demo(const std::vector<std::string>& argv) {
  Args a("sva demo",
         "The main job: simulate the default scene (cached in --work), draw previews, train the SVA map, evaluate\n"
         "SVA and the appearance-only baseline on random poses of the test readings, print accuracy, pose errors and\n"
         "time per update against readings, which device ran SVA and its time per update next to the CPU\n"
         "reference's on the same trials, and write the figure (DIR/eval.png).",
         argv);
  a.option("--work", "DIR", "work and cache directory (default ./sva-demo)")
      .option("--scene", "NAME|FILE", "scene (default paper3d)")
      .option("--seed", "S", "random seed (default 1)")
      .option("--train", "N", "training readings per object (default: the scene's)")
      .option("--test", "N", "test readings per object (default: the scene's)")
      .option("--threads", "N", "worker threads (default: SVA_THREADS or all cores)")
      .option("--trials", "N", "evaluation trials (default: 2 repetitions over the objects)")
      .option("--max-readings", "M", "readings per trial (default 20)")
      .option("--backend", "auto|cpu|vulkan", "vote backend of SVA (default auto: the GPU when one is usable)");
  if (!a.parse()) return 0;
  DemoConfig cfg;
  cfg.work = a.get_or("--work", "sva-demo");
  cfg.scene_name = a.get_or("--scene", "paper3d");
  cfg.seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, std::numeric_limits<long long>::max()));
  cfg.train = static_cast<int>(a.integer("--train", -1, 0, 10000000));
  cfg.test = static_cast<int>(a.integer("--test", -1, 0, 10000000));
  cfg.threads = static_cast<unsigned>(a.integer("--threads", 0, 1, 1024));
  cfg.trials = static_cast<std::size_t>(a.integer("--trials", 0, 1, 1000000));
  cfg.max_readings = static_cast<std::size_t>(a.integer("--max-readings", 20, 1, 100000));
  cfg.backend = parse_backend_kind(a.get_or("--backend", "auto"), "sva demo: --backend");
  Scene scene = load_scene(cfg.scene_name);
  for (const std::string& w : eval::symmetry_warnings(scene)) std::printf("[scene]    warning: %s\n", w.c_str());
  std::error_code ec;
  std::filesystem::create_directories(cfg.work, ec);
  if (ec) throw Error(cfg.work.string() + ": cannot create work directory: " + ec.message());
  const auto t0 = std::chrono::steady_clock::now();
  DemoData data = stage_simulate(cfg, scene);
  stage_preview(cfg, data);
  stage_summary(data);
  const Map map = stage_train(cfg, data);
  stage_evaluate(cfg, map, data);
  std::printf("[done]     %.0f s in all; outputs in %s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), cfg.work.c_str());
  return 0;
}

}  // namespace sva::cli
