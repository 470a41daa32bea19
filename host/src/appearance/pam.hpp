#pragma once
// Partitioning Around Medoids on the dissimilarity 1 - <a, b> of unit
// descriptors: BUILD initialisation, then FasterPAM swaps (Schubert &
// Rousseeuw 2021: eager swaps, O(n) per candidate with cached nearest and
// second-nearest medoids) until no single swap lowers the loss, which is
// classic PAM's stopping rule; then a few restarts from random medoids.
#include <cstdint>
#include <vector>

namespace sva::appearance {

struct PamOptions {
  std::uint32_t k = 25;
  std::uint64_t seed = 1;      // order in which swap candidates are visited, restart medoids
  std::uint32_t restarts = 2;  // extra swap searches from seeded random medoids; the best wins
  // Up to this many points the n x n float dissimilarity matrix is kept in
  // memory (n = 16384: 1 GiB); beyond, rows are recomputed on the fly.
  std::size_t max_matrix_points = 16384;
  unsigned threads = 0;  // matrix, BUILD and the swap searches side by side; results do not depend on it
  bool progress = false;
};

struct PamResult {
  std::vector<std::uint32_t> medoids;     // indices into the points, min(k, n) of them
  std::vector<std::uint32_t> membership;  // per point, index into `medoids` of its nearest
  double loss = 0;                        // sum over points of the dissimilarity to their medoid
  std::uint32_t swaps = 0;
  std::uint32_t passes = 0;
};

// points: n x dim, row-major. n >= 1.
PamResult pam(const std::vector<float>& points, std::uint32_t dim, const PamOptions& options);

// Loss of a given medoid set (tests, and the exhaustive check).
double pam_loss(const std::vector<float>& points, std::uint32_t dim, const std::vector<std::uint32_t>& medoids);

}  // namespace sva::appearance
