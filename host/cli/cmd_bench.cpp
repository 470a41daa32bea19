// sva bench: speed of recognition on one machine, next to the accuracy it buys.
// Time per update at chosen reading counts, votes and session-updates per
// second, zero-mass votes and host and device memory, for the CPU reference and
// the Vulkan backend (one session, and a batch of sessions per update), and the
// bare fixed-point atomic scatter on the same device (the roofline of the vote
// scatter), with the ratios between them. The runs and the report are the tools'
// library's (sva/eval/speed_run.hpp); this file parses the options and prints.
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/speed_run.hpp>
#include <sva/io/text_file.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include <sva/io/json.hpp>
#include "args.hpp"

namespace sva::cli {

namespace {

using nlohmann::json;

std::vector<std::size_t> parse_checkpoints(const std::string& text) {
  std::vector<std::size_t> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    long v = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || v < 1 || v > 100000)
      throw Error("sva bench: --readings expects a list like 10,30,100, got \"" + text + "\"");
    out.push_back(static_cast<std::size_t>(v));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// --pose-prior MM[,DEG]: the position's sigma, and the rotation's when given.
bench::BenchPosePrior parse_pose_prior(const std::string& text) {
  const auto fail = [&] {
    return Error("sva bench: --pose-prior expects MM or MM,DEG (sigmas > 0, e.g. 5,10), got \"" + text + "\"");
  };
  bench::BenchPosePrior p;
  std::stringstream ss(text);
  std::string item;
  std::vector<double> v;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(x) || !(x > 0.0) || x > 1e6) throw fail();
    v.push_back(x);
  }
  if (v.empty() || v.size() > 2 || text.back() == ',') throw fail();
  p.position_sigma_mm = v[0];
  if (v.size() == 2) {
    if (v[1] > 180.0) throw fail();
    p.rotation_sigma_deg = v[1];
  }
  return p;
}

std::string run_name(const json& r) {
  return r["backend"].get<std::string>() + (r["sessions_per_submission"].get<std::size_t>() > 1 ? " batch" : "");
}

void print_table(const json& runs) {
  // growth ms: of host ms, growing the sessions' belief tables (Vulkan). upd. subm., est. subm.: an update's and an
  // estimate's device round trips; upd. alloc., est. alloc.: their device memory allocations (each a batch's divided
  // by its sessions; 0 on the CPU).
  std::printf("%-14s %-9s %9s %10s %12s %9s %14s %10s %12s %10s %9s %9s %9s %9s %10s %10s %11s %11s %10s\n", "run",
              "readings", "ms/update", "upd/s", "votes/update", "zero %", "votes/s", "accuracy", "trans. mm",
              "kernel ms", "fold ms", "host ms", "growth ms", "est. ms", "upd. subm.", "est. subm.", "upd. alloc.",
              "est. alloc.", "belief MB");
  for (const auto& r : runs)
    for (const auto& p : r["curve"]) {
      auto num = [&](const char* key) { return p[key].is_null() ? 0.0 : p[key].get<double>(); };
      const std::string trans =
          p["translation_error_mm"].is_null() ? "-" : std::to_string(num("translation_error_mm")).substr(0, 6);
      // belief MB: the median session's belief tables after the update (a live session's memory).
      std::printf(
          "%-14s %-9zu %9.2f %10.3g %12.0f %9.3g %14.3g %10.2f %12s %10.2f %9.2f %9.2f %9.2f %9.2f %10.2f %10.2f "
          "%11.2f %11.2f %10.2f\n",
          run_name(r).c_str(), p["readings"].get<std::size_t>(), num("update_ms"), num("session_updates_per_second"),
          num("votes_per_update"), 100.0 * num("votes_zero_fraction"), num("votes_per_second"), num("accuracy"),
          trans.c_str(), num("gpu_kernel_ms"), num("gpu_fold_ms"), num("backend_host_ms"),
          num("backend_belief_growth_ms"), num("estimate_ms"), num("update_device_submissions"),
          num("estimate_device_submissions"), num("update_device_allocations"), num("estimate_device_allocations"),
          num("belief_bytes_per_session") / 1e6);
    }
}

