#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <sstream>
#include <string>

#include "backends/vulkan/vulkan_engine.hpp"
#include "recognition/fixture.hpp"
#include "vk_test_support.hpp"

using namespace sva;

namespace {

// Several sessions, each a different pose of a different object, with a few
// readings each; returns the batch of the last readings' pairs.
VoteBatch make_batch(const test::World& w, const PoseSpace& space, const test::WorldSpec& spec, int sessions,
                     int readings, std::vector<std::unique_ptr<BayesFilter>>* filters) {
  VoteBatch batch;
  static std::vector<std::unique_ptr<VoteBackend>> backends;  // outlive the filters
  for (int s = 0; s < sessions; ++s) {
    const int object = s % spec.objects;
    const RigidPose pose =
        test::random_pose(100 + static_cast<std::uint64_t>(s), spec.planar ? 8.0 : 150.0, spec.planar);
    backends.push_back(make_cpu_vote_backend(*w.map, space, {}));
    auto f = std::make_unique<BayesFilter>(*w.map, space, FilterOptions{}, *backends.back());
    for (int r = 0; r + 1 < readings; ++r)
      f->add(test::observe(w.objects[object][static_cast<std::size_t>(r * 7 % spec.points)], pose));
    f->queue_pairs(test::observe(w.objects[object][static_cast<std::size_t>(readings * 7 % spec.points)], pose),
                   static_cast<std::uint32_t>(s), &batch);
    if (filters) filters->push_back(std::move(f));
  }
  return batch;
}

void require_identical(const std::vector<PairVotes>& cpu, const std::vector<PairVotes>& gpu) {
  REQUIRE(cpu.size() == gpu.size());
  std::uint64_t votes = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    INFO("pair " << i);
    CHECK(cpu[i].matches == gpu[i].matches);
    CHECK(cpu[i].votes == gpu[i].votes);
    CHECK(cpu[i].votes_outside == gpu[i].votes_outside);
    CHECK(cpu[i].keys == gpu[i].keys);
    CHECK(cpu[i].mass == gpu[i].mass);
    // The work counted: the same map entries and bins; every bin's key was scattered at least once on the
    // device, with a compare-and-swap per probe and one add per (pre-aggregated) vote.
    CHECK(cpu[i].entries == gpu[i].entries);
    CHECK(cpu[i].bins == gpu[i].bins);
    CHECK(gpu[i].bins == gpu[i].keys.size());
    CHECK(gpu[i].table_probes >= gpu[i].bins);
    CHECK(gpu[i].atomics >= gpu[i].table_probes + gpu[i].bins);
    CHECK(gpu[i].atomics <= 2 * gpu[i].table_probes);  // an add follows each successful probe, at most one per probe
    CHECK(cpu[i].atomics == 0);
    votes += cpu[i].votes;
  }
  CHECK(votes > 1000);  // the comparison covered real work
}

}  // namespace

TEST_CASE("Vulkan votes equal the CPU reference bit for bit (spatial, several sessions)") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VoteBatch batch = make_batch(w, space, spec, 4, 5, nullptr);
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {});
  require_identical(cpu->vote(batch), gpu->vote(batch));
  CHECK(gpu->statistics().validation_messages == 0);
}

TEST_CASE("Vulkan votes equal the CPU reference on a planar space with pruned objects") {
  const test::WorldSpec spec = test::planar_spec();
  auto w = test::make_world(spec);
  PoseSpace space(test::letters_space(), static_cast<std::uint32_t>(spec.objects));
  VoteBatch batch = make_batch(w, space, spec, 3, 6, nullptr);
  batch.object_active.assign(std::size_t{batch.sessions} * space.objects(), 1);
  batch.object_active[1] = 0;  // session 0 no longer votes for object 1
  VoteSettings vs;
  vs.likelihood_cutoff = 0.05f;
  auto cpu = make_cpu_vote_backend(*w.map, space, vs);
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, vs);
  require_identical(cpu->vote(batch), gpu->vote(batch));
}

