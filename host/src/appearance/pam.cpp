#include "appearance/pam.hpp"

#include <sva/base/interrupt.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/progress.hpp>
#include <sva/base/rng.hpp>

#include <algorithm>
#include <cassert>
#include <memory>
#include <numeric>

namespace sva::appearance {

namespace {

// Larger than any dissimilarity (they lie in [0, 2]): "no second medoid".
constexpr float kNoSecond = 3.0f;
// A swap must lower the loss by more than rounding noise, so float ties
// cannot make the search cycle.
constexpr double kMinGain = 1e-9;

// Dissimilarities row by row. Rows are computed the same way whether they
// come from the cached matrix or on the fly, so both modes give equal bits:
// the terms of each inner product are added in dimension order, which also
// makes d(i, j) and d(j, i) identical.
class Dissimilarity {
 public:
  Dissimilarity(const std::vector<float>& points, std::uint32_t dim, bool cache, unsigned threads)
      : n_(points.size() / dim), dim_(dim), points_(points), transposed_(points.size()) {
    for (std::size_t j = 0; j < n_; ++j)
      for (std::uint32_t t = 0; t < dim; ++t) transposed_[t * n_ + j] = points[j * dim + t];
    if (!cache) return;
    matrix_.reset(new float[n_ * n_]);
    constexpr std::size_t block = 32;
    util::parallel_for((n_ + block - 1) / block,
                       [&](std::size_t b) {
                         for (std::size_t i = b * block; i < std::min(n_, (b + 1) * block); ++i)
                           compute(i, &matrix_[i * n_]);
                       },
                       threads);
  }
  std::size_t size() const { return n_; }
  // Row i (= column i); `scratch` (n floats) is used when there is no matrix.
  const float* row(std::size_t i, float* scratch) const {
    if (matrix_) return &matrix_[i * n_];
    compute(i, scratch);
    return scratch;
  }
  bool cached() const { return matrix_ != nullptr; }

