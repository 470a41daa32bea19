// A batch of sessions on the CPU reference, as a batch study or `sva bench --batch` runs it: every session gets a
// reading, then every session an estimate, step after step (bench/speed/batch_speed.sh). Prints the session-updates
// per second on the workers (an update and an estimate each), the process's CPU time, and a digest of the last
// estimates, which must not change with the thread count. With span=1 the same batch runs again under a span probe
// (sva/base/parallel.hpp), each step's loops split for `threads` but run in turn on one core: its work and critical
// path, and so a model of the batch on `threads` cores of this machine's kind (docs/recognition.md, "Batches on many
// cores"): the model for 16 threads against the model for 2 is issue 52's batch scaling.
//   batch_speed MAP TEST [sessions=64] [readings=10] [threads=0: all] [top_k=1] [depth=full|light] [span=0]
// Session t touches object t % objects at a random pose, as `sva bench`'s trials do (seed 1).
#include <sva/base/parallel.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "sessions.hpp"
#include "cpu_time.hpp"
#include "whole_number_arg.hpp"

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::size_t arg(int argc, char** argv, int i, std::size_t fallback, std::size_t lo, std::size_t hi) {
  return sva::bench::whole_number_arg("batch_speed", argc, argv, i, fallback, lo, hi);
}

struct Batch {
  std::vector<std::size_t> ids;
  std::vector<sva::bench::BenchSession> sessions;
  std::vector<std::vector<sva::Reading>> steps;  // [reading][session]
  std::size_t top_k = 1;
  sva::EstimateDepth depth = sva::EstimateDepth::full;
};

// Where one run of the batch spent its time, summed over its steps (ms), and what it answered last.
struct Run {
  double update_ms = 0.0, estimate_ms = 0.0, cpu_s = 0.0;
  // Under the probe: each call's work, span and list schedule on the threads (SpanProbe::scheduled_ms).
  struct Model {
    double work = 0.0, span = 0.0, scheduled = 0.0;
  } update, estimate;
  std::uint64_t digest = sva::bench::kDigestStart;
  std::vector<sva::Estimate> last;  // each session's after its last reading
};

// One step's call, timed on the workers, or under a span probe (its work, span and schedule added to *model).
template <class F>
double timed(F&& call, bool probed, Run::Model* model) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!probed) {
    call();
    return ms_since(t0);
  }
  const sva::util::SpanProbe probe;
  call();
  model->work += probe.work_ms(), model->span += probe.span_ms();
  model->scheduled += probe.scheduled_ms();
  return ms_since(t0);
}

Run run_batch(const sva::Map& map, const sva::RecognizerOptions& options, const Batch& b, bool probed) {
  sva::BatchRecognizer batch(map, map.pose_space(), b.ids.size(), options);
  Run r;
  const double c0 = sva::bench::process_cpu_seconds();
  for (const std::vector<sva::Reading>& step : b.steps) {
    r.update_ms += timed([&] { batch.add_readings(b.ids, step); }, probed, &r.update);
    r.estimate_ms += timed([&] { r.last = batch.estimates(b.ids, b.top_k, b.depth); }, probed, &r.estimate);
  }
  r.cpu_s = sva::bench::process_cpu_seconds() - c0;
  for (const sva::Estimate& e : r.last) r.digest = sva::bench::digest(r.digest, e);
  return r;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 3 || std::strcmp(argv[1], "--help") == 0) {
    std::fprintf(stderr,
                 "usage: batch_speed MAP TEST [sessions=64] [readings=10] [threads=0] [top_k=1] [depth=full|light] "
                 "[span=0]\n");
    return argc < 3 ? 2 : 0;
  }
  const std::size_t sessions = arg(argc, argv, 3, 64, 1, 4096);
  const std::size_t readings = arg(argc, argv, 4, 10, 1, 100000);
  sva::RecognizerOptions options;
  options.backend = sva::BackendKind::cpu;
  options.threads = static_cast<unsigned>(arg(argc, argv, 5, 0, 0, 1024));
  Batch b;
  b.top_k = arg(argc, argv, 6, 1, 0, 100);
  if (argc > 7) b.depth = sva::parse_estimate_depth(argv[7], "batch_speed: depth");
  const bool span_model = arg(argc, argv, 8, 0, 0, 1) != 0;
  const sva::Map map = sva::Map::load(argv[1]);
  const sva::Dataset test = sva::load_dataset(argv[2]);
  const auto by_object = sva::bench::readings_by_object(map, test);
  b.steps.assign(readings, {});
  for (std::size_t t = 0; t < sessions; ++t) {
    b.ids.push_back(t);
    b.sessions.push_back(sva::bench::make_session(by_object, map.pose_space(), t, readings, argv[2]));
    for (std::size_t i = 0; i < readings; ++i) b.steps[i].push_back(b.sessions.back().readings[i]);
  }
  const unsigned threads = options.threads ? options.threads : sva::util::default_threads();
  const double updates = static_cast<double>(sessions * readings);
  const Run w = run_batch(map, options, b, false);
  const double wall_s = 1e-3 * (w.update_ms + w.estimate_ms);
  // What the speed buys: the objects right after the last reading, and their median translation error.
  std::vector<double> errors;
  for (std::size_t t = 0; t < sessions; ++t)
    if (w.last[t].object == b.sessions[t].object)
      errors.push_back(glm::length(w.last[t].pose.T - b.sessions[t].truth.T));
  std::sort(errors.begin(), errors.end());
  std::printf(
      "%zu sessions x %zu readings, top %zu, %s, %u thread(s): %.1f session-updates/s (update %.2f + estimate %.2f ms "
      "a step); CPU %.2f s; %zu/%zu objects right, median translation error %.2f mm; digest %016llx\n",
      sessions, readings, b.top_k, sva::estimate_depth_name(b.depth), threads, updates / wall_s,
      w.update_ms / static_cast<double>(readings), w.estimate_ms / static_cast<double>(readings), w.cpu_s,
      errors.size(), sessions, errors.empty() ? 0.0 : errors[errors.size() / 2],
      static_cast<unsigned long long>(w.digest));
  if (!span_model) return 0;
  const Run p = run_batch(map, options, b, true);
  if (p.digest != w.digest) throw sva::Error("the batch under the span probe gave other answers");
  const double work = p.update.work + p.estimate.work, span = p.update.span + p.estimate.span;
  const double cores = static_cast<double>(threads), fastest = std::max(work / cores, span);
  const double scheduled = std::max(p.update.scheduled + p.estimate.scheduled, fastest);
  std::printf(
      "under a span probe, its loops split for %u thread(s), timed on one: work %.1f ms (update %.1f + estimate %.1f), "
      "span %.1f ms (update %.1f + estimate %.1f), scheduled on %u %.1f ms: on %u cores between %.1f and %.1f "
      "session-updates/s, %.1f as scheduled (a model)\n",
      threads, work, p.update.work, p.estimate.work, span, p.update.span, p.estimate.span, threads, scheduled, threads,
      updates / (1e-3 * (work / cores + span)), updates / (1e-3 * fastest), updates / (1e-3 * scheduled));
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "batch_speed: %s\n", e.what());
  return 1;
}