// Where a session's estimate went (BatchRecognizer::EstimateTiming, per session): reading the belief (stage 1, a
// device's reads included), the fine poses, the surface check, the posterior and the report.
void print_estimate_stages(const json& runs) {
  std::printf(
      "\nestimate per session by stage, ms (docs/architecture.md: 1 belief, 2 fits, 3 verify, 4-5 posterior):\n%-14s "
      "%-9s %9s %9s "
      "%9s %10s %9s\n",
      "run", "readings", "est. ms", "belief", "fits", "verify", "posterior");
  for (const auto& r : runs)
    for (const auto& p : r["curve"]) {
      auto num = [](const json& v) { return v.is_null() ? 0.0 : v.get<double>(); };
      const json& st = p["estimate_stage_ms"];
      std::printf("%-14s %-9zu %9.2f %9.2f %9.2f %10.2f %9.2f\n", run_name(r).c_str(), p["readings"].get<std::size_t>(),
                  num(p["estimate_ms"]), num(st["belief"]), num(st["fits"]), num(st["verify"]), num(st["posterior"]));
    }
}

// A figure of the JSON printed with `format`, or "n/a" where it is null (not counted, not measured).
std::string number_or_na(const json& v, const char* format = "%.0f") {
  if (v.is_null()) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v.get<double>());
  return buf;
}

// Where a device update's time went (speed_run.cpp's update_split_json), per submission of its sessions.
void print_update_split(const json& runs) {
  bool header = false;
  for (const auto& r : runs)
    for (const auto& p : r["curve"]) {
      const json& u = p["update_split_ms"];
      if (u.is_null()) continue;
      if (!header)
        std::printf(
            "\nan update's time by part, ms per submission (docs/evaluation.md, \"update_split_ms\"):\n%-14s %-9s "
            "%9s %15s %12s %10s %13s %11s\n",
            "run", "readings", "kernels", "between kernels", "wait past", "recording", "host outside", "of it growth");
      header = true;
      auto num = [](const json& v) { return number_or_na(v, "%.3f"); };
      std::printf("%-14s %-9zu %9s %15s %12s %10s %13s %11s\n", run_name(r).c_str(), p["readings"].get<std::size_t>(),
                  num(u["kernels"]).c_str(), num(u["device_between_kernels"]).c_str(),
                  num(u["wait_past_device"]).c_str(), num(u["recording"]).c_str(),
                  num(u["host_outside_submissions"]).c_str(), num(u["belief_growth"]).c_str());
    }
}

// The device's time by kernel at one curve point, for one pipeline or, with name "", summed over them all (ms,
// dispatches); null where the point did not time its kernels.
json kernel_cell(const json& point, const std::string& name) {
  const json& k = point["kernel_ms_by_pipeline"];
  if (k.is_null()) return nullptr;
  if (!name.empty()) return k.contains(name) ? k[name] : json{{"ms", 0.0}, {"dispatches", 0.0}};
  double ms = 0.0, dispatches = 0.0;
  for (const auto& [n, v] : k.items()) {
    ms += v["ms"].get<double>();
    dispatches += v["dispatches"].get<double>();
  }
  return {{"ms", ms}, {"dispatches", dispatches}};
}

// A run's pipelines with timed kernels, the heaviest first (at the largest reading count that ran each).
std::vector<std::string> pipelines_by_time(const json& curve) {
  std::map<std::string, double> last_ms;
  for (const auto& p : curve)  // by reading count, ascending
    if (p["kernel_ms_by_pipeline"].is_object())
      for (const auto& [name, v] : p["kernel_ms_by_pipeline"].items()) last_ms[name] = v["ms"].get<double>();
  std::vector<std::string> names;
  for (const auto& [name, ms] : last_ms) names.push_back(name);
  std::stable_sort(names.begin(), names.end(),
                   [&](const std::string& a, const std::string& b) { return last_ms[a] > last_ms[b]; });
  return names;
}

// The header of print_kernels_by_pipeline: a column pair per reading count of `curve`, which it returns.
std::vector<std::size_t> print_kernels_header(const json& curve) {
  std::printf(
      "\nthe device's time by kernel, ms and dispatches per submission, the mean over its updates "
      "(docs/evaluation.md, \"kernel_ms_by_pipeline\"):\n%-14s %-29s",
      "", "");
  std::vector<std::size_t> readings;
  for (const auto& p : curve) {
    readings.push_back(p["readings"].get<std::size_t>());
    std::printf(" %19s", (std::to_string(readings.back()) + " readings").c_str());
  }
  std::printf("\n%-14s %-29s", "run", "pipeline");
  for (std::size_t i = 0; i < readings.size(); ++i) std::printf(" %10s %8s", "ms", "disp.");
  std::printf("\n");
  return readings;
}

