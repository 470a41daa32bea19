// The floor of the CPU reference's hash-table work on this machine (bench/speed/hash_floor.sh; docs/recognition.md,
// "The floor of the tables"). An update adds every run of a match's votes into its pair's table (a few thousand bins,
// in the caches) and every fold term into the session's belief (millions of bins, in memory). `sva bench` counts
// both per update; this tool times them bare, with the engine's own table (backends/cpu/bin_accumulator.hpp), on
// random keys (the belief's additions one after another, and in batches whose home slots are loaded first, as
// Belief::add makes them), and times one independent hashed load per key: what an addition would cost if nothing but
// its cache miss were left. Those times the counts are the least an update can take with these tables, whatever the
// vote math costs.
//   hash_floor [pair_slots pair_adds pair_bins belief_bins terms new_percent repeats]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "backends/cpu/bin_accumulator.hpp"
#include "whole_number_arg.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Sizes {
  // paper3d at 30 readings (sva bench's work counts on the full map): 267,521 probes into 29 pairs' tables, 79,958
  // fold terms, a belief table of 34 MB.
  std::size_t pair_slots = 65536;     // a kept pair table's slots
  std::size_t pair_adds = 9200;       // additions into one pair's table (runs of a match's votes)
  std::size_t pair_bins = 2760;       // distinct bins among them (the pair's fold terms)
  std::size_t belief_bins = 1200000;  // bins in the session's belief
  std::size_t terms = 80000;          // fold terms of one update
  unsigned new_percent = 33;          // terms whose bin the belief does not hold yet
  int repeats = 10;                   // best of
};

// splitmix64: keys below 2^62, as pose keys are.
std::uint64_t next_key(std::uint64_t& s) {
  s += 0x9e3779b97f4a7c15ULL;
  std::uint64_t z = s;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return (z ^ (z >> 31)) >> 2;
}

double ns_per(Clock::time_point start, std::size_t n) {
  return std::chrono::duration<double, std::nano>(Clock::now() - start).count() / static_cast<double>(n);
}

// One pair after another into one kept table, emptied between pairs as the backend empties its worker's table.
double pair_table_ns(const Sizes& z) {
  sva::BinAccumulator table(z.pair_slots / 2);
  std::uint64_t seed = 1;
  double best = 1e30;
  for (int r = 0; r < z.repeats; ++r) {
    std::vector<std::uint64_t> bins(z.pair_bins), adds(z.pair_adds);
    for (auto& b : bins) b = next_key(seed);
    for (auto& a : adds) a = bins[next_key(seed) % bins.size()];
    constexpr int kPairs = 29;
    const auto start = Clock::now();
    for (int p = 0; p < kPairs; ++p) {
      table.clear_keeping_capacity();
      for (const std::uint64_t a : adds) table.add(a ^ static_cast<std::uint64_t>(p), 5);
    }
    best = std::min(best, ns_per(start, kPairs * adds.size()));
  }
  return best;
}

struct BeliefFigures {
  double add_ns = 0.0, batched_ns = 0.0, load_ns = 0.0, megabytes = 0.0;
  int repeats = 0;  // timed
};

// An update's terms: a share new to the belief, the rest among the bins it holds.
std::vector<std::uint64_t> draw_terms(const Sizes& z, const std::vector<std::uint64_t>& held, std::uint64_t& seed) {
  std::vector<std::uint64_t> terms(z.terms);
  for (auto& t : terms) t = next_key(seed) % 100 < z.new_percent ? next_key(seed) : held[next_key(seed) % held.size()];
  return terms;
}