TEST_CASE("Vulkan backend: tiny map chunks and a tiny table still give the exact CPU answer") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VoteBatch batch = make_batch(w, space, spec, 2, 4, nullptr);
  VulkanBackendOptions o;
  o.max_chunk_entries = 97;    // 64-entry chunks (a power of two): many (lavapipe's 128 MiB rule, exercised small)
  o.initial_table_slots = 64;  // overflow: the table grows and the batch reruns
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {}, o);
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  require_identical(cpu->vote(batch), gpu->vote(batch));
  const BackendStats st = gpu->statistics();
  CHECK(st.map_chunks > 10);
  CHECK(st.table_grows >= 1);
  CHECK(st.validation_messages == 0);
}

TEST_CASE("Vulkan backend folds into identical beliefs through update_sessions") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {});
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  std::vector<std::unique_ptr<BayesFilter>> fc, fg;
  std::vector<RigidPose> poses;
  for (int s = 0; s < 3; ++s) {
    fc.push_back(std::make_unique<BayesFilter>(*w.map, space, FilterOptions{}, *cpu));
    fg.push_back(std::make_unique<BayesFilter>(*w.map, space, FilterOptions{}, *gpu));
    poses.push_back(test::random_pose(500 + static_cast<std::uint64_t>(s), 150.0));
  }
  for (int r = 0; r < 5; ++r) {
    std::vector<ObservedReading> obs;
    for (int s = 0; s < 3; ++s)
      obs.push_back(
          test::observe(w.objects[static_cast<std::size_t>(s)][static_cast<std::size_t>(r * 11 % spec.points)],
                        poses[static_cast<std::size_t>(s)]));
    std::vector<BayesFilter*> pc, pg;
    for (int s = 0; s < 3; ++s) {
      pc.push_back(fc[static_cast<std::size_t>(s)].get());
      pg.push_back(fg[static_cast<std::size_t>(s)].get());
    }
    update_sessions(pc, obs);
    update_sessions(pg, obs);
  }
  for (int s = 0; s < 3; ++s) {
    const auto a = test::candidates(*fc[static_cast<std::size_t>(s)], 5),
               b = test::candidates(*fg[static_cast<std::size_t>(s)], 5);
    CHECK(a.object == b.object);
    CHECK(a.object_probability == b.object_probability);
    REQUIRE(a.top.size() == b.top.size());
    for (std::size_t i = 0; i < a.top.size(); ++i) CHECK(a.top[i].probability == b.top[i].probability);
    const BeliefState& bc = fc[static_cast<std::size_t>(s)]->belief();
    const BeliefState& bg = fg[static_cast<std::size_t>(s)]->belief();
    CHECK(bc.pairs_folded() == bg.pairs_folded());
    CHECK(bc.touched() == bg.touched());
    CHECK(bc.table() == bg.table());
  }
}

TEST_CASE("Vulkan backend: staged uploads into unmapped device memory give the exact CPU answer") {
  // As on a GPU without a large BAR: the map, the vote table and the beliefs
  // sit in device memory the host cannot map; uploads and read-backs are copies.
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VulkanBackendOptions o;
  o.force_staging = true;
  o.initial_table_slots = 64;   // a growth and a rerun on the staged path too
  o.initial_belief_slots = 64;  // and belief growth
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {}, o);
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  require_identical(cpu->vote(make_batch(w, space, spec, 2, 4, nullptr)),
                    gpu->vote(make_batch(w, space, spec, 2, 4, nullptr)));
  BayesFilter fc(*w.map, space, FilterOptions{}, *cpu), fg(*w.map, space, FilterOptions{}, *gpu);
  const RigidPose pose = test::random_pose(77, 150.0);
  for (int r = 0; r < 6; ++r) {
    const ObservedReading obs = test::observe(w.objects[1][static_cast<std::size_t>(r * 13 % spec.points)], pose);
    fc.add(obs);
    fg.add(obs);
  }
  CHECK(fg.belief().table() == fc.belief().table());
  CHECK(test::candidates(fg, 3).object_probability == test::candidates(fc, 3).object_probability);
  CHECK(gpu->statistics().validation_messages == 0);
}

