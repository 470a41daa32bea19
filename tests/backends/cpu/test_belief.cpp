// The CPU belief keeps its estimate's reductions up to date as it folds
// (maximum, per-object touched count, best bin and mass, top-k through the
// band of bins near the maximum). They must equal a full pass over the table.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <algorithm>

#include "backends/cpu/belief.hpp"
#include "belief/belief_math.hpp"
#include "recognition/fixture.hpp"

namespace {

// The reductions by brute force over every touched bin (the definition).
sva::BeliefSummary full_pass(const sva::Belief& b, const sva::PoseSpace& space) {
  sva::BeliefSummary s;
  const std::uint32_t n = space.objects();
  s.touched.assign(n, 0);
  s.touched_mass.assign(n, 0);
  s.best_offset.assign(n, 0);
  s.best_key.assign(n, 0);
  const std::vector<sva::BinOffset> all = b.table();
  for (const auto& x : all) s.max_offset = std::max(s.max_offset, x.offset);
  const std::uint32_t bits = sva::belief_math::mass_bits(space.bins_per_object());
  for (const auto& x : all) {
    const std::uint32_t o = sva::PoseSpace::object_of(x.key);
    s.touched_mass[o] += sva::belief_math::sva_exp2_neg_units(s.max_offset - x.offset, bits);
    if (s.touched[o] == 0 || x.offset > s.best_offset[o] || (x.offset == s.best_offset[o] && x.key < s.best_key[o])) {
      s.best_offset[o] = x.offset;
      s.best_key[o] = x.key;
    }
    ++s.touched[o];
  }
  return s;
}

std::vector<sva::BinOffset> full_top(const sva::Belief& b, std::size_t k) {
  std::vector<sva::BinOffset> all = b.table();
  std::sort(all.begin(), all.end(),
            [](const auto& x, const auto& y) { return x.offset != y.offset ? x.offset > y.offset : x.key < y.key; });
  all.resize(std::min(k, all.size()));
  return all;
}

// One pair's votes on a 2-object space: the first `peak` votes on one region (translation bins 25, rotation bins
// 4), the rest spread over `spread` translation bins per axis, each of a random mass.
sva::BinAccumulator sharp_votes(const sva::PoseSpace& space, sva::util::Rng& rng, int votes, int peak, int spread) {
  sva::BinAccumulator acc(4096);
  for (int v = 0; v < votes; ++v) {
    sva::BinIndex i;
    i.object = static_cast<std::uint32_t>(rng.below(2));
    const bool on_peak = v < peak;
    for (int a = 0; a < 3; ++a) {
      i.t[a] = on_peak ? 25 : static_cast<int>(rng.below(static_cast<std::uint64_t>(spread)));
      i.r[a] = on_peak ? 4 : static_cast<int>(rng.below(9));
    }
    acc.add(space.pack(i), static_cast<std::int64_t>(1 + rng.below(1u << 20)));
  }
  return acc;
}

// Folds `pairs` pairs of sharp_votes into the belief.
void fold_sharp_pairs(sva::Belief& belief, const sva::PoseSpace& space, sva::util::Rng& rng, int pairs, int votes,
                      int peak, int spread) {
  for (int pair = 0; pair < pairs; ++pair)
    REQUIRE(belief.add(belief.terms(sharp_votes(space, rng, votes, peak, spread)), 1));
}

}  // namespace

