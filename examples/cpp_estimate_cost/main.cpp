// What an estimate costs: Recognizer::estimate(0) (no hypotheses), estimate(1) and estimate(3) (distinct
// hypotheses with masses and covariances, and one per object), on the CPU backend, after N readings of one object
// (default 3) of a dataset, with the fine pose off (it is the same in every case).
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
  sva::RecognizerOptions ro;
  ro.refine_pose = false;
  sva::Recognizer rec(engine, map.pose_space(), ro);
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
  auto time = [&](std::size_t k) {
    const int reps = 20;
    auto a = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) (void)rec.estimate(k);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count() / reps;
  };
  const double e0 = time(0), e1 = time(1), e3 = time(3);
  const sva::Estimate e = rec.estimate(3);
  std::printf(
      "%zu readings, %zu objects: update %.1f ms (mean); estimate(0) %.2f ms, estimate(1) %.2f ms, estimate(3) %.2f "
      "ms; %zu hypotheses, best %s p=%.3f\n",
      used, map.objects(), upd, e0, e1, e3, e.hypotheses.size(), e.object_name.c_str(), e.object_probability[e.object]);
}
