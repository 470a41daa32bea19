// sva bench: speed of recognition on one machine, next to the accuracy it buys.
// Time per update at chosen reading counts and votes per second, for the CPU
// reference and the Vulkan backend (one session, and a batch of sessions in
// one submission), and the bare fixed-point atomic scatter on the same device
// (the roofline of the vote scatter), with the ratios between them.
#include <sva/batch_recognizer.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "args.hpp"
#include "eval/evaluation.hpp"
#include "eval/metrics.hpp"
#include "eval/trials.hpp"
#include "io/text_file.hpp"
#include "recognition/lockstep.hpp"
#include "roofline/roofline.hpp"
#include "util/interrupt.hpp"
#include "util/parallel.hpp"
#include "util/progress.hpp"

namespace sva::cli {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct Checkpoint {
  std::vector<double> update_ms;   // per trial (batched: per session-update)
  std::uint64_t votes = 0;
  double seconds = 0.0;
  std::size_t correct = 0, trials = 0;
  std::vector<double> translation_mm;
  std::vector<double> kernel_ms, backend_host_ms, fold_ms;
  std::vector<double> estimate_ms;  // per session: object, refined pose and top-1 after the update
};

std::vector<std::size_t> parse_checkpoints(const std::string& text) {
  std::vector<std::size_t> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    long v = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || v < 1 || v > 100000) throw Error("sva bench: --readings expects a list like 10,30,100, got \"" + text + "\"");
    out.push_back(static_cast<std::size_t>(v));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void record_checkpoint(Checkpoint& c, const BatchRecognizer& rec, const std::vector<eval::Trial>& tr,
                       const std::vector<Estimate>& est, std::uint64_t votes, double secs, double estimate_secs) {
  const auto n = static_cast<double>(est.size());
  c.update_ms.push_back(1e3 * secs / n);
  c.estimate_ms.push_back(1e3 * estimate_secs / n);
  c.votes += votes;
  c.seconds += secs;
  const auto t = rec.last_backend_timing();
  c.kernel_ms.push_back(t.kernel_ms);
  c.backend_host_ms.push_back(t.host_ms);
  c.fold_ms.push_back(t.fold_ms);
  for (std::size_t i = 0; i < est.size(); ++i) {
    ++c.trials;
    if (est[i].object != tr[i].object) continue;
    ++c.correct;
    if (est[i].pose_valid) c.translation_mm.push_back(glm::length(est[i].pose.T - tr[i].pose.T));
  }
}

// Runs `sessions` trials in lock step (one update carries one reading of each)
// and records the checkpoints. sessions = 1 measures the single-session latency.
json run_backend(const Map& map, const Dataset& test, BackendKind backend, std::size_t trials, std::size_t sessions,
                 const std::vector<std::size_t>& checkpoints, std::uint64_t seed, const std::string& label,
                 const std::string& device_choice) {
  const std::size_t max_readings = checkpoints.back();
  eval::TrialGenerator gen(test, map.pose_space(), seed, max_readings);
  RecognizerOptions ro;
  ro.backend = backend;
  ro.vulkan_device = device_choice;
  std::map<std::size_t, Checkpoint> cp;
  std::uint64_t all_votes = 0;
  double all_seconds = 0.0;
  util::Progress progress(label, trials * max_readings);
  BatchRecognizer rec(map, map.pose_space(), std::min(sessions, trials), ro);
  const std::string device = rec.backend_description();
  std::vector<eval::Trial> tr;
  LockstepHooks hooks;
  hooks.progress = &progress;
  hooks.group = [&](std::size_t first, std::size_t count) {
    tr.clear();
    std::vector<std::span<const Reading>> readings;
    for (std::size_t i = 0; i < count; ++i) tr.push_back(gen.make(first + i));
    for (const auto& t : tr) readings.emplace_back(t.readings);
    return readings;
  };
  hooks.on_step = [&](const LockstepStep& s) {
    const std::size_t step = s.step + 1;
    const double secs = s.update_ms / 1e3;
    std::uint64_t votes = 0;
    std::vector<Estimate> est;
    const auto t1 = Clock::now();
    for (std::size_t i : s.sessions) {
      est.push_back(rec.estimate(i, 1));
      votes += est.back().votes;
    }
    const double estimate_secs = std::chrono::duration<double>(Clock::now() - t1).count();
    all_votes += votes;
    all_seconds += secs;
    if (std::binary_search(checkpoints.begin(), checkpoints.end(), step))
      record_checkpoint(cp[step], rec, tr, est, votes, secs, estimate_secs);
  };
  run_lockstep(rec, trials, hooks);
  progress.finish();
  json j = {{"backend", eval::backend_name(backend)}, {"device", device}, {"sessions_per_submission", sessions},
            {"trials", trials}, {"votes_per_second", all_seconds > 0 ? static_cast<double>(all_votes) / all_seconds : 0.0}};
  json points = json::array();
  for (auto& [step, c] : cp) {
    auto med = [](const std::vector<double>& v) -> json {
      auto m = eval::median(v);
      return m ? json(*m) : json(nullptr);
    };
    points.push_back({{"readings", step},
                      {"update_ms", med(c.update_ms)},
                      {"votes_per_update", c.trials ? static_cast<double>(c.votes) / static_cast<double>(c.trials) : 0.0},
                      {"votes_per_second", c.seconds > 0 ? static_cast<double>(c.votes) / c.seconds : 0.0},
                      {"gpu_kernel_ms", med(c.kernel_ms)},
                      {"backend_host_ms", med(c.backend_host_ms)},
                      {"gpu_fold_ms", med(c.fold_ms)},
                      {"estimate_ms", med(c.estimate_ms)},
                      {"accuracy", c.trials ? static_cast<double>(c.correct) / static_cast<double>(c.trials) : 0.0},
                      {"translation_error_mm", med(c.translation_mm)}});
  }
  j["curve"] = points;
  return j;
}

// The bare-scatter roofline of the device, as the JSON report gives it.
json roofline(std::size_t votes, std::size_t bins, const std::string& device) {
  const bench::Roofline r = bench::measure_roofline(votes, bins, device);
  json j = {{"device", r.device}, {"votes", r.votes}, {"bins", r.bins}, {"kernel_ms", r.kernel_ms},
            {"votes_per_second", r.votes_per_second}};
  if (r.hash_kernel_ms > 0) {
    j["hash_kernel_ms"] = r.hash_kernel_ms;
    j["hash_votes_per_second"] = r.hash_votes_per_second;
  }
  return j;
}

}  // namespace