TEST_CASE("a pair's fold terms are its bins with votes, grouped by shard in slot order, each term the fold's") {
  const sva::PoseSpace space(sva::test::paper_space(), 3);
  const sva::Belief belief(space, 1e-6);
  const std::uint64_t eps = sva::belief_math::eps_units(1e-6);
  sva::util::Rng rng(11, 3);
  std::size_t terms = 0, left_out = 0;
  // A large pair first, then small ones: the thread's scratch, sized by the large one, must not leak its bins into
  // the next; bins whose votes sum to zero or below are no terms.
  for (const int votes : {20000, 300, 7, 1, 2500}) {
    sva::BinAccumulator acc(16);
    for (int v = 0; v < votes; ++v) {
      sva::BinIndex i;
      i.object = static_cast<std::uint32_t>(rng.below(3));
      for (int a = 0; a < 3; ++a) {
        i.t[a] = static_cast<int>(rng.below(40));
        i.r[a] = static_cast<int>(rng.below(9));
      }
      const std::uint64_t pick = rng.below(10);
      const std::int64_t m = pick == 0 ? 0 : pick == 1 ? -5 : static_cast<std::int64_t>(1 + rng.below(1u << 20));
      acc.add(space.pack(i), m);
    }
    // The definition: every bin with positive mass, in slot order, grouped by shard.
    std::uint64_t total = 0;
    std::vector<std::pair<std::uint64_t, std::uint64_t>> bins;
    acc.for_each([&](std::uint64_t k, std::int64_t m) {
      if (m <= 0) return;
      bins.emplace_back(k, static_cast<std::uint64_t>(m));
      total += static_cast<std::uint64_t>(m);
    });
    std::vector<sva::BinOffset> expected;
    for (std::size_t shard = 0; shard < sva::kBeliefShards; ++shard)
      for (const auto& [k, m] : bins)
        if (sva::belief_shard_of(k) == shard) expected.push_back({k, sva::belief_math::sva_fold_units(m, total, eps)});
    const sva::BeliefTerms got = belief.terms(acc);
    INFO(votes << " votes");
    CHECK(got.terms == expected);
    for (std::size_t shard = 0; shard < sva::kBeliefShards; ++shard)
      for (const sva::BinOffset& t : got.shard(shard)) CHECK(sva::belief_shard_of(t.key) == shard);
    terms += got.size();
    left_out += acc.size() - got.size();
  }
  CHECK(terms > 10000);    // not vacuous: pairs with terms
  CHECK(left_out > 1000);  // and bins without votes that are left out
}

TEST_CASE("the belief's incremental reductions equal a full pass, through folds that move the maximum far") {
  const sva::PoseSpace space(sva::test::paper_space(), 3);
  sva::Belief belief(space, 1e-6);
  sva::util::Rng rng(7, 1);
  for (int pair = 0; pair < 60; ++pair) {
    // Votes over a wide spread of bins, one region voted far more often, so
    // most bins drop out of the band as the maximum climbs.
    sva::BinAccumulator acc(256);
    for (int v = 0; v < 400; ++v) {
      sva::BinIndex i;
      i.object = static_cast<std::uint32_t>(rng.below(3));
      const bool peak = rng.uniform(0.0, 1.0) < 0.3;
      for (int a = 0; a < 3; ++a) {
        i.t[a] = peak ? 20 + static_cast<int>(rng.below(2)) : static_cast<int>(rng.below(50));
        i.r[a] = peak ? 4 : static_cast<int>(rng.below(9));
      }
      acc.add(space.pack(i), static_cast<std::int64_t>(1 + rng.below(1u << 20)));
    }
    REQUIRE(belief.add(belief.terms(acc), 1 + static_cast<std::uint32_t>(pair % 2)));
    if (pair % 7 == 0 || pair == 59) {
      INFO("after pair " << pair);
      CHECK(belief.summarise() == full_pass(belief, space));
      for (std::size_t k : {1u, 5u, 64u, 100000u}) CHECK(belief.best_bins(k) == full_top(belief, k));
    }
  }
  // Not vacuous: the maximum is far above most bins (many left the band).
  const sva::BeliefSummary s = belief.summarise();
  const std::vector<sva::BinOffset> all = belief.table();
  const auto far = std::count_if(all.begin(), all.end(), [&](const auto& x) {
    return s.max_offset - x.offset > (std::uint64_t{sva::belief_math::mass_bits(space.bins_per_object())} + 1) << 32;
  });
  CHECK(far > static_cast<long>(all.size() / 2));
  belief.reset();
  CHECK(belief.summarise() == full_pass(belief, space));
  CHECK(belief.best_bins(3).empty());
}