// Which kernels a device update's time is (speed_run.cpp's kernel_by_pipeline_json): a row per run and pipeline (or
// pass: "belief_reduce:table_histogram" is the longest name, 29 characters), the heaviest first, then all of them
// together; a column pair per reading count.
void print_kernels_by_pipeline(const json& runs) {
  std::vector<std::size_t> readings;  // the columns: the first timed run's reading counts
  for (const auto& r : runs) {
    const json& curve = r["curve"];
    const std::vector<std::string> names = pipelines_by_time(curve);
    if (names.empty()) continue;
    if (readings.empty()) readings = print_kernels_header(curve);
    for (std::size_t row = 0; row <= names.size(); ++row) {
      const std::string name = row < names.size() ? names[row] : "";
      std::printf("%-14s %-29s", run_name(r).c_str(), name.empty() ? "(all kernels)" : name.c_str());
      for (std::size_t want : readings) {
        json cell;
        for (const auto& p : curve)
          if (p["readings"].get<std::size_t>() == want) cell = kernel_cell(p, name);
        std::printf(" %10s %8s", number_or_na(cell.is_null() ? cell : cell["ms"], "%.3f").c_str(),
                    number_or_na(cell.is_null() ? cell : cell["dispatches"], "%.1f").c_str());
      }
      std::printf("\n");
    }
  }
}

// The work per update as the backend counts it (the CPU reference: all but device atomics; Vulkan: all but the
// belief probes), and the bytes it implies.
void print_work(const json& runs) {
  bool header = false;
  for (const auto& r : runs)
    for (const auto& p : r["curve"]) {
      const json& w = p["work_per_update"];
      if (w.is_null()) continue;
      if (!header)
        std::printf(
            "\nwork per update (docs/recognition.md, \"Work counted\"):\n%-14s %-9s %7s %12s %10s %11s %13s %11s "
            "%10s %13s %9s %11s %9s\n",
            "run", "readings", "pairs", "map entries", "matches", "votes", "table probes", "atomics", "bins",
            "belief probes", "map MB", "tables MB", "fold MB");
      header = true;
      const json& b = w["bytes"];
      std::printf("%-14s %-9zu %7.0f %12.0f %10.0f %11.0f %13.0f %11s %10.0f %13s %9.2f %11.2f %9.2f\n",
                  run_name(r).c_str(), p["readings"].get<std::size_t>(), w["pairs"].get<double>(),
                  w["map_entries"].get<double>(), w["matches"].get<double>(), w["votes"].get<double>(),
                  w["vote_table_probes"].get<double>(), number_or_na(w["vote_table_atomics"]).c_str(),
                  w["bins"].get<double>(), number_or_na(w["belief_probes"]).c_str(), b["map"].get<double>() / 1e6,
                  b["vote_tables"].get<double>() / 1e6, b["fold"].get<double>() / 1e6);
    }
}

// The modelled GPU time per session-update of an H100 beside the measured one (docs/vulkan-backend.md, "Work and an
// estimate for an H100"): an estimate from the counted work, which the first run on the device checks.
void print_model(const json& runs) {
  bool header = false;
  for (const auto& r : runs)
    for (const auto& p : r["curve"]) {
      const json& m = p["gpu_model"];
      if (m.is_null()) continue;
      if (!header)
        std::printf(
            "\nmodel of the GPU time per session-update on an %s (%s; an estimate, not a measurement: "
            "atomics and bytes only, a floor; an H200 took 6-110x longer, docs/vulkan-backend.md):\n%-14s %-9s %12s "
            "%12s %16s %18s\n",
            m["device"].get<std::string>().c_str(), m["figures"].get<std::string>().c_str(), "run", "readings",
            "atomics", "bytes MB", "model ms", "measured ms/update");
      header = true;
      const bool measured = r["backend"] == "vulkan" && !p["update_ms"].is_null();
      std::printf("%-14s %-9zu %11.0f%s %12.2f %7.3f - %6.3f %18s\n", run_name(r).c_str(),
                  p["readings"].get<std::size_t>(), m["atomics"].get<double>(),
                  m["atomics_counted"].get<bool>() ? " " : "*", m["bytes"].get<double>() / 1e6,
                  m["low_ms"].get<double>(), m["high_ms"].get<double>(),
                  measured ? std::to_string(p["update_ms"].get<double>()).substr(0, 8).c_str() : "-");
    }
  if (header)
    std::printf(
        "(* atomics modelled from the CPU's counts: two per vote, no subgroup pre-aggregation; the measured "
        "time is this machine's device, which may not be the model's)\n");
}

