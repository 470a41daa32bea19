// The CPU reference vote backend: for every observed pair, every map key it
// looks up and every entry under that key, align (Sec 4.1, 4.3) and scatter the
// Gaussian in beta into pose bins, with the shared math of sva_vote_math.h.
// Pairs run in parallel; each pair's sums are integers, so the result does not
// depend on the thread count.
#include <sva/error.hpp>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <string>

#include "recognition/bin_accumulator.hpp"
#include "recognition/vote_backend.hpp"
#include "recognition/vote_math.hpp"
#include "util/interrupt.hpp"
#include "util/parallel.hpp"

namespace sva {

namespace {

using Clock = std::chrono::steady_clock;
using vote_math::SvaPatch;
using vote_math::vec3;

SvaPatch patch_of(const ObservedPatch& o) {
  SvaPatch p;
  p.p = vec3(o.position[0], o.position[1], o.position[2]);
  p.n = vec3(o.normal[0], o.normal[1], o.normal[2]);
  p.conf = o.norm_conf;
  return p;
}

class CpuVoteBackend final : public VoteBackend {
 public:
  CpuVoteBackend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings)
      : map_(map), grid_(space.grid()), objects_(space.objects()), settings_(settings) {
    const auto& r = map.readings;
    patches_.resize(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) {
      patches_[i].p = vec3(r.px[i], r.py[i], r.pz[i]);
      patches_[i].n = vec3(r.nx[i], r.ny[i], r.nz[i]);
      patches_[i].conf = r.norm_conf[i];
    }
  }

  const char* name() const override { return "cpu"; }

  std::vector<PairVotes> vote(const VoteBatch& batch) override {
    const auto start = Clock::now();
    std::vector<PairVotes> out(batch.pairs.size());
    util::parallel_for(
        batch.pairs.size(), [&](std::size_t i) { vote_pair(batch, batch.pairs[i], &out[i]); }, settings_.threads);
    last_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return out;
  }

  std::unique_ptr<BeliefState> make_belief(const PoseSpace& space, double eps) override {
    return std::make_unique<Belief>(space, eps);
  }

  // Folds in pair order; the fixed-point offsets make any order give the same belief.
  std::vector<PairStats> vote_and_fold(const VoteBatch& batch, std::span<BeliefState* const> beliefs) override {
    const auto start = Clock::now();
    std::vector<PairVotes> votes = vote(batch);
    std::vector<PairStats> out(votes.size());
    for (std::size_t i = 0; i < votes.size(); ++i) {
      const std::uint32_t s = batch.pairs[i].session;
      if (s >= beliefs.size()) throw Error("cpu backend: pair of session " + std::to_string(s) + " has no belief");
      auto* belief = dynamic_cast<Belief*>(beliefs[s]);
      if (!belief) throw Error("cpu backend: session " + std::to_string(s) + " has a belief made by another backend");
      out[i] = votes[i];
      out[i].folded = belief->fold(votes[i]);
    }
    last_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return out;
  }

 private:
  void vote_pair(const VoteBatch& batch, const PairQuery& q, PairVotes* out) const {
    const SvaPatch a1 = patch_of(q.a), b1 = patch_of(q.b);
    const std::uint8_t* active =
        batch.object_active.empty() ? nullptr : batch.object_active.data() + std::size_t{q.session} * objects_;
    BinAccumulator acc(4096);
    for (std::uint32_t k = q.key_begin; k < q.key_end; ++k) {
      const PairKeyWeight kw = batch.keys[k];
      auto it = std::lower_bound(map_.keys.begin(), map_.keys.end(), kw.key);
      if (it == map_.keys.end() || *it != kw.key) continue;
      const std::size_t slot = static_cast<std::size_t>(it - map_.keys.begin());
      const std::uint32_t begin = map_.offsets[slot], end = map_.offsets[slot + 1];
      for (std::uint32_t e = begin; e < end; ++e) {
        if ((e & 1023u) == 0) util::throw_if_interrupted();
        const std::uint32_t ra = map_.entry_a[e], rb = map_.entry_b[e];
        const std::uint32_t object = map_.readings.object[ra];
        if (active && !active[object]) continue;
        const float likelihood = kw.weight * map_.entry_weight[e];
        if (!(likelihood > 0.0f) || likelihood < settings_.likelihood_cutoff) continue;
        const vote_math::SvaAlignment al = vote_math::sva_align(a1, b1, patches_[ra], patches_[rb]);
        const int n = vote_math::sva_beta_sample_count(al, grid_);
        if (n == 0) continue;
        ++out->matches;
        const float wsum = vote_math::sva_beta_weight_sum(al, n);
        for (int s = 0; s < n; ++s) {
          const vote_math::SvaVote v = vote_math::sva_vote(al, grid_, object, likelihood, wsum, s, n);
          if (!v.inside) {
            ++out->votes_outside;
            continue;
          }
          ++out->votes;
          if (v.mass > 0) acc.add(v.key, v.mass);
        }
      }
    }
    acc.sorted(&out->keys, &out->mass);
  }

  const PairMap& map_;
  vote_math::SvaPoseGrid grid_;
  std::uint32_t objects_;
  VoteSettings settings_;
  std::vector<SvaPatch> patches_;
  double last_ms_ = 0.0;  // host time of the last vote or vote_and_fold

 public:
  BackendStats statistics() const override {
    BackendStats s;
    s.backend = name();
    const unsigned threads = settings_.threads ? settings_.threads : util::default_threads();
    s.device = "CPU reference (" + std::to_string(threads) + " threads)";
    s.last_host_ms = last_ms_;
    return s;
  }
};

}  // namespace

std::unique_ptr<VoteBackend> make_cpu_vote_backend(const PairMap& map, const PoseSpace& space, const VoteSettings& settings) {
  return std::make_unique<CpuVoteBackend>(map, space, settings);
}

}  // namespace sva