TEST_CASE("the best bins past the band, kept between folds as bins rise past their floor, equal a full sort") {
  // On 1 to 3 workers: each shard's pass runs on its own (Belief's threads), the same bins for any count.
  const unsigned threads = GENERATE(1u, 2u, 3u);
  INFO(threads << " threads");
  // A sharp belief: one region voted by every pair, so the band holds a few bins and the estimate's next modes
  // (dozens of bins) lie past it. Asked after every fold, the kept upper set must follow the bins that rise into it.
  const sva::PoseSpace space(sva::test::paper_space(), 2);
  sva::Belief belief(space, 1e-6, threads);
  sva::util::Rng rng(23, 1);
  for (int pair = 0; pair < 80; ++pair) {
    const sva::BinAccumulator acc = sharp_votes(space, rng, 600, 20, 40);
    REQUIRE(belief.add(belief.terms(acc), 1));
    INFO("after pair " << pair);
    for (std::size_t k : {48u, 300u}) REQUIRE(belief.best_bins(k) == full_top(belief, k));
    if (pair == 50) {  // forgetting drops the kept set; the next request makes it again
      const sva::BeliefSummary s = belief.summarise();
      belief.forget_below(s.max_offset > (std::uint64_t{40} << 32) ? s.max_offset - (std::uint64_t{40} << 32) : 0, {});
      REQUIRE(belief.best_bins(48) == full_top(belief, 48));
    }
  }
  // Not vacuous: the band held fewer bins than asked, so the answers came from past it.
  const sva::BeliefSummary s = belief.summarise();
  const std::uint64_t band = (std::uint64_t{sva::belief_math::mass_bits(space.bins_per_object())} + 1) << 32;
  const std::vector<sva::BinOffset> top = full_top(belief, 48);
  CHECK(s.max_offset - top.back().offset >= band);
}

TEST_CASE("a belief that sharpens prunes its band: the flat phase's bins stop costing memory and reads") {
  // A flat phase (thousands of bins, each within the band of the maximum), then pairs that vote one small region
  // of 128 bins, which falls in every shard: each shard's maximum climbs past the band's width, and every flat bin
  // leaves the band.
  const sva::PoseSpace space(sva::test::paper_space(), 2);
  sva::Belief belief(space, 1e-6);
  sva::util::Rng rng(31, 1);
  fold_sharp_pairs(belief, space, rng, 3, 3000, 0, 50);
  const std::size_t flat_bins = belief.touched(), flat_bytes = belief.table_bytes();
  for (int pair = 0; pair < 12; ++pair) {
    sva::BinAccumulator acc(256);
    for (int v = 0; v < 128; ++v) {
      sva::BinIndex i;
      i.object = static_cast<std::uint32_t>(v % 2);
      i.t[0] = 60 + (v / 2) % 4, i.t[1] = 60 + (v / 8) % 4, i.t[2] = 60 + v / 32;
      i.r[0] = i.r[1] = i.r[2] = 4;
      acc.add(space.pack(i), 1 << 20);
    }
    REQUIRE(belief.add(belief.terms(acc), 1));
  }
  INFO("bins " << flat_bins << " -> " << belief.touched() << ", bytes " << flat_bytes << " -> "
               << belief.table_bytes());
  REQUIRE(belief.touched() == flat_bins + 128);
  const sva::BeliefSummary s = belief.summarise();
  const std::vector<sva::BinOffset> top = full_top(belief, 129);
  const std::uint64_t band = (std::uint64_t{sva::belief_math::mass_bits(space.bins_per_object())} + 1) << 32;
  REQUIRE(top.size() == 129);
  REQUIRE(s.max_offset - top[128].offset >= band);  // not vacuous: every flat bin lies below the band
  // The band's tables, kept stale, held every flat bin: pruned, the belief is a third smaller.
  CHECK(belief.table_bytes() * 3 < flat_bytes * 2);
  CHECK(s == full_pass(belief, space));
  for (std::size_t k : {1u, 3u, 200u}) CHECK(belief.best_bins(k) == full_top(belief, k));
}