std::string mib(const json& bytes, const char* format = "%.1f MiB") {
  if (bytes.is_null()) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, bytes.get<double>() / (1024.0 * 1024.0));
  return buf;
}

// The highest RSS during the run and its rise over the RSS at the run's start.
std::string peak_during(const json& m) {
  if (m["peak_rss_during_bytes"].is_null()) return "peak during the run n/a (VmHWM could not be reset)";
  const double peak = m["peak_rss_during_bytes"].get<double>();
  return "peak during the run " + mib(peak) + " (" + mib(peak - m["rss_before_bytes"].get<double>(), "%+.1f MiB") + ")";
}

// The estimate's host stages the run asked for (--estimate, --refine, --surface-check).
std::string estimate_kind(const json& r) {
  std::string kind = r.value("estimate", "full") == "light"
                         ? std::string("light estimates (no host fits)")
                         : std::string("refine ") + (r["refine_pose"].get<bool>() ? "on" : "off") + ", surface check " +
                               (r["surface_check"].get<bool>() ? "on" : "off");
  const json& p = r["pose_prior"];
  if (p.is_null()) return kind;
  char text[96];
  std::snprintf(text, sizeof text, ", pose prior %.3g mm", p["position_sigma_mm"].get<double>());
  kind += text;
  if (!p["rotation_sigma_deg"].is_null()) {
    std::snprintf(text, sizeof text, " and %.3g deg", p["rotation_sigma_deg"].get<double>());
    kind += text;
  }
  return kind;
}

// What the run left out of the paper's votes (--max-pairs, --likelihood-cutoff), and whether its tables were warm
// (--warm), or nothing.
std::string vote_kind(const json& r) {
  std::string kind;
  char text[64];
  if (r["max_pairs_per_update"].get<int>() > 0) {
    std::snprintf(text, sizeof text, ", max pairs %d", r["max_pairs_per_update"].get<int>());
    kind += text;
  }
  if (r["likelihood_cutoff"].get<double>() > 0.0) {
    std::snprintf(text, sizeof text, ", likelihood cut-off %.3g", r["likelihood_cutoff"].get<double>());
    kind += text;
  }
  if (r["warm"].get<bool>()) kind += ", warm tables";
  return kind;
}

// Per run: throughput and zero-mass votes over all its updates, then memory.
void print_run_summaries(const json& runs) {
  for (const auto& r : runs) {
    const json& m = r["memory"];
    std::printf(
        "%s (%zu per submission, top %zu per estimate, %s%s): %.3g session-updates/s (%.3g with their estimates), "
        "%.3g votes/s; votes of mass 0: %llu of %llu (%.3g%%)\n",
        run_name(r).c_str(), r["sessions_per_submission"].get<std::size_t>(), r["top_k"].get<std::size_t>(),
        estimate_kind(r).c_str(), vote_kind(r).c_str(), r["session_updates_per_second"].get<double>(),
        r["session_updates_with_estimates_per_second"].get<double>(), r["votes_per_second"].get<double>(),
        r["votes_zero"].get<unsigned long long>(), r["votes"].get<unsigned long long>(),
        100.0 * r["votes_zero_fraction"].get<double>());
    const bool cpu = r["backend"] == "cpu";
    std::printf(
        "  host: peak RSS %s (process so far), RSS %s -> %s (%s), %s; device: %s (map %s; allocations hold %s)\n",
        mib(m["peak_rss_bytes"]).c_str(), mib(m["rss_before_bytes"]).c_str(), mib(m["rss_after_bytes"]).c_str(),
        mib(m["rss_increase_bytes"], "%+.1f MiB").c_str(), peak_during(m).c_str(),
        cpu ? "none" : mib(m["device_bytes"]).c_str(), cpu ? "none" : mib(m["map_device_bytes"]).c_str(),
        cpu ? "none" : mib(m["device_held_bytes"]).c_str());
  }
}