TEST_CASE("Vulkan backends on one map share one engine: one device, one uploaded map") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  const std::size_t before = VulkanEngine::alive();
  auto a = test::vulkan_backend_or_skip(*w.map, space, {});
  auto b = test::vulkan_backend_or_skip(*w.map, space, {});
  CHECK(VulkanEngine::alive() == before + 1);
  VulkanBackendOptions chunked;
  chunked.max_chunk_entries = 97;  // another upload of the map: another engine
  auto c = test::vulkan_backend_or_skip(*w.map, space, {}, chunked);
  CHECK(VulkanEngine::alive() == before + 2);
  {
    // Sessions of both backends update alternately and stay exact (the
    // sessions end before their backends, as the API requires).
    auto cpu = make_cpu_vote_backend(*w.map, space, {});
    BayesFilter fa(*w.map, space, FilterOptions{}, *a), fb(*w.map, space, FilterOptions{}, *b),
        fr(*w.map, space, FilterOptions{}, *cpu);
    const RigidPose pose = test::random_pose(78, 150.0);
    for (int r = 0; r < 5; ++r) {
      const ObservedReading obs = test::observe(w.objects[2][static_cast<std::size_t>(r * 5 % spec.points)], pose);
      fa.add(obs);
      fb.add(obs);
      fr.add(obs);
    }
    CHECK(fa.belief().table() == fr.belief().table());
    CHECK(fb.belief().table() == fr.belief().table());
  }
  a.reset();
  b.reset();
  c.reset();
  CHECK(VulkanEngine::alive() == before);
}

TEST_CASE("Vulkan backend: the vote kernel without subgroup pre-aggregation gives the same exact answer") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VoteBatch batch = make_batch(w, space, spec, 3, 5, nullptr);
  VulkanBackendOptions o;
  o.portable_vote_kernel = true;
  o.initial_table_slots = 64;
  auto portable = test::vulkan_backend_or_skip(*w.map, space, {}, o);
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  require_identical(cpu->vote(batch), portable->vote(batch));
  CHECK(portable->statistics().device.find("subgroup") == std::string::npos);
  CHECK(portable->statistics().validation_messages == 0);
}

namespace {

// The batch's pair p alone, with its keys [first, last) of the pair's own.
VoteBatch sub_batch(const VoteBatch& batch, std::size_t p, std::uint32_t first, std::uint32_t last) {
  VoteBatch sub;
  sub.sessions = batch.sessions;
  sub.object_active = batch.object_active;
  PairQuery q = batch.pairs[p];
  sub.keys.assign(batch.keys.begin() + q.key_begin + first, batch.keys.begin() + q.key_begin + last);
  q.key_begin = 0;
  q.key_end = last - first;
  sub.pairs.push_back(q);
  return sub;
}

bool same_votes(const std::vector<PairVotes>& a, const std::vector<PairVotes>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].matches != b[i].matches || a[i].votes != b[i].votes || a[i].keys != b[i].keys || a[i].mass != b[i].mass)
      return false;
  return true;
}

// How the masses of two equal bin lists differ, in units: "bins B, differing D (GPU - CPU: d1 d2 ...)".
std::string mass_differences(const std::vector<PairVotes>& cpu, const std::vector<PairVotes>& gpu) {
  std::ostringstream os;
  std::size_t bins = 0, differing = 0, shown = 0;
  for (std::size_t p = 0; p < cpu.size() && p < gpu.size(); ++p) {
    if (cpu[p].keys != gpu[p].keys) return "bins differ";
    for (std::size_t i = 0; i < cpu[p].mass.size(); ++i, ++bins) {
      if (cpu[p].mass[i] == gpu[p].mass[i]) continue;
      if (++differing <= 12) os << (shown++ ? " " : "") << gpu[p].mass[i] - cpu[p].mass[i] << "/" << cpu[p].mass[i];
    }
  }
  return std::to_string(differing) + " of " + std::to_string(bins) +
         " bins differ (GPU - CPU / CPU units: " + os.str() + ")";
}

}  // namespace