TEST_CASE("forgetting gives the memory back: the table is sized for the bins it keeps") {
  const sva::PoseSpace space(sva::test::paper_space(), 2);
  sva::Belief belief(space, 1e-6);
  sva::util::Rng rng(11, 1);
  fold_sharp_pairs(belief, space, rng, 40, 3000, 50, 50);  // a wide spread, one region every pair
  const std::size_t before_bins = belief.touched(), before_bytes = belief.table_bytes();
  const std::uint64_t max = belief.summarise().max_offset;
  const std::uint64_t below = max - (std::uint64_t{64} << 32);
  const std::size_t forgotten = belief.forget_below(below, {});
  const std::size_t kept = belief.touched();
  INFO("bins " << before_bins << " -> " << kept << ", bytes " << before_bytes << " -> " << belief.table_bytes());
  REQUIRE(forgotten + kept == before_bins);
  REQUIRE(kept * 16 < before_bins);  // not vacuous: most bins were hopeless
  // Half load at most, and a power of two: under 4 slots of 16 bytes per kept bin (and the band's table).
  CHECK(belief.table_bytes() < 4 * 16 * std::max<std::size_t>(kept, 512) + 64 * 1024);
  CHECK(belief.table_bytes() * 4 < before_bytes);
}

TEST_CASE("forgetting keeps the bins at or above the floor and the asked-for ones below it, and nothing else") {
  const sva::PoseSpace space(sva::test::paper_space(), 2);
  sva::Belief belief(space, 1e-6);
  sva::util::Rng rng(5, 1);
  fold_sharp_pairs(belief, space, rng, 30, 2000, 40, 40);
  const std::vector<sva::BinOffset> before = belief.table();
  const std::uint64_t below = belief.summarise().max_offset - (std::uint64_t{64} << 32);
  // Asked to keep: every 50th bin below the floor (one of each object at least), one above it, and keys never touched.
  std::vector<std::uint64_t> keep;
  std::size_t below_count = 0;
  for (const sva::BinOffset& b : before)
    if (b.offset < below && below_count++ % 50 == 0) keep.push_back(b.key);
  const auto above = std::find_if(before.begin(), before.end(), [&](const auto& b) { return b.offset >= below; });
  REQUIRE(above != before.end());
  keep.push_back(above->key);
  sva::BinIndex untouched;
  untouched.t[0] = 1;
  untouched.t[1] = 2;
  untouched.t[2] = 3;
  keep.push_back(space.pack(untouched));
  std::sort(keep.begin(), keep.end());
  REQUIRE(keep.size() > 20);
  const std::size_t forgotten = belief.forget_below(below, keep);
  std::vector<sva::BinOffset> expected;
  for (const sva::BinOffset& b : before)
    if (b.offset >= below || std::binary_search(keep.begin(), keep.end(), b.key)) expected.push_back(b);
  REQUIRE(expected.size() * 4 < before.size());  // not vacuous: most bins were forgotten
  CHECK(forgotten == before.size() - expected.size());
  CHECK(belief.table() == expected);  // the kept bins with their offsets; the untouched key stays untouched
  const sva::BeliefSummary s = belief.summarise(), full = full_pass(belief, space);
  CHECK(s.touched == full.touched);
  CHECK(s.best_key == full.best_key);
}

TEST_CASE("a belief that has just forgotten takes a large pair's terms at a few probes each") {
  // After forgetting, the belief's table is far smaller than a pair's vote table, whose slot order the terms
  // arrive in. Homes from the same hash bits made the small table be swept once per size ratio while it grew, each
  // sweep piling onto the last (21 probes per term on average on paper3d, up to 783; here 7.3 against 3.3).
  const sva::PoseSpace space(sva::test::paper_space(), 2);
  sva::Belief belief(space, 1e-6);
  sva::util::Rng rng(9, 1);
  fold_sharp_pairs(belief, space, rng, 10, 3000, 200, 40);
  belief.forget_below(belief.summarise().max_offset - (std::uint64_t{8} << 32), {});
  REQUIRE(belief.touched() < 1000);
  const sva::BinAccumulator wide = sharp_votes(space, rng, 60000, 200, 60);
  REQUIRE(wide.capacity() > 32 * belief.touched());
  const sva::BeliefTerms terms = belief.terms(wide);
  const std::uint64_t probes = belief.table_probes();
  REQUIRE(belief.add(terms, 1));
  const double per_term = static_cast<double>(belief.table_probes() - probes) / static_cast<double>(terms.size());
  INFO(terms.size() << " terms into a table of " << belief.touched() << " bins: " << per_term << " probes each");
  CHECK(per_term < 5.0);
}