void print_roofline(const json& out) {
  if (!out.contains("roofline")) return;
  const json& roof = out["roofline"];
  std::printf("roofline (bare atomic scatter on %s): %.3g votes/s\n", roof["device"].get<std::string>().c_str(),
              roof["votes_per_second"].get<double>());
  if (roof.contains("hash_votes_per_second"))
    std::printf("bare hash scatter (the vote kernel's table, no vote math): %.3g votes/s\n",
                roof["hash_votes_per_second"].get<double>());
  if (roof.contains("vote_math") && !roof["vote_math"]["exact_samples_per_second"].is_null()) {
    // The math alone, exact (the engine's) and with the device's own division and square root: what bounds the
    // vote kernel, beside the table's bare scatter.
    const json& m = roof["vote_math"];
    std::printf(
        "vote math alone (no map, owner rule or table): %.3g samples/s exact%s, %.3g with the device's own "
        "division and square root\n",
        m["exact_samples_per_second"].get<double>(),
        m["exact_agrees_with_cpu"].get<bool>() ? " (the CPU's bits)" : " (NOT the CPU's bits)",
        m["device_division_samples_per_second"].get<double>());
  }
  if (roof.contains("host_reads")) {
    // What the host pays per load of a kernel's result: in place (on a discrete GPU its BAR, uncached) and from the
    // host-cached copy that the engine reads there instead (gpu::add_mirror_read).
    const json& h = roof["host_reads"];
    std::printf(
        "host reads of a kernel's result: %.3g ns per 8-byte load in place (mapped, %s), %.3g ns from a "
        "host-cached copy%s\n",
        h["mapped_ns_per_load"].get<double>(),
        h["mapped_device_local"].get<bool>() ? "the device's memory" : "host memory",
        h["readback_ns_per_load"].get<double>(), h["sums_agree"].get<bool>() ? "" : " (WRONG WORDS READ)");
  }
  for (const auto& r : out["runs"]) {
    if (r.contains("fraction_of_roofline"))
      std::printf("%s (%zu per submission): %.3g votes/s = %.1f%% of the roofline\n",
                  r["device"].get<std::string>().c_str(), r["sessions_per_submission"].get<std::size_t>(),
                  r["votes_per_second"].get<double>(), 100.0 * r["fraction_of_roofline"].get<double>());
  }
}

bench::BenchPlan parse_plan(const Args& a) {
  bench::BenchPlan plan;
  // A choice of runs, not of a backend: each run names its backend (no auto, which would hide which one ran).
  const std::string which = a.get_or("--backend", "both");
  if (which != "cpu" && which != "vulkan" && which != "both")
    throw Error("sva bench: --backend must be cpu, vulkan or both, got \"" + which + "\"");
  if (which != "vulkan") plan.backends.push_back(BackendKind::cpu);
  if (which != "cpu") plan.backends.push_back(BackendKind::vulkan);
  plan.checkpoints = parse_checkpoints(a.get_or("--readings", "10,30,100"));
  plan.trials = static_cast<std::size_t>(a.integer("--trials", 3, 1, 100000));
  plan.batch = static_cast<std::size_t>(a.integer("--batch", 64, 0, 4096));
  plan.seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, INT64_MAX));
  plan.roofline_votes = static_cast<std::size_t>(a.integer("--roofline-votes", 1 << 22, 1024, 1 << 26));
  plan.device = a.get_or("--device", "");
  plan.refine_pose = a.on_off("--refine", true);
  plan.surface_check = a.on_off("--surface-check", true);
  plan.estimate = parse_estimate_depth(a.get_or("--estimate", "full"), "sva bench: --estimate");
  plan.max_pairs_per_update = static_cast<int>(a.integer("--max-pairs", 0, 0, 1 << 20));
  plan.likelihood_cutoff = static_cast<float>(a.number("--likelihood-cutoff", 0.0, 0.0, 128.0));
  plan.belief_budget_bins = static_cast<std::size_t>(
      a.integer("--belief-budget", static_cast<long long>(plan.belief_budget_bins), 0, 1ll << 40));
  plan.top_k = static_cast<std::size_t>(a.integer("--top-k", 1, 1, 1000));
  if (auto p = a.get("--pose-prior")) plan.pose_prior = parse_pose_prior(*p);
  plan.warm = a.on_off("--warm", false);
  return plan;
}

}  // namespace