// Where the backends disagree, which scale shows it first: every key of every pair alone (the single-key path:
// entries, alignment, scatter), every pair with all its keys (the owner rule across a pair's keys), the whole batch
// (pairs sharing the vote table). Prints the count of disagreeing sub-batches at each scale.
TEST_CASE("Vulkan votes equal the CPU reference for each key alone, each pair alone and the whole batch") {
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), static_cast<std::uint32_t>(spec.objects));
  VoteBatch batch = make_batch(w, space, spec, 4, 5, nullptr);
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {});
  std::size_t keys = 0, keys_differing = 0, multi_key_pairs = 0, pairs_differing = 0;
  for (std::size_t p = 0; p < batch.pairs.size(); ++p) {
    const std::uint32_t n = batch.pairs[p].key_end - batch.pairs[p].key_begin;
    for (std::uint32_t k = 0; k < n; ++k, ++keys) {
      const VoteBatch one = sub_batch(batch, p, k, k + 1);
      const auto c = cpu->vote(one), g = gpu->vote(one);
      if (same_votes(c, g)) continue;
      if (keys_differing++ < 3) WARN("pair " << p << " key " << k << ": " << mass_differences(c, g));
    }
    multi_key_pairs += n > 1;
    const VoteBatch whole_pair = sub_batch(batch, p, 0, n);
    if (!same_votes(cpu->vote(whole_pair), gpu->vote(whole_pair))) ++pairs_differing;
  }
  const bool batch_differs = !same_votes(cpu->vote(batch), gpu->vote(batch));
  WARN("on " << gpu->statistics().device << ": " << keys_differing << " of " << keys << " single keys, "
             << pairs_differing << " of " << batch.pairs.size() << " pairs (" << multi_key_pairs
             << " with several keys) and " << (batch_differs ? "the" : "not the") << " whole batch differ");
  CHECK(keys > batch.pairs.size());  // some pair has several keys: the owner rule is exercised
  CHECK(keys_differing == 0);
  CHECK(pairs_differing == 0);
  CHECK_FALSE(batch_differs);
}

// The smallest disagreement to read: a map of 6 points of one object, so that a key holds one or two map pairs and
// a bin one or two votes; prints every bin of the first keys whose votes differ (CPU -> GPU units).
TEST_CASE("Vulkan votes equal the CPU reference on a map of a few pairs, bin by bin") {
  test::WorldSpec spec;
  spec.objects = 1;
  spec.points = 6;
  auto w = test::make_world(spec);
  PoseSpace space(test::paper_space(), 1);
  auto cpu = make_cpu_vote_backend(*w.map, space, {});
  auto gpu = test::vulkan_backend_or_skip(*w.map, space, {});
  BayesFilter f(*w.map, space, FilterOptions{}, *cpu);
  const RigidPose pose = test::random_pose(5, 150.0);
  for (int r = 0; r < 5; ++r) f.add(test::observe(w.objects[0][static_cast<std::size_t>(r)], pose));
  VoteBatch batch;
  f.queue_pairs(test::observe(w.objects[0][5], pose), 0, &batch);
  std::size_t keys = 0, differing = 0;
  for (std::size_t p = 0; p < batch.pairs.size(); ++p) {
    for (std::uint32_t k = 0; k < batch.pairs[p].key_end - batch.pairs[p].key_begin; ++k, ++keys) {
      const VoteBatch one = sub_batch(batch, p, k, k + 1);
      const auto c = cpu->vote(one), g = gpu->vote(one);
      if (same_votes(c, g)) continue;
      if (differing++ >= 4) continue;
      std::ostringstream os;
      os << "pair " << p << " key " << k << " (weight " << one.keys[0].weight << "): " << c[0].matches << " matches, "
         << c[0].votes << " votes, " << c[0].mass.size() << " bins (CPU -> GPU units):";
      for (std::size_t i = 0; i < c[0].mass.size() && i < g[0].mass.size() && i < 40; ++i)
        os << " " << c[0].mass[i] << (c[0].mass[i] == g[0].mass[i] ? "" : "->" + std::to_string(g[0].mass[i]));
      WARN(os.str());
    }
  }
  CHECK(keys > 0);
  CHECK(differing == 0);
}