TEST_CASE("one session's pairs added shard by shard in parallel give the belief that adding them one by one gives") {
  // Belief::add_all is the CPU reference's fold of one session (issue 52): every shard on its own worker. Offsets
  // are integer sums, so the tables, the reductions and the best bins must equal adding the pairs in order, for any
  // thread count; a pair without terms or with count 0 does not fold.
  const sva::PoseSpace space(sva::test::paper_space(), 3);
  sva::util::Rng rng(31, 1);
  sva::Belief reference(space, 1e-6);
  std::vector<sva::BeliefTerms> terms;
  std::vector<std::uint32_t> counts;
  for (int pair = 0; pair < 24; ++pair) {
    terms.push_back(reference.terms(sharp_votes(space, rng, 1500, 60, 30)));
    counts.push_back(pair == 5 ? 0u : 1u + static_cast<std::uint32_t>(pair % 2));
  }
  terms[9] = reference.terms(sva::BinAccumulator(16));  // no vote mass
  REQUIRE(terms[9].empty());
  for (std::size_t i = 0; i < terms.size(); ++i) CHECK(reference.add(terms[i], counts[i]) == (i != 5 && i != 9));
  for (unsigned threads : {1u, 2u, 8u}) {
    INFO(threads << " threads");
    sva::Belief belief(space, 1e-6, threads);
    std::vector<std::uint8_t> folded;
    std::vector<std::uint64_t> probes;
    belief.add_all(terms, counts, threads, &folded, &probes);
    CHECK(belief.table() == reference.table());
    CHECK(belief.summarise() == reference.summarise());
    CHECK(belief.summarise() == full_pass(belief, space));
    for (std::size_t k : {1u, 16u, 200u, 5000u}) CHECK(belief.best_bins(k) == full_top(reference, k));
    CHECK(belief.pairs_folded() == reference.pairs_folded());
    REQUIRE(folded.size() == terms.size());
    std::uint64_t probed = 0;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      CHECK((folded[i] != 0) == (i != 5 && i != 9));
      if (folded[i]) CHECK(probes[i] >= terms[i].size());  // at least one probe per term
      probed += probes[i];
    }
    CHECK(probed == belief.table_probes());
  }
  // Not vacuous: the pairs spread over every shard.
  for (std::size_t s = 0; s < sva::kBeliefShards; ++s) CHECK(terms[0].shard(s).size() > 0);
}

TEST_CASE("a belief's offsets of many keys, looked up in chunks on the workers, are each key's own, 0 when untouched") {
  // An estimate's neighbourhoods read about 10,000 bins at once (Belief::offsets, in chunks of 2,048 on the belief's
  // workers): every answer in its key's place, for any thread count, touched keys among untouched ones.
  const sva::PoseSpace space(sva::test::paper_space(), 3);
  sva::util::Rng rng(32, 1);
  for (unsigned threads : {1u, 2u, 8u}) {
    INFO(threads << " threads");
    sva::Belief belief(space, 1e-6, threads);
    for (int pair = 0; pair < 6; ++pair) belief.add(belief.terms(sharp_votes(space, rng, 1500, 60, 30)), 1);
    const std::vector<sva::BinOffset> table = belief.table();
    REQUIRE(table.size() > 3000);
    std::vector<std::uint64_t> keys;
    std::vector<std::uint64_t> expected;
    for (std::size_t i = 0; i < table.size(); ++i) {
      keys.push_back(table[i].key), expected.push_back(table[i].offset);
      if (i % 3 == 0 && (i + 1 == table.size() || table[i + 1].key != table[i].key + 1))
        keys.push_back(table[i].key + 1), expected.push_back(0);  // a key between touched ones: untouched
    }
    for (std::size_t i = keys.size(); i > 1; --i) {  // shuffled, the answers with their keys
      const std::size_t j = static_cast<std::size_t>(rng.uniform(0.0, static_cast<double>(i))) % i;
      std::swap(keys[i - 1], keys[j]);
      std::swap(expected[i - 1], expected[j]);
    }
    REQUIRE(keys.size() % 2048 != 0);  // a last chunk shorter than the others
    CHECK(belief.offsets(keys) == expected);
    CHECK(belief.offsets(std::span(keys).first(5)) ==
          std::vector<std::uint64_t>(expected.begin(), expected.begin() + 5));
    CHECK(belief.offsets({}).empty());
  }
}

