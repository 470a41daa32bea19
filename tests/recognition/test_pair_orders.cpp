// Eq 5's two orders of a pair, and one alignment per (observed pair, map pair),
// on readings of the Embree simulator (the built-in "tiny" scene) with a map
// trained by the real builder: soft classes and the distance interpolation put
// one training pair under several keys, which is what these rules are about.
#include <catch2/catch.hpp>

#include <set>
#include <utility>

#include <sva/sim/simulate.hpp>

#include "backends/vote_backend.hpp"
#include "fixture.hpp"
#include "map/map_builder.hpp"
#include "map/pair_keys.hpp"
#include "reading/observed_reading.hpp"

namespace {

struct SimWorld {
  std::shared_ptr<sva::PairMap> map;
  std::vector<sva::ObservedReading> observed;  // test readings under one pose
  std::vector<std::uint32_t> object;
};

const SimWorld& sim_world() {
  static const SimWorld w = [] {
    const sva::Scene scene = sva::load_scene("tiny");
    sva::sim::SimulateOptions so;
    so.train_per_object = 60;
    so.test_per_object = 12;
    so.seed = 3;
    const sva::sim::SimulatedData data = sva::sim::simulate(scene, so);
    sva::TrainOptions to;
    to.clusters = 6;
    const sva::TrainParameters p = sva::resolve_train_parameters(scene, to);
    SimWorld out;
    out.map = sva::train_pair_map(data.train, p, nullptr);
    const sva::RigidPose pose = sva::test::random_pose(5, 40.0);
    for (const sva::Sample& s : data.test.samples) {
      if (s.reading.status != sva::ControllerStatus::converged) continue;
      sva::Reading r = s.reading;
      r.position = pose.apply(r.position);
      r.normal = pose.rotate(r.normal);
      r.x_axis = pose.rotate(r.x_axis);
      out.observed.push_back(sva::describe_reading(*out.map, r, "test reading"));
      out.object.push_back(s.object);
    }
    return out;
  }();
  return w;
}

sva::PairQuery query(const sva::PairMap& map, const sva::ObservedReading& a, const sva::ObservedReading& b,
                     sva::VoteBatch* batch) {
  sva::PairQuery q;
  for (int k = 0; k < 3; ++k) {
    q.a.position[k] = static_cast<float>(a.position[k]);
    q.a.normal[k] = static_cast<float>(a.normal[k]);
    q.b.position[k] = static_cast<float>(b.position[k]);
    q.b.normal[k] = static_cast<float>(b.normal[k]);
  }
  q.a.norm_conf = a.norm_conf;
  q.b.norm_conf = b.norm_conf;
  q.key_begin = static_cast<std::uint32_t>(batch->keys.size());
  sva::for_each_query_key(a.classes, b.classes, map.distance.bins(glm::length(b.position - a.position)), map.key_space,
                          [&](sva::PairKeyWeight k) { batch->keys.push_back(k); });
  q.key_end = static_cast<std::uint32_t>(batch->keys.size());
  return q;
}

}  // namespace

TEST_CASE("both orders of an observed pair cast the same votes, bin for bin, on simulated readings") {
  const SimWorld& w = sim_world();
  REQUIRE(w.observed.size() >= 16);
  const sva::PoseSpace space(sva::test::paper_space(), static_cast<std::uint32_t>(w.map->objects.size()));
  auto cpu = sva::make_cpu_vote_backend(*w.map, space, {});
  sva::VoteBatch batch;
  for (std::size_t i = 0; i < w.observed.size(); ++i)
    for (std::size_t j = i + 1; j < w.observed.size(); ++j) {
      if (w.object[i] != w.object[j]) continue;
      batch.pairs.push_back(query(*w.map, w.observed[i], w.observed[j], &batch));
      batch.pairs.push_back(query(*w.map, w.observed[j], w.observed[i], &batch));
    }
  batch.sessions = 1;
  const std::vector<sva::PairVotes> votes = cpu->vote(batch);
  std::size_t voted = 0, several_keys = 0;
  for (std::size_t p = 0; p < votes.size(); p += 2) {
    const sva::PairVotes& f = votes[p];
    const sva::PairVotes& r = votes[p + 1];
    INFO("observed pair " << p / 2);
    CHECK(f.keys == r.keys);
    CHECK(f.mass == r.mass);
    CHECK(f.matches == r.matches);
    CHECK(f.votes == r.votes);
    CHECK(f.votes_outside == r.votes_outside);
    CHECK(f.votes_zero == r.votes_zero);
    if (!f.keys.empty()) ++voted;
    if (batch.pairs[p].key_end - batch.pairs[p].key_begin > 1) ++several_keys;
  }
  // Not vacuous: most pairs vote, and many look up more than one key.
  CHECK(voted * 2 > votes.size() / 2);
  CHECK(several_keys > 0);
}

TEST_CASE("a map pair stored under several of an observed pair's keys is aligned once") {
  const SimWorld& w = sim_world();
  const sva::PairMap& m = *w.map;
  const sva::PoseSpace space(sva::test::paper_space(), static_cast<std::uint32_t>(m.objects.size()));
  auto cpu = sva::make_cpu_vote_backend(m, space, {});
  std::size_t shared = 0;
  for (std::size_t i = 0; i + 1 < w.observed.size(); ++i) {
    const std::size_t j = i + 1;
    if (w.object[i] != w.object[j]) continue;
    sva::VoteBatch batch;
    batch.sessions = 1;
    batch.pairs.push_back(query(m, w.observed[i], w.observed[j], &batch));
    // The distinct map pairs under the pair's keys, and how many (key, entry) matches they make.
    std::set<std::pair<std::uint32_t, std::uint32_t>> distinct;
    std::size_t entries = 0;
    for (std::uint32_t k = batch.pairs[0].key_begin; k < batch.pairs[0].key_end; ++k) {
      const auto [b, e] = m.find(batch.keys[k].key);
      for (std::uint32_t x = b; x < e; ++x) {
        ++entries;
        // A reversed key matches the stored pair with its ends swapped.
        if (batch.keys[k].reversed)
          distinct.insert({m.entry_b[x], m.entry_a[x]});
        else
          distinct.insert({m.entry_a[x], m.entry_b[x]});
      }
    }
    const sva::PairVotes v = cpu->vote(batch)[0];
    INFO("observed pair " << i);
    // Every distinct map pair of these readings is far enough apart to align.
    CHECK(v.matches == distinct.size());
    shared += entries - distinct.size();
  }
  CHECK(shared > 0);  // some map pairs did sit under several keys
}
