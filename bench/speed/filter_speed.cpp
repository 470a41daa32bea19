// Time per Bayes-filter update as readings accumulate, on a trained map and
// its test readings (CPU reference backend), with votes per second, the votes
// whose fixed-point mass rounds to zero, the recognition error those updates
// buy and the peak resident memory (RSS) of the process.
//   filter_speed MAP.svam TEST.svad [trials=3] [readings=100] [threads=0]
//                [object_prune_probability=0] [max_pairs_per_update=0] [likelihood_cutoff=0] [span=0]
// span=1: the updates at readings 10, 30 and 100 run under a span probe (sva/base/parallel.hpp) instead of on the
// workers: their loops split for `threads` but run in turn on one core, timed, which gives their work and critical
// path and so a model of the update on `threads` cores of this machine's kind (docs/recognition.md, "One session on
// many cores"): Brent's bounds, and between them the loops' list schedule on the threads (SpanProbe::scheduled_ms).
// Trial t recognises object t % objects from its test readings, drawn at
// random, moved by a random pose (rotation arbitrary, translation in the pose
// space's range, as in the paper's protocol).
#include <sva/base/rng.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include <sva/base/parallel.hpp>
#include <sva/base/so3.hpp>
#include <sva/eval/process_memory.hpp>

#include "cpu_time.hpp"
#include "sessions.hpp"
#include "whole_number_arg.hpp"