TEST_CASE("a pair's votes in parts join into the terms of its votes summed whole, shard by shard on the workers") {
  // A pair cut into pieces (cpu_vote_backend.cpp) votes into one table per piece; Belief::terms joins the parts
  // shard by shard. Each bin's mass is the sum of its parts', so the terms must be the whole pair's: the same bins
  // and units in every shard (in another order within it), for any thread count.
  const sva::PoseSpace space(sva::test::paper_space(), 3);
  const sva::Belief belief(space, 1e-6);
  sva::util::Rng rng(8, 2);
  for (const std::size_t parts : {1u, 2u, 5u}) {
    sva::BinAccumulator whole(16);
    std::vector<sva::BinAccumulator> part(parts, sva::BinAccumulator(16));
    for (int v = 0; v < 30000; ++v) {
      sva::BinIndex i;
      i.object = static_cast<std::uint32_t>(rng.below(3));
      for (int a = 0; a < 3; ++a) {
        i.t[a] = static_cast<int>(rng.below(12));  // few bins: most are met by several parts
        i.r[a] = static_cast<int>(rng.below(9));
      }
      const auto m = static_cast<std::int64_t>(1 + rng.below(1u << 20));
      whole.add(space.pack(i), m);
      part[rng.below(parts)].add(space.pack(i), m);
    }
    std::vector<sva::ShardedVotes> sharded(parts);
    for (std::size_t p = 0; p < parts; ++p) sva::ShardedVotes::of(part[p], &sharded[p]);
    const sva::BeliefTerms expected = belief.terms(whole);
    for (const unsigned threads : {1u, 4u}) {
      INFO(parts << " parts, " << threads << " threads");
      sva::BeliefTerms got;
      std::uint64_t probes = 0;
      belief.terms(sharded, threads, &got, &probes);
      CHECK(got.begin == expected.begin);
      for (std::size_t s = 0; s < sva::kBeliefShards; ++s) {
        std::vector<sva::BinOffset> a(got.shard(s).begin(), got.shard(s).end());
        std::vector<sva::BinOffset> b(expected.shard(s).begin(), expected.shard(s).end());
        const auto by_key = [](const sva::BinOffset& x, const sva::BinOffset& y) { return x.key < y.key; };
        std::sort(a.begin(), a.end(), by_key);
        std::sort(b.begin(), b.end(), by_key);
        CHECK(a == b);
      }
      CHECK(probes >= got.size());  // each part's bin added once
    }
    CHECK(expected.size() > 10000);  // not vacuous
  }
  // No parts, or parts without votes: no terms.
  sva::BeliefTerms none;
  std::uint64_t probes = 1;
  belief.terms(std::span<const sva::ShardedVotes>(), 2, &none, &probes);
  CHECK(none.empty());
  CHECK(probes == 0);
  std::vector<sva::ShardedVotes> empty(2);
  for (sva::ShardedVotes& e : empty) sva::ShardedVotes::of(sva::BinAccumulator(16), &e);
  belief.terms(empty, 2, &none, &probes);
  CHECK(none.empty());
}