 private:
  void compute(std::size_t i, float* __restrict out) const {
    std::fill(out, out + n_, 0.0f);
    const std::size_t whole = n_ / 8 * 8;
    for (std::uint32_t t = 0; t < dim_; ++t) {
      const float a = points_[i * dim_ + t];
      const float* __restrict col = &transposed_[t * n_];
      // Fixed 8-wide blocks: vectorised at -O2 without any reordering of sums.
      for (std::size_t j = 0; j < whole; j += 8)
        for (std::size_t l = 0; l < 8; ++l) out[j + l] += a * col[j + l];
      for (std::size_t j = whole; j < n_; ++j) out[j] += a * col[j];
    }
    for (std::size_t j = 0; j < n_; ++j) out[j] = std::max(0.0f, 1.0f - out[j]);
    out[i] = 0.0f;
  }
  std::size_t n_;
  std::uint32_t dim_;
  const std::vector<float>& points_;
  std::vector<float> transposed_;
  std::unique_ptr<float[]> matrix_;
};

// Sum over o of min(row[o] - nearest[o], 0), in eight fixed lanes so the
// compiler vectorises it without changing the result.
double build_gain(const float* row, const float* nearest, std::size_t n) {
  float lane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t o = 0;
  for (; o + 8 <= n; o += 8)
    for (int l = 0; l < 8; ++l) lane[l] += std::min(row[o + l] - nearest[o + l], 0.0f);
  double s = 0;
  for (; o < n; ++o) s += std::min(row[o] - nearest[o], 0.0f);
  for (float v : lane) s += v;
  return s;
}

struct State {
  std::vector<std::uint32_t> medoid;        // point index per slot
  std::vector<std::uint32_t> near, second;  // slot per point
  std::vector<float> dnear, dsecond;
};

void assign(State& s, const std::vector<const float*>& rows, std::size_t n) {
  const std::size_t k = s.medoid.size();
  for (std::size_t o = 0; o < n; ++o) {
    std::uint32_t a = 0, b = 0;
    float da = kNoSecond, db = kNoSecond;
    for (std::size_t m = 0; m < k; ++m) {
      const float d = rows[m][o];
      if (d < da) {
        b = a, db = da;
        a = static_cast<std::uint32_t>(m), da = d;
      } else if (d < db) {
        b = static_cast<std::uint32_t>(m), db = d;
      }
    }
    s.near[o] = a, s.dnear[o] = da, s.second[o] = b, s.dsecond[o] = db;
  }
}

}  // namespace

double pam_loss(const std::vector<float>& points, std::uint32_t dim, const std::vector<std::uint32_t>& medoids) {
  Dissimilarity d(points, dim, false, 1);
  std::vector<float> best(d.size(), kNoSecond), scratch(d.size());
  for (auto m : medoids) {
    const float* r = d.row(m, scratch.data());
    for (std::size_t o = 0; o < d.size(); ++o) best[o] = std::min(best[o], r[o]);
  }
  double loss = 0;
  for (float v : best) loss += v;
  return loss;
}

namespace {

// FasterPAM from the given medoids: visit candidates in `order`, apply the
// best swap for a candidate as soon as it improves the loss, stop after a
// full cycle without one.
PamResult swap_search(const Dissimilarity& dis, std::vector<std::uint32_t> medoids,
                      const std::vector<std::uint32_t>& order) {
  const std::size_t n = dis.size(), k = medoids.size();
  std::vector<float> scratch(n);
  State s;
  s.medoid = std::move(medoids);
  s.near.assign(n, 0);
  s.second.assign(n, 0);
  s.dnear.assign(n, kNoSecond);
  s.dsecond.assign(n, kNoSecond);
  // Rows of the current medoids (copied when computed on the fly).
  std::vector<std::vector<float>> owned(dis.cached() ? 0 : k);
  std::vector<const float*> rows(k, nullptr);
  auto set_row = [&](std::size_t slot, std::uint32_t point) {
    if (dis.cached()) {
      rows[slot] = dis.row(point, nullptr);
    } else {
      owned[slot].resize(n);
      dis.row(point, owned[slot].data());
      rows[slot] = owned[slot].data();
    }
  };
  std::vector<char> is_medoid(n, 0);
  for (std::size_t m = 0; m < k; ++m) {
    is_medoid[s.medoid[m]] = 1;
    set_row(m, s.medoid[m]);
  }
  assign(s, rows, n);
  std::vector<double> removal(k), delta(k);
  auto update_removal = [&] {
    std::fill(removal.begin(), removal.end(), 0.0);
    for (std::size_t o = 0; o < n; ++o) removal[s.near[o]] += static_cast<double>(s.dsecond[o]) - s.dnear[o];
  };
  update_removal();
  PamResult res;
  constexpr std::uint32_t kMaxPasses = 100;
  std::size_t since_swap = 0;
  for (std::size_t step = 0; k < n && since_swap < n; ++step) {
    if (step % n == 0) {
      if (res.passes == kMaxPasses) break;
      ++res.passes;
    }
    util::throw_if_interrupted();
    const std::uint32_t xc = order[step % n];
    ++since_swap;
    if (is_medoid[xc]) continue;
    const float* r = dis.row(xc, scratch.data());
    delta = removal;
    double shared = 0;
    for (std::size_t o = 0; o < n; ++o) {
      const float d = r[o];
      if (d < s.dnear[o]) {
        shared += static_cast<double>(d) - s.dnear[o];
        delta[s.near[o]] += static_cast<double>(s.dnear[o]) - s.dsecond[o];
      } else if (d < s.dsecond[o]) {
        delta[s.near[o]] += static_cast<double>(d) - s.dsecond[o];
      }
    }
    std::size_t m = 0;
    for (std::size_t i = 1; i < k; ++i)
      if (delta[i] < delta[m]) m = i;
    if (delta[m] + shared >= -kMinGain) continue;
    is_medoid[s.medoid[m]] = 0;
    is_medoid[xc] = 1;
    s.medoid[m] = xc;
    set_row(m, xc);
    assign(s, rows, n);
    update_removal();
    ++res.swaps;
    since_swap = 0;
  }
  res.medoids = s.medoid;
  res.membership = s.near;
  for (std::size_t o = 0; o < n; ++o) res.loss += s.dnear[o];
  return res;
}

// BUILD: greedily add the point that lowers the loss most (ties: lowest index).
std::vector<std::uint32_t> build(const Dissimilarity& dis, std::size_t k, unsigned threads, bool progress) {
  const std::size_t n = dis.size();
  std::unique_ptr<util::Progress> bar;
  if (progress) bar = std::make_unique<util::Progress>("clustering: PAM BUILD", k);
  std::vector<std::uint32_t> medoids;
  std::vector<float> dnear(n, kNoSecond), scratch(n);
  std::vector<char> is_medoid(n, 0);
  std::vector<double> gain(n);
  constexpr std::size_t block = 64;
  const std::size_t blocks = (n + block - 1) / block;
  for (std::size_t m = 0; m < k; ++m) {
    util::parallel_for(
        blocks,
        [&](std::size_t b) {
          std::vector<float> local(dis.cached() ? 0 : n);
          for (std::size_t c = b * block; c < std::min(n, (b + 1) * block); ++c) {
            if (is_medoid[c]) continue;
            gain[c] = build_gain(dis.row(c, local.data()), dnear.data(), n);
          }
        },
        threads);
    std::size_t best = n;
    for (std::size_t c = 0; c < n; ++c)
      if (!is_medoid[c] && (best == n || gain[c] < gain[best])) best = c;
    is_medoid[best] = 1;
    medoids.push_back(static_cast<std::uint32_t>(best));
    const float* r = dis.row(best, scratch.data());
    for (std::size_t o = 0; o < n; ++o) dnear[o] = std::min(dnear[o], r[o]);
    if (bar) bar->advance();
  }
  if (bar) bar->finish();
  return medoids;
}

}  // namespace

PamResult pam(const std::vector<float>& points, std::uint32_t dim, const PamOptions& opt) {
  assert(dim > 0 && !points.empty() && points.size() % dim == 0);
  const std::size_t n = points.size() / dim;
  const std::size_t k = std::max<std::size_t>(1, std::min<std::size_t>(opt.k, n));
  const Dissimilarity dis(points, dim, n <= opt.max_matrix_points, opt.threads);

  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  util::Rng rng(opt.seed, 0x9a3c1u);
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);

