// The estimate's host stages timed on fixed sessions (bench/speed/estimate_speed.sh): a batch of sessions is fed
// its readings once, then the same estimates are asked for again and again, and the best of the repeats is the
// stages' time free of the first run's cold caches. Every repeat after the first reads the best bins the CPU belief
// kept from the first (Belief::best_bins keeps them until the next fold), so the best leaves out the pass over the
// belief that a fresh estimate after an update makes for them: `sva bench`'s est. ms has it. Prints the ms per session
// of each stage (docs/architecture.md: 1 belief, 2 fits, 3 verify, 4-5 posterior), the process's CPU time per session
// (steadier than wall time on a shared machine), and a digest of every answer (object, probabilities, poses,
// hypotheses with their covariances, each object's too), which must not change when a stage is made faster. Last, each
// session's estimate alone under a span probe (sva/base/parallel.hpp): its work and critical path, as its loops split
// for `threads` (a model of one robot's session on that many cores).
//   estimate_speed MAP TEST [sessions (default 6)] [readings (default 30)] [repeats (default 5)] [threads (default 1)]
//                  [top_k (default 3)] [depth: full (default) or light]
// Session t touches object t % objects at a random pose, as `sva bench`'s trials do (seed 1).
#include <sva/base/parallel.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "sessions.hpp"
#include "cpu_time.hpp"
#include "whole_number_arg.hpp"

namespace {

std::size_t arg(int argc, char** argv, int i, std::size_t fallback, std::size_t lo, std::size_t hi) {
  return sva::bench::whole_number_arg("estimate_speed", argc, argv, i, fallback, lo, hi);
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 3 || std::strcmp(argv[1], "--help") == 0) {
    std::fprintf(stderr,
                 "usage: estimate_speed MAP TEST [sessions=6] [readings=30] [repeats=5] [threads=1] [top_k=3] "
                 "[depth=full|light]\n");
    return argc < 3 ? 2 : 0;
  }
  const std::size_t sessions = arg(argc, argv, 3, 6, 1, 4096);
  const std::size_t readings = arg(argc, argv, 4, 30, 1, 100000);
  const int repeats = static_cast<int>(arg(argc, argv, 5, 5, 1, 1000));
  sva::RecognizerOptions options;
  options.backend = sva::BackendKind::cpu;
  options.threads = static_cast<unsigned>(arg(argc, argv, 6, 1, 1, 1024));
  const std::size_t top_k = arg(argc, argv, 7, 3, 0, 100);
  const sva::EstimateDepth depth =
      argc > 8 ? sva::parse_estimate_depth(argv[8], "estimate_speed: depth") : sva::EstimateDepth::full;
  const sva::Map map = sva::Map::load(argv[1]);
  const sva::Dataset test = sva::load_dataset(argv[2]);
  const auto by_object = sva::bench::readings_by_object(map, test);
  sva::BatchRecognizer batch(map, map.pose_space(), sessions, options);
  std::vector<std::size_t> ids(sessions);
  std::vector<std::vector<sva::Reading>> per_session(sessions);
  for (std::size_t t = 0; t < sessions; ++t) {
    ids[t] = t;
    per_session[t] = sva::bench::make_session(by_object, map.pose_space(), t, readings, argv[2]).readings;
  }
  for (std::size_t i = 0; i < readings; ++i) {
    std::vector<sva::Reading> step;
    for (std::size_t t = 0; t < sessions; ++t) step.push_back(per_session[t][i]);
    batch.add_readings(ids, step);
  }
  sva::BatchRecognizer::EstimateTiming best{};
  double best_total = 1e300, best_cpu = 1e300;
  std::uint64_t answers = 0;
  for (int r = 0; r < repeats; ++r) {
    const double c0 = sva::bench::process_cpu_seconds();
    const std::vector<sva::Estimate> e = batch.estimates(ids, top_k, depth);
    best_cpu = std::min(best_cpu, sva::bench::process_cpu_seconds() - c0);
    const sva::BatchRecognizer::EstimateTiming t = batch.last_estimate_timing();
    const double total = t.belief_ms + t.fit_ms + t.verify_ms + t.posterior_ms;
    if (total < best_total) best_total = total, best = t;
    std::uint64_t h = sva::bench::kDigestStart;
    for (const sva::Estimate& x : e) h = sva::bench::digest(h, x);
    if (r > 0 && h != answers) throw sva::Error("the same estimates asked again gave other answers");
    answers = h;
  }
  // Each session's estimate alone, under a span probe: its work and its critical path as the loops split it for
  // `threads` (sva/base/parallel.hpp), a model of a many-core host's latency for one robot's session.
  double work = 0.0, span = 0.0, longest_span = 0.0, scheduled = 0.0;
  sva::BatchRecognizer::EstimateTiming stages{};
  for (std::size_t t = 0; t < sessions; ++t) {
    const sva::util::SpanProbe probe;
    batch.estimates(std::span(&ids[t], 1), top_k, depth);
    work += probe.work_ms(), span += probe.span_ms();
    scheduled += std::max(probe.scheduled_ms(), std::max(probe.work_ms() / options.threads, probe.span_ms()));
    longest_span = std::max(longest_span, probe.span_ms());
    const sva::BatchRecognizer::EstimateTiming s = batch.last_estimate_timing();
    stages.belief_span_ms += s.belief_span_ms, stages.fit_span_ms += s.fit_span_ms;
    stages.verify_span_ms += s.verify_span_ms, stages.posterior_span_ms += s.posterior_span_ms;
  }
  const double n = static_cast<double>(sessions);
  std::printf(
      "%zu sessions at %zu readings, top %zu, %s, %u thread(s), best of %d: ms per session: "
      "estimate %.2f = belief %.2f + fits %.2f + verify %.2f + posterior %.2f; CPU %.2f ms per session; digest "
      "%016llx\n",
      sessions, readings, top_k, sva::estimate_depth_name(depth), options.threads, repeats, best_total / n,
      best.belief_ms / n, best.fit_ms / n, best.verify_ms / n, best.posterior_ms / n, 1e3 * best_cpu / n,
      static_cast<unsigned long long>(answers));
  std::printf(
      "one session alone, its loops split for %u thread(s), timed on one: work %.2f ms, span %.2f ms (longest %.2f): "
      "on P cores at least max(work / P, span), at most work / P + span, as scheduled on %u %.2f ms (a model); span by "
      "stage: belief %.2f + fits %.2f + verify %.2f + posterior %.2f\n",
      options.threads, work / n, span / n, longest_span, options.threads, scheduled / n, stages.belief_span_ms / n,
      stages.fit_span_ms / n, stages.verify_span_ms / n, stages.posterior_span_ms / n);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "estimate_speed: %s\n", e.what());
  return 1;
}