// A belief of `belief_bins` bins, grown as a session grows it, then updates of `terms` terms each: the additions one
// after another, the additions as Belief::add makes them (each batch of 32 terms' home slots loaded first), and one
// independent load of the home slot of each term (the miss alone, overlapped as far as the core can). Each pass has
// terms of its own, so that none finds another's lines in the caches. The repeats stop before the new bins would grow
// the table (at three quarters full), so that it keeps the size and load it was asked for.
BeliefFigures belief_ns(const Sizes& z) {
  sva::BeliefTable table(1024);
  std::vector<std::uint64_t> held(z.belief_bins);
  std::uint64_t seed = 7;
  for (auto& k : held) table.add(k = next_key(seed), 3);
  BeliefFigures f;
  f.add_ns = f.batched_ns = f.load_ns = 1e30;
  const std::size_t new_per_repeat = 2 * (z.terms * z.new_percent / 100 + 1);  // two passes add
  for (; f.repeats < z.repeats && (table.size() + new_per_repeat) * 4 <= table.capacity() * 3; ++f.repeats) {
    const std::vector<std::uint64_t> loaded = draw_terms(z, held, seed), added = draw_terms(z, held, seed),
                                     batched = draw_terms(z, held, seed);
    std::uint64_t sink = 0;
    auto start = Clock::now();
    for (const std::uint64_t t : loaded) sink += table.home_key(t);
    f.load_ns = std::min(f.load_ns, ns_per(start, loaded.size()));
    if (sink == 1) std::printf(" ");  // keeps the loads
    const std::size_t capacity = table.capacity();
    start = Clock::now();
    for (const std::uint64_t t : added) table.add(t, 11);
    f.add_ns = std::min(f.add_ns, ns_per(start, added.size()));
    start = Clock::now();
    sva::for_each_loaded(
        table, std::span<const std::uint64_t>(batched), [](std::uint64_t k) { return k; },
        [&](std::uint64_t t) { table.add(t, 11); });
    f.batched_ns = std::min(f.batched_ns, ns_per(start, batched.size()));
    if (table.capacity() != capacity) std::abort();  // the bound above keeps it
  }
  f.megabytes = static_cast<double>(table.bytes()) / 1e6;
  return f;
}

std::size_t arg(int argc, char** argv, int i, std::size_t fallback, std::size_t lo, std::size_t hi) {
  return sva::bench::whole_number_arg("hash_floor", argc, argv, i, fallback, lo, hi);
}

}  // namespace

int main(int argc, char** argv) {
  Sizes z;
  constexpr std::size_t kMost = std::size_t{1} << 28;
  z.pair_slots = arg(argc, argv, 1, z.pair_slots, 16, kMost);
  z.pair_adds = arg(argc, argv, 2, z.pair_adds, 1, kMost);
  z.pair_bins = arg(argc, argv, 3, z.pair_bins, 1, z.pair_adds);
  z.belief_bins = arg(argc, argv, 4, z.belief_bins, 1, kMost);
  z.terms = arg(argc, argv, 5, z.terms, 1, kMost);
  z.new_percent = static_cast<unsigned>(arg(argc, argv, 6, z.new_percent, 0, 100));
  z.repeats = static_cast<int>(arg(argc, argv, 7, static_cast<std::size_t>(z.repeats), 1, 1000));
  std::printf("pair table: %zu slots, %zu additions over %zu bins per pair: %.1f ns per addition\n", z.pair_slots,
              z.pair_adds, z.pair_bins, pair_table_ns(z));
  const BeliefFigures b = belief_ns(z);
  if (b.repeats == 0) {
    std::fprintf(stderr,
                 "hash_floor: a belief of %zu bins has no room for the new bins of %zu terms (%u%% new) before it "
                 "grows: ask fewer terms or a smaller share new\n",
                 z.belief_bins, z.terms, z.new_percent);
    return 1;
  }
  std::printf(
      "belief: %zu bins (%.0f MB), %zu terms, %u%% new: %.1f ns per addition, %.1f ns with each batch's slots loaded "
      "first, %.1f ns per independent load (best of %d)\n",
      z.belief_bins, b.megabytes, z.terms, z.new_percent, b.add_ns, b.batched_ns, b.load_ns, b.repeats);
  return 0;
}