  auto random_medoids = [&](std::uint32_t r) {
    util::Rng pick(opt.seed, 0x5eedu, r);
    std::vector<std::uint32_t> all(n);
    std::iota(all.begin(), all.end(), 0u);
    for (std::size_t i = 0; i < k; ++i) std::swap(all[i], all[i + pick.below(n - i)]);
    all.resize(k);
    return all;
  };
  // BUILD reads the whole matrix k times: cheap when it is cached, k full
  // passes of n^2 inner products when not. Then start from seeded random
  // medoids instead, as FasterPAM does; the swaps and restarts do the rest.
  const std::vector<std::uint32_t> first = dis.cached() ? build(dis, k, opt.threads, opt.progress) : random_medoids(0);
  // Swap search stops in a local optimum, as classic PAM does; restarts from
  // seeded random medoids keep the best, which finds the global optimum of
  // small sets far more often than one descent. The searches are independent
  // (each its own start, the same visiting order), so they run side by side
  // and are then compared in order, as one after another would be.
  const std::size_t searches = k < n ? 1 + std::size_t{opt.restarts} : 1;
  std::unique_ptr<util::Progress> bar;
  if (opt.progress && searches > 1)
    bar = std::make_unique<util::Progress>(
        dis.cached() ? "clustering: FasterPAM swap searches" : "clustering: FasterPAM (rows on the fly)", searches);
  std::vector<PamResult> found(searches);
  util::parallel_for(
      searches,
      [&](std::size_t r) {
        found[r] = swap_search(dis, r == 0 ? first : random_medoids(static_cast<std::uint32_t>(r)), order);
        if (bar) bar->advance();
      },
      opt.threads);
  if (bar) bar->finish();
  PamResult best = std::move(found[0]);
  for (std::size_t r = 1; r < searches; ++r) {
    PamResult& res = found[r];
    res.swaps += best.swaps;
    res.passes += best.passes;
    if (res.loss < best.loss - kMinGain)
      best = std::move(res);
    else
      best.swaps = res.swaps, best.passes = res.passes;
  }
  return best;
}

}  // namespace sva::appearance
