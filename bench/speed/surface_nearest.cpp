// The verify stage's and the fine pose's primitive, timed bare (bench/speed/surface_nearest.sh): the point of an
// object's mesh nearest to a query (SurfaceModel::nearest, host/src/estimate/surface_model.hpp), on the meshes a map
// carries. Queries lie near each surface as a reading under a good hypothesis does: a point of a random triangle,
// moved along its normal by up to 2 mm and across it by up to 1 mm, searched within the model's reach. Prints the
// time per query and a digest of every answer (triangle, distance bits), which must not change when nearest() is
// made faster.
//   surface_nearest MAP [queries per object] [repeats]
#include <sva/base/rng.hpp>
#include <sva/error.hpp>
#include <sva/eval/process_memory.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "estimate/verify.hpp"
#include "map/map_file.hpp"

namespace {

struct Query {
  std::uint32_t object;
  glm::dvec3 p;
};

std::vector<Query> make_queries(const sva::PairMap& map, std::size_t per_object) {
  std::vector<Query> out;
  for (std::uint32_t o = 0; o < map.surfaces.size(); ++o) {
    const sva::ObjectSurface& s = map.surfaces[o];
    if (s.triangles.empty()) continue;
    sva::util::Rng rng(7, o);
    for (std::size_t i = 0; i < per_object; ++i) {
      const glm::uvec3 t = s.triangles[rng.below(s.triangles.size())];
      const glm::dvec3 a(s.positions[t.x]), b(s.positions[t.y]), c(s.positions[t.z]);
      double u = rng.uniform(), v = rng.uniform();
      if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double len = glm::length(n);
      const glm::dvec3 unit = len > 0.0 ? n / len : glm::dvec3(0.0, 0.0, 1.0);
      const glm::dvec3 across(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
      out.push_back({o, a + u * (b - a) + v * (c - a) + (4.0 * rng.uniform() - 2.0) * unit + 2.0 * across});
    }
  }
  return out;
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) { return (h ^ v) * 0x100000001b3ULL; }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0) {
    std::fprintf(stderr, "usage: surface_nearest MAP [queries per object (default 20000)] [repeats (default 5)]\n");
    return argc < 2 ? 2 : 0;
  }
  try {
    const std::size_t per_object = argc > 2 ? std::stoul(argv[2]) : 20000;
    const int repeats = argc > 3 ? std::stoi(argv[3]) : 5;
    const auto map = sva::load_pair_map(argv[1]);
    const double before_mb = double(sva::bench::resident_memory().rss_bytes) / 1e6;
    const auto model = sva::surface_model_of(*map);
    const double model_mb = double(sva::bench::resident_memory().rss_bytes) / 1e6 - before_mb;
    if (!model) throw sva::Error(std::string(argv[1]) + ": the map carries no meshes (trained with --no-surfaces)");
    const std::vector<Query> queries = make_queries(*map, per_object);
    double best_ns = 1e300;
    std::uint64_t digest = 0xcbf29ce484222325ULL;
    std::size_t found = 0;
    for (int r = 0; r < repeats; ++r) {
      std::uint64_t h = 0xcbf29ce484222325ULL;
      std::size_t f = 0;
      const auto t0 = std::chrono::steady_clock::now();
      for (const Query& q : queries) {
        const sva::SurfaceModel::Nearest n = model->nearest(q.object, q.p, model->reach_mm());
        if (!n.found) continue;
        ++f;
        std::uint64_t bits;
        std::memcpy(&bits, &n.distance, sizeof bits);
        h = mix(mix(h, n.triangle), bits);
      }
      const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
      best_ns = std::min(best_ns, ns / double(queries.size()));
      digest = h, found = f;
    }
    std::printf(
        "%zu queries on %zu meshes within %.2f mm: %.1f ns per query (best of %d), %.1f%% found, digest "
        "%016llx; the model %.1f MB resident\n",
        queries.size(), map->surfaces.size(), model->reach_mm(), best_ns, repeats,
        100.0 * double(found) / double(queries.size()), static_cast<unsigned long long>(digest), model_mb);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surface_nearest: %s\n", e.what());
    return 1;
  }
}