int cmd_bench(const std::vector<std::string>& argv) {
  Args a("sva bench",
         "Measure recognition speed on this machine next to the accuracy it buys: time per update and votes per\n"
         "second for the CPU reference and the Vulkan backend (one session, and a batch of sessions per\n"
         "submission), the bare atomic-scatter roofline of the device, and the ratios.",
         argv);
  a.option("--map", "MAP", "map file (sva train)")
      .option("--data", "TEST", "test dataset (sva simulate)")
      .option("--json", "OUT.json", "write the figures as JSON")
      .option("--backend", "cpu|vulkan|both", "backends to measure (default both)")
      .option("--readings", "LIST", "reading counts to report, e.g. 10,30,100 (default)")
      .option("--trials", "N", "trials per backend (default 3)")
      .option("--batch", "N", "sessions per submission for the batched Vulkan run (default 16; 0 = skip)")
      .option("--seed", "S", "trial seed (default 1)")
      .option("--device", "NAME|INDEX", "Vulkan device (default: prefer a discrete GPU; env SVA_VK_DEVICE)")
      .option("--roofline-votes", "N", "votes in the bare-scatter measurement (default 4194304)");
  if (!a.parse()) return 0;
  const std::string map_file = a.required("--map"), data_file = a.required("--data");
  // A choice of runs, not of a backend: each run names its backend (no auto, which would hide which one ran).
  const std::string which = a.get_or("--backend", "both");
  if (which != "cpu" && which != "vulkan" && which != "both")
    throw Error("sva bench: --backend must be cpu, vulkan or both, got \"" + which + "\"");
  const auto checkpoints = parse_checkpoints(a.get_or("--readings", "10,30,100"));
  const auto trials = static_cast<std::size_t>(a.integer("--trials", 3, 1, 100000));
  const auto batch = static_cast<std::size_t>(a.integer("--batch", 16, 0, 4096));
  const auto seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, INT64_MAX));
  const auto roof_votes = static_cast<std::size_t>(a.integer("--roofline-votes", 1 << 22, 1024, 1 << 26));
  const std::string dev = a.get_or("--device", "");
  const Map map = Map::load(map_file);
  const Dataset test = load_dataset(data_file);
  eval::check_compatible(map, test, map_file, data_file);

  json out = {{"map", map_file}, {"data", data_file}, {"scene", map.scene_name()}, {"map_entries", map.entries()},
              {"threads", util::default_threads()}};
  json runs = json::array();
  if (which != "vulkan") runs.push_back(run_backend(map, test, BackendKind::cpu, trials, 1, checkpoints, seed, "cpu", dev));
  if (which != "cpu") {
    runs.push_back(run_backend(map, test, BackendKind::vulkan, trials, 1, checkpoints, seed, "vulkan", dev));
    if (batch > 1)
      runs.push_back(run_backend(map, test, BackendKind::vulkan, std::max(trials, batch), batch, checkpoints, seed, "vulkan batch", dev));
    out["roofline"] = roofline(roof_votes, 1 << 20, dev);
  }
  out["runs"] = runs;

  // Ratios against the CPU reference (per update) and the roofline (votes/s).
  std::printf("%-14s %-9s %9s %12s %14s %10s %12s %10s %9s %9s %9s\n", "run", "readings", "ms/update", "votes/update", "votes/s",
              "accuracy", "trans. mm", "kernel ms", "fold ms", "host ms", "est. ms");
  const json* cpu = nullptr;
  for (const auto& r : runs)
    if (r["backend"] == "cpu") cpu = &r;
  for (auto& r : out["runs"]) {
    const std::string name = std::string(r["backend"]) + (r["sessions_per_submission"].get<std::size_t>() > 1 ? " batch" : "");
    for (std::size_t i = 0; i < r["curve"].size(); ++i) {
      auto& p = r["curve"][i];
      const double ms = p["update_ms"].is_null() ? 0.0 : p["update_ms"].get<double>();
      if (cpu && r["backend"] != "cpu" && i < (*cpu)["curve"].size() && ms > 0 && !(*cpu)["curve"][i]["update_ms"].is_null())
        p["speedup_vs_cpu"] = (*cpu)["curve"][i]["update_ms"].get<double>() / ms;
      auto num = [&](const char* key) { return p[key].is_null() ? 0.0 : p[key].get<double>(); };
      std::printf("%-14s %-9zu %9.2f %12.0f %14.3g %10.2f %12s %10.2f %9.2f %9.2f %9.2f\n", name.c_str(), p["readings"].get<std::size_t>(), ms,
                  p["votes_per_update"].get<double>(), p["votes_per_second"].get<double>(), p["accuracy"].get<double>(),
                  p["translation_error_mm"].is_null() ? "-" : std::to_string(p["translation_error_mm"].get<double>()).substr(0, 6).c_str(),
                  num("gpu_kernel_ms"), num("gpu_fold_ms"), num("backend_host_ms"), num("estimate_ms"));
    }
    if (out.contains("roofline") && r["backend"] == "vulkan")
      r["fraction_of_roofline"] = r["votes_per_second"].get<double>() / out["roofline"]["votes_per_second"].get<double>();
  }
  if (out.contains("roofline")) {
    std::printf("roofline (bare atomic scatter on %s): %.3g votes/s\n", out["roofline"]["device"].get<std::string>().c_str(),
                out["roofline"]["votes_per_second"].get<double>());
    if (out["roofline"].contains("hash_votes_per_second"))
      std::printf("bare hash scatter (the vote kernel's table, no vote math): %.3g votes/s\n",
                  out["roofline"]["hash_votes_per_second"].get<double>());
  }
  for (const auto& r : out["runs"]) {
    if (r.contains("fraction_of_roofline"))
      std::printf("%s (%zu per submission): %.3g votes/s = %.1f%% of the roofline\n", r["device"].get<std::string>().c_str(),
                  r["sessions_per_submission"].get<std::size_t>(), r["votes_per_second"].get<double>(),
                  100.0 * r["fraction_of_roofline"].get<double>());
  }
  if (auto path = a.get("--json")) io::write_text_file(*path, out.dump(2) + "\n");
  return 0;
}

}  // namespace sva::cli