int cmd_bench(const std::vector<std::string>& argv) {
  Args a("sva bench",
         "Measure recognition speed on this machine next to the accuracy it buys: time per update, votes and\n"
         "session-updates per second, votes of mass 0, peak and per-run host memory (RSS) and device memory, for\n"
         "the CPU reference and the Vulkan backend (one session, and a batch of sessions per update), the bare\n"
         "atomic-scatter roofline of the device, and the ratios.",
         argv);
  a.option("--map", "MAP", "map file (sva train)")
      .option("--data", "TEST", "test dataset (sva simulate)")
      .option("--json", "OUT.json", "write the figures as JSON")
      .option("--backend", "cpu|vulkan|both", "backends to measure (default both)")
      .option("--readings", "LIST", "reading counts to report, e.g. 10,30,100 (default)")
      .option("--trials", "N", "trials per run (default 3; a batched run has at least --batch)")
      .option("--batch", "N", "sessions per update in each backend's batched run (default 64; 0 = none)")
      .option("--seed", "S", "trial seed (default 1)")
      .option("--refine", "on|off", "fine pose after every update, timed in estimate_ms (default on)")
      .option("--surface-check", "on|off",
              "verify the leading objects against their surfaces after every update (default on; off, with --refine "
              "off: the host fits the best object alone, where the map's calibration says \"none of these\")")
      .option("--estimate", "full|light",
              "the estimate after every update: full (default) or light, the belief's answer without the host's fits "
              "(docs/recognition.md, \"Light and full estimates\")")
      .option("--max-pairs", "N",
              "bounded cost per update: pairs per update, both orders counted (58: the new reading with the 29 most "
              "recent ones; default 0, every earlier reading: the exact filter; docs/recognition.md)")
      .option("--likelihood-cutoff", "L",
              "matches whose likelihood (Eq 15, summed over the keys they share) is below L cast no vote (default 0: "
              "every match votes, the paper's method; the map's calibration was fitted at 0; docs/recognition.md)")
      .option("--belief-budget", "BINS",
              "touched pose bins per session before hopeless ones are forgotten (default 4194304; 0 = no bound; "
              "docs/recognition.md, \"Bounded memory\")")
      .option("--top-k", "K",
              "hypotheses per estimate after every update (default 1; sva recognize's default is 3, which takes the "
              "estimate's modes)")
      .option("--pose-prior", "MM[,DEG]",
              "give every session a camera's pose prior: every object at the trial's true pose, with these sigmas "
              "of position and rotation (default none; sva/prior.hpp)")
      .option("--warm", "on|off",
              "first step one untimed group of each run's sessions to the last reading count, so that the timed "
              "sessions' tables start at the size they reach, as in a long study's later groups (default off: a "
              "batched run whose trials fill one group grows every session's tables)")
      .option("--device", "NAME|INDEX", "Vulkan device (default: prefer a discrete GPU; env SVA_VK_DEVICE)")
      .option("--roofline-votes", "N", "votes in the bare-scatter measurement (default 4194304)");
  if (!a.parse()) return 0;
  const std::string map_file = a.required("--map"), data_file = a.required("--data");
  const bench::BenchPlan plan = parse_plan(a);
  const Map map = Map::load(map_file);
  const Dataset test = load_dataset(data_file);
  eval::check_compatible(map, test, map_file, data_file);

  json out = bench::run_bench(map, test, plan);
  out["map"] = map_file;
  out["data"] = data_file;

  print_table(out["runs"]);
  print_estimate_stages(out["runs"]);
  print_update_split(out["runs"]);
  print_kernels_by_pipeline(out["runs"]);
  print_work(out["runs"]);
  print_model(out["runs"]);
  print_run_summaries(out["runs"]);
  print_roofline(out);
  std::printf("peak RSS of the process: %s\n", mib(out["peak_rss_bytes"]).c_str());
  if (auto path = a.get("--json")) io::write_text_file(*path, io::dump_json(out, 2) + "\n");
  return 0;
}

}  // namespace sva::cli