namespace {

// Argument i as a number in [0, 1], 0 when not given (the prune probability and the likelihood cut-off).
double fraction_arg(int argc, char** argv, int i) {
  if (argc <= i) return 0.0;
  char* end = nullptr;
  const double v = std::strtod(argv[i], &end);
  if (!end || end == argv[i] || *end != '\0' || !(v >= 0.0 && v <= 1.0)) {
    std::fprintf(stderr, "filter_speed: argument %d (\"%s\") is not a number in 0..1\n", i, argv[i]);
    std::exit(2);
  }
  return v;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double p95(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1)];
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 3 || std::strcmp(argv[1], "--help") == 0) {
    std::fprintf(stderr,
                 "usage: filter_speed MAP.svam TEST.svad [trials=3] [readings=100] [threads=0] [prune=0] [max_pairs=0] "
                 "[cutoff=0] [span=0]\n");
    return argc < 3 ? 2 : 0;
  }
  const int trials = static_cast<int>(sva::bench::whole_number_arg("filter_speed", argc, argv, 3, 3, 1, 100000));
  const int readings = static_cast<int>(sva::bench::whole_number_arg("filter_speed", argc, argv, 4, 100, 1, 100000));
  sva::RecognizerOptions options;
  options.threads = static_cast<unsigned>(sva::bench::whole_number_arg("filter_speed", argc, argv, 5, 0, 0, 1024));
  options.object_prune_probability = fraction_arg(argc, argv, 6);
  options.max_pairs_per_update =
      static_cast<int>(sva::bench::whole_number_arg("filter_speed", argc, argv, 7, 0, 0, 1000000));
  options.likelihood_cutoff = static_cast<float>(fraction_arg(argc, argv, 8));
  const bool span_model = sva::bench::whole_number_arg("filter_speed", argc, argv, 9, 0, 0, 1) != 0;
  const sva::Map map = sva::Map::load(argv[1]);
  const sva::Dataset test = sva::load_dataset(argv[2]);
  const sva::PoseSpaceSpec space = map.pose_space();
  const std::size_t objects = map.objects();
  const auto by_object = sva::bench::readings_by_object(map, test);

  const int marks[] = {10, 30, 100};
  std::vector<double> at_mark[3], cpu_at_mark[3], work_at_mark[3], span_at_mark[3], sched_at_mark[3];
  double total_votes = 0.0, total_seconds = 0.0;
  std::uint64_t total_zero = 0;  // votes inside the space whose mass rounds to 0: counted, they add nothing
  int correct = 0;
  std::vector<double> terr;
  for (int t = 0; t < trials; ++t) {
    const std::uint32_t object = static_cast<std::uint32_t>(t % static_cast<int>(objects));
    const auto& pool = by_object[object];
    if (pool.empty()) continue;
    sva::util::Rng rng(2026, static_cast<std::uint64_t>(t));
    sva::RigidPose truth;
    const glm::dvec3 axis = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    truth.R = sva::so3::exp(axis * rng.uniform(0.0, std::numbers::pi));
    const double lo = space.translation_min_mm, hi = space.translation_max_mm;
    truth.T = {rng.uniform(lo, hi), rng.uniform(lo, hi),
               space.kind == sva::PoseSpaceSpec::Kind::planar ? 0.0 : rng.uniform(lo, hi)};
    if (space.kind == sva::PoseSpaceSpec::Kind::planar) truth.R = sva::so3::about_z(rng.uniform(-3.1, 3.1));
    sva::Recognizer rec(map, space, options);
    for (int i = 0; i < readings; ++i) {
      sva::Reading r = *pool[rng.below(pool.size())];
      r.position = truth.apply(r.position);
      r.normal = truth.rotate(r.normal);
      r.x_axis = truth.rotate(r.x_axis);
      const int mark = static_cast<int>(std::find(marks, marks + 3, i + 1) - marks);
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = sva::bench::process_cpu_seconds();
      if (span_model && mark < 3) {
        const sva::util::SpanProbe probe;
        rec.add_reading(r);
        work_at_mark[mark].push_back(probe.work_ms());
        span_at_mark[mark].push_back(probe.span_ms());
        sched_at_mark[mark].push_back(probe.scheduled_ms());
      } else {
        rec.add_reading(r);
      }
      const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double cpu = sva::bench::process_cpu_seconds() - c0;
      const sva::Estimate e = rec.estimate(1);
      total_votes += static_cast<double>(e.votes);
      total_zero += e.votes_zero;
      total_seconds += sec;
      if (mark < 3 && !span_model) {
        at_mark[mark].push_back(sec);
        cpu_at_mark[mark].push_back(cpu);
      }
    }
    const sva::Estimate e = rec.estimate(1);
    if (e.object == object) {
      ++correct;
      terr.push_back(glm::length(e.pose.T - truth.T));
    }
    std::printf("trial %d: object %u -> %s (p = %.3f)%s\n", t, object, e.object_name.c_str(),
                e.object_probability[e.object], e.object == object ? "" : "  WRONG");
    std::fflush(stdout);
  }
  std::printf(
      "\nCPU reference backend, %s threads, map: %zu entries, %zu objects; object prune %g, max pairs %d, likelihood "
      "cut-off %g\n",
      options.threads ? std::to_string(options.threads).c_str() : "all", map.entries(), objects,
      options.object_prune_probability, options.max_pairs_per_update, static_cast<double>(options.likelihood_cutoff));
  for (int m = 0; m < 3; ++m)
    if (!at_mark[m].empty())
      std::printf("update at reading %3d: wall median %.3f s, p95 %.3f s; CPU median %.3f s (%zu trials)\n", marks[m],
                  median(at_mark[m]), p95(at_mark[m]), median(cpu_at_mark[m]), at_mark[m].size());
  for (int m = 0; m < 3; ++m)
    if (!work_at_mark[m].empty()) {
      const double work = median(work_at_mark[m]), span = median(span_at_mark[m]), p = options.threads;
      std::printf(
          "update at reading %3d under a span probe, its loops split for %s threads: work median %.2f ms, span median "
          "%.2f ms (%zu trials)",
          marks[m], options.threads ? std::to_string(options.threads).c_str() : "all", work, span,
          work_at_mark[m].size());
      if (options.threads)
        std::printf("; on %u cores of this machine's kind between %.2f and %.2f ms, as scheduled %.2f ms (a model)",
                    options.threads, std::max(work / p, span), work / p + span,
                    std::max(median(sched_at_mark[m]), std::max(work / p, span)));
      std::printf("\n");
    }
  std::printf("votes per second: %.3g (%.3g votes in %.1f s of updates)\n", total_votes / std::max(total_seconds, 1e-9),
              total_votes, total_seconds);
  std::printf("votes of mass 0 (below half a 2^-24 unit): %llu of %.3g (%.3g%%)\n",
              static_cast<unsigned long long>(total_zero), total_votes,
              100.0 * static_cast<double>(total_zero) / std::max(total_votes, 1.0));
  std::printf("after %d readings: %d/%d objects right, median translation error %.1f mm\n", readings, correct, trials,
              median(terr));
  std::printf("peak RSS of the process: %.1f MiB\n",
              static_cast<double>(sva::bench::MemoryMeter().process_peak_bytes()) / (1024.0 * 1024.0));
  return 0;
} catch (const sva::Error& e) {
  std::fprintf(stderr, "filter_speed: %s\n", e.what());
  return 1;
}
