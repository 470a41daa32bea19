// What an estimate costs: Recognizer::estimate(0) (no hypotheses), estimate(1) and estimate(3) (distinct
// hypotheses with masses and covariances, and one per object), each light (the belief's answer, no fit on the host),
// then estimate(3) in full (the fine pose and the surface check, from 6 readings on), on the CPU backend, after N
// readings of one object (default 3) of a dataset.
//
//   cpp_estimate_cost MAP.svam TEST.svad N [OBJECT]
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sva/dataset.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>
int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s MAP.svam TEST.svad READINGS [OBJECT]\n", argv[0]);
    return 2;
  }
  const sva::Map map = sva::Map::load(argv[1]);
  const sva::Dataset data = sva::load_dataset(argv[2]);
  const std::size_t n = std::strtoul(argv[3], nullptr, 10);
  const std::uint32_t object = argc > 4 ? static_cast<std::uint32_t>(std::strtoul(argv[4], nullptr, 10)) : 3;
  sva::EngineOptions eo;
  eo.backend = sva::BackendKind::cpu;
  const sva::Engine engine(map, eo);
  sva::Recognizer rec(engine, map.pose_space());
  std::size_t used = 0;
  auto t0 = std::chrono::steady_clock::now();
  for (const auto& s : data.samples) {
    if (s.object != object) continue;
    try {
      rec.add_reading(s.reading);
    } catch (const sva::Error&) {
      continue;
    }
    if (++used == n) break;
  }
  if (used == 0) {
    std::fprintf(stderr, "%s: no reading of object %u could be added\n", argv[2], object);
    return 1;
  }
  const double upd = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / used;
  auto time = [&](std::size_t k, sva::EstimateDepth depth) {
    const int reps = 20;
    auto a = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) (void)rec.estimate(k, depth);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count() / reps;
  };
  const auto light = sva::EstimateDepth::light;
  const double e0 = time(0, light), e1 = time(1, light), e3 = time(3, light);
  const double full = time(3, sva::EstimateDepth::full);
  const sva::Estimate e = rec.estimate(3);
  std::printf(
      "%zu readings, %zu objects: update %.1f ms (mean); light estimate(0) %.2f ms, estimate(1) %.2f ms, estimate(3) "
      "%.2f ms; full estimate(3) %.2f ms (fine pose %s); %zu hypotheses, best %s p=%.3f\n",
      used, map.objects(), upd, e0, e1, e3, full, e.pose_refined ? "on" : "not yet", e.hypotheses.size(),
      e.object_name.c_str(), e.object_probability[e.object]);
}
