#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <tuple>

#include "appearance/appearance_baseline.hpp"
#include "appearance/synthetic.hpp"
#include "map/map_access.hpp"
#include "map/map_builder.hpp"
#include "map/map_file.hpp"
#include "map/pair_map.hpp"
#include "test_support.hpp"

using namespace sva;
using Catch::Contains;

namespace {

std::vector<char> bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const std::filesystem::path& p, const std::vector<char>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(b.data(), static_cast<std::streamsize>(b.size()));
}

const Dataset& data() {
  static const Dataset d = test::synthetic_dataset(3, 60);
  return d;
}

// The map's tests read the pair index; the calibration is tests/calibration's (and thread independence's, below).
TrainOptions no_calibration() {
  TrainOptions o;
  o.calibrate = false;
  return o;
}

const Map& trained() {
  static const Map m = Map::train(data(), no_calibration());
  return m;
}

}  // namespace

TEST_CASE("map: training on a synthetic dataset gives a valid, consistent map") {
  TrainReport rep;
  const Map map = Map::train(data(), no_calibration(), &rep);
  const PairMap& m = MapAccess::pair_map(map);
  CHECK(map.objects() == 3);
  CHECK(map.classes() == 6);
  CHECK(map.readings() == 180);
  CHECK(rep.readings_used == 180);
  CHECK(map.entries() > 1000);
  CHECK(map.scene_name() == "synthetic");
  CHECK(map.object_names() == std::vector<std::string>{"obj0", "obj1", "obj2"});
  CHECK(m.ambiguity >= 1.0);
  CHECK_NOTHROW(validate_pair_map(m, "trained"));
  // Every ordered same-object pair in range appears, and under the right keys.
  for (std::size_t e = 0; e < m.entry_count(); e += 97) {
    const auto a = m.entry_a[e], b = m.entry_b[e];
    const double d = std::hypot(m.readings.px[a] - m.readings.px[b], m.readings.py[a] - m.readings.py[b],
                                m.readings.pz[a] - m.readings.pz[b]);
    CHECK(d >= m.distance.min_mm);
    CHECK(d <= m.distance.max_mm);
    const auto key_index =
        static_cast<std::size_t>(std::upper_bound(m.offsets.begin(), m.offsets.end(), e) - m.offsets.begin()) - 1;
    const std::uint32_t bin = m.keys[key_index] % m.distance.count;
    bool bin_ok = false;
    for (const auto& bw : m.distance.bins(d)) bin_ok = bin_ok || bw.bin == bin;
    CHECK(bin_ok);
    const auto range = m.find(m.keys[key_index]);
    CHECK(range.first <= e);
    CHECK(e < range.second);
  }
  CHECK(m.find(0xffffffffu).first == m.find(0xffffffffu).second);
  // Weights of one ordered pair over all its keys sum to 1 (class and bin weights each sum to 1).
  double pair_sum = 0;
  for (std::size_t e = 0; e < m.entry_count(); ++e)
    if (m.entry_a[e] == m.entry_a[0] && m.entry_b[e] == m.entry_b[0]) pair_sum += m.entry_weight[e];
  CHECK(pair_sum == Approx(1.0).margin(1e-4));
}

TEST_CASE("map: pair_readings pairs a seeded draw of each object's readings and keeps the rest as surface") {
  TrainOptions o = no_calibration();
  o.pair_readings = 20;
  TrainReport rep;
  const Map map = Map::train(data(), o, &rep);
  const PairMap& m = MapAccess::pair_map(map);
  CHECK(map.readings() == 180);  // every reading is kept: the fine pose and the surface check read them all
  CHECK(rep.readings_used == 180);
  CHECK(rep.readings_paired == 60);
  CHECK(map.summary().readings_paired == 60);
  CHECK_NOTHROW(validate_pair_map(m, "paired subset"));
  // The paired readings come first in their object's group, and no entry reaches past them.
  std::vector<std::size_t> first(4, 0);
  for (std::size_t i = 0; i < m.readings.size(); ++i) first[m.readings.object[i] + 1] = i + 1;
  for (std::size_t o2 = 1; o2 < first.size(); ++o2) first[o2] = std::max(first[o2], first[o2 - 1]);
  for (std::size_t e = 0; e < m.entry_count(); ++e) {
    const std::uint32_t a = m.entry_a[e], b = m.entry_b[e], obj = m.readings.object[a];
    CHECK(a - first[obj] < 20);
    CHECK(b - first[obj] < 20);
  }
  // A third of the readings make about a ninth of the pairs.
  CHECK(map.entries() < trained().entries() / 5);
  CHECK(map.entries() > trained().entries() / 20);
  // Drawn, not the first ones: another seed pairs other readings; the same seed, on any thread count, the same.
  TrainOptions other = o;
  other.seed = 2;
  const Map reseeded = Map::train(data(), other);
  CHECK(MapAccess::pair_map(reseeded).readings.px != m.readings.px);
  TrainOptions one_thread = o;
  one_thread.threads = 1;
  const Map again = Map::train(data(), one_thread);
  CHECK(MapAccess::pair_map(again).entry_a == m.entry_a);
  CHECK(MapAccess::pair_map(again).readings.px == m.readings.px);
  // More than an object holds pairs them all: the same pairs as the full map.
  o.pair_readings = 1000;
  CHECK(Map::train(data(), o).entries() == trained().entries());
  o.pair_readings = 1;
  CHECK_THROWS_WITH(Map::train(data(), o), Contains("pair readings 1") && Contains("two readings"));
}

TEST_CASE("map: the CSR index equals a naive enumeration of the pairs") {
  PairMap m;
  m.objects.resize(2);
  m.distance = {5, 0.0, 10.0};
  m.key_space = {3, 5};
  util::Rng rng(12);
  std::vector<std::vector<ClassWeight>> classes;
  for (int i = 0; i < 40; ++i) {
    m.readings.object.push_back(i < 25 ? 0 : 1);
    m.readings.px.push_back(static_cast<float>(rng.uniform(0, 8)));
    m.readings.py.push_back(static_cast<float>(rng.uniform(0, 8)));
    m.readings.pz.push_back(0.0f);
    for (auto* v : {&m.readings.nx, &m.readings.ny}) v->push_back(0.0f);
    m.readings.nz.push_back(1.0f);
    m.readings.norm_conf.push_back(0.5f);
    if (i % 3 == 0)
      classes.push_back({{static_cast<std::uint32_t>(i % 3), 1.0f}});
    else
      classes.push_back({{0, 0.25f}, {2, 0.75f}});
  }
  build_pair_index(m, classes, 2, false);
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, float>> naive;
  for (std::uint32_t a = 0; a < 40; ++a)
    for (std::uint32_t b = a + 1; b < 40; ++b) {  // each unordered pair once (map version 2)
      if (m.readings.object[a] != m.readings.object[b]) continue;
      const double d =
          std::hypot(double(m.readings.px[a]) - m.readings.px[b], double(m.readings.py[a]) - m.readings.py[b], 0.0);
      for (const auto& ca : classes[a])
        for (const auto& cb : classes[b])
          for (const auto& bw : m.distance.bins(d))
            naive.emplace_back(m.key_space.pack(ca.cls, cb.cls, bw.bin), a, b, ca.weight * cb.weight * bw.weight);
    }
  std::stable_sort(naive.begin(), naive.end(),
                   [](const auto& x, const auto& y) { return std::get<0>(x) < std::get<0>(y); });
  REQUIRE(m.entry_count() == naive.size());
  for (std::size_t e = 0; e < naive.size(); ++e) {
    const auto key_index =
        static_cast<std::size_t>(std::upper_bound(m.offsets.begin(), m.offsets.end(), e) - m.offsets.begin()) - 1;
    CHECK(m.keys[key_index] == std::get<0>(naive[e]));
    CHECK(m.entry_a[e] == std::get<1>(naive[e]));
    CHECK(m.entry_b[e] == std::get<2>(naive[e]));
    CHECK(m.entry_weight[e] == std::get<3>(naive[e]));
  }
  CHECK(std::is_sorted(m.keys.begin(), m.keys.end()));
}

TEST_CASE("map: save/load round trip is bit-exact, and training is thread-independent") {
  const auto dir = test::temp_dir("map-roundtrip");
  TrainOptions o;
  o.threads = 1;
  o.calibration_sessions = 10;  // the calibration's sessions too: the same bytes for 1 and 2 threads
  o.calibration_readings = 4;
  Map::train(data(), o).save(dir / "t1.svamap");
  o.threads = 2;
  Map::train(data(), o).save(dir / "t2.svamap");
  const auto b1 = bytes_of(dir / "t1.svamap");
  CHECK(b1 == bytes_of(dir / "t2.svamap"));
  const Map loaded = Map::load(dir / "t1.svamap");
  loaded.save(dir / "again.svamap");
  CHECK(b1 == bytes_of(dir / "again.svamap"));
  CHECK(MapAccess::pair_map(loaded).entry_weight == MapAccess::pair_map(trained()).entry_weight);
  CHECK(MapAccess::pair_map(loaded).appearance.medoids == MapAccess::pair_map(trained()).appearance.medoids);
  CHECK(loaded.scene_hash() == trained().scene_hash());
  // A different seed still gives a valid map; the same seed the same bytes.
  o.seed = 2;
  Map::train(data(), o).save(dir / "s2.svamap");
  CHECK_NOTHROW(Map::load(dir / "s2.svamap"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("map: corrupt, truncated and wrong-version files are refused with the file name") {
  const auto dir = test::temp_dir("map-corrupt");
  const auto good = dir / "good.svamap";
  trained().save(good);
  const auto bytes = bytes_of(good);
  auto flipped = bytes;
  flipped[flipped.size() / 2] ^= 0x40;
  write_bytes(dir / "flipped.svamap", flipped);
  CHECK_THROWS_WITH(Map::load(dir / "flipped.svamap"), Contains("flipped.svamap") && Contains("checksum"));
  write_bytes(dir / "short.svamap",
              std::vector<char>(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bytes.size() - 100)));
  CHECK_THROWS_WITH(Map::load(dir / "short.svamap"), Contains("short.svamap") && Contains("truncated"));
  auto version = bytes;
  version[8] = static_cast<char>(kMapVersion + 1);  // a newer build's map
  write_bytes(dir / "version.svamap", version);
  CHECK_THROWS_WITH(Map::load(dir / "version.svamap"), Contains("version.svamap") && Contains("version"));
  write_bytes(dir / "empty.svamap", {});
  CHECK_THROWS_WITH(Map::load(dir / "empty.svamap"), Contains("empty"));
  CHECK_THROWS_WITH(Map::load(dir / "missing.svamap"), Contains("missing.svamap"));
  std::filesystem::remove_all(dir);
}

// The loader weighs the checksum beside its parse where it may use a second thread (SVA_THREADS > 1): a flipped byte
// that breaks the parse (the scene's name length, an object count, an entry) must still be named a checksum mismatch,
// on one thread and on two.
TEST_CASE("map: a flipped byte is named corrupt wherever it lies, the checksum weighed first or beside the parse") {
  const auto dir = test::temp_dir("map-flips");
  trained().save(dir / "good.svamap");
  const auto bytes = bytes_of(dir / "good.svamap");
  for (const char* threads : {"1", "2"}) {
    const test::ScopedEnv env("SVA_THREADS", threads);
    CHECK_NOTHROW(Map::load(dir / "good.svamap"));
    for (const std::size_t at :
         {std::size_t{32}, std::size_t{39}, std::size_t{100}, bytes.size() / 3, bytes.size() / 2, bytes.size() - 1}) {
      auto flipped = bytes;
      flipped[at] ^= 0x40;
      write_bytes(dir / "flipped.svamap", flipped);
      INFO(threads << " thread(s), byte " << at << " of " << bytes.size());
      CHECK_THROWS_WITH(Map::load(dir / "flipped.svamap"), Contains("flipped.svamap") && Contains("checksum"));
    }
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("map: a version-1 map (both orders of every pair) loads as version 2 (each pair once)") {
  const auto dir = test::temp_dir("map-v1");
  const PairMap v2 = MapAccess::pair_map(trained());
  // The version-1 layout: every entry (a, b) under (ca, cb, d) also as (b, a) under (cb, ca, d).
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, float>> all;
  const std::uint32_t nd = v2.key_space.n_dist_bins, nc = v2.key_space.n_classes;
  for (std::size_t k = 0; k < v2.keys.size(); ++k)
    for (std::uint32_t e = v2.offsets[k]; e < v2.offsets[k + 1]; ++e) {
      const std::uint32_t key = v2.keys[k], d = key % nd, ca = key / nd / nc, cb = key / nd % nc;
      all.emplace_back(key, v2.entry_a[e], v2.entry_b[e], v2.entry_weight[e]);
      all.emplace_back(v2.key_space.pack(cb, ca, d), v2.entry_b[e], v2.entry_a[e], v2.entry_weight[e]);
    }
  std::sort(all.begin(), all.end());
  PairMap v1 = v2;
  v1.keys.clear();
  v1.offsets.assign(1, 0);
  v1.entry_a.clear();
  v1.entry_b.clear();
  v1.entry_weight.clear();
  for (const auto& [key, a, b, w] : all) {
    if (v1.keys.empty() || v1.keys.back() != key) {
      v1.keys.push_back(key);
      v1.offsets.push_back(v1.offsets.back());
    }
    v1.entry_a.push_back(a);
    v1.entry_b.push_back(b);
    v1.entry_weight.push_back(w);
    ++v1.offsets.back();
  }
  REQUIRE(v1.entry_count() == 2 * v2.entry_count());
  write_pair_map(v1, dir / "v1.svamap", 1);
  const auto loaded = load_pair_map(dir / "v1.svamap");
  CHECK(loaded->keys == v2.keys);
  CHECK(loaded->offsets == v2.offsets);
  CHECK(loaded->entry_a == v2.entry_a);
  CHECK(loaded->entry_b == v2.entry_b);
  CHECK(loaded->entry_weight == v2.entry_weight);
  std::filesystem::remove_all(dir);
}

TEST_CASE("map: the loader validates contents that pass the checksum") {
  const auto dir = test::temp_dir("map-validate");
  auto broken = [&](auto&& mutate, const std::string& expect) {
    auto m = std::make_shared<PairMap>(MapAccess::pair_map(trained()));
    mutate(*m);
    // Written without save_pair_map's own check, as a buggy or hostile writer would.
    CHECK_THROWS_WITH(validate_pair_map(*m, "mutated"), Contains("mutated") && Contains(expect));
  };
  broken([](PairMap& m) { m.keys[1] = m.keys[0]; }, "increasing");
  broken([](PairMap& m) { m.offsets[1] = m.offsets.back() + 1; }, "increasing");
  broken([](PairMap& m) { m.entry_a[3] = 1u << 30; }, "out of range");
  broken([](PairMap& m) { m.entry_weight[0] = 0.0f; }, "weight");
  broken([](PairMap& m) { std::swap(m.entry_a[0], m.entry_b[0]); }, "second order");
  broken(
      [](PairMap& m) {
        std::swap(m.entry_a[0], m.entry_a[1]);
        std::swap(m.entry_b[0], m.entry_b[1]);
      },
      "not strictly increasing");
  broken([](PairMap& m) { m.entry_weight[0] = std::nanf(""); }, "weight");
  broken([](PairMap& m) { m.readings.nx[0] = 3.0f; }, "unit");
  broken([](PairMap& m) { m.readings.px[2] = INFINITY; }, "non-finite");
  broken([](PairMap& m) { m.keys.back() = 1u << 29; }, "key space");
  broken([](PairMap& m) { m.appearance.psi[0] = -1.0f; }, "psi");
  broken([](PairMap& m) { m.appearance.medoids.pop_back(); }, "medoid");
  broken([](PairMap& m) { m.distance.min_mm = 200.0; }, "distance range");
  std::filesystem::remove_all(dir);
}

TEST_CASE("map: bad training input is refused with a clear message") {
  Dataset empty = data();
  empty.samples.clear();
  CHECK_THROWS_WITH(Map::train(empty, {}), Contains("no readings"));
  Dataset missing = data();
  for (auto& s : missing.samples)
    if (s.object == 1) s.reading.pressure.assign(36, 0.0f);  // nothing to describe
  CHECK_THROWS_WITH(Map::train(missing, {}), Contains("obj1") && Contains("no usable"));
  Dataset failed = data();
  for (auto& s : failed.samples)
    if (s.object == 2) s.reading.status = ControllerStatus::not_converged;
  CHECK_THROWS_WITH(Map::train(failed, {}), Contains("obj2"));
  TrainOptions range;
  range.dist_min_mm = 50;
  range.dist_max_mm = 50;
  CHECK_THROWS_WITH(Map::train(data(), range), Contains("distance range"));
  TrainOptions desc;
  desc.descriptor = "sift";
  CHECK_THROWS_WITH(Map::train(data(), desc), Contains("sift"));
  CHECK_THROWS_AS(Map().entries(), Error);
}

TEST_CASE("map: a dataset with some bad readings skips and counts them, and trains and calibrates on the rest") {
  // Apart from the refusals above: its calibration's held-out sessions take 45 s under the sanitizers, which the test
  // command's sanitizer stage leaves out (CMakePresets.json, asan-fast).
  Dataset some = data();
  some.samples[0].reading.pressure.assign(36, 0.0f);
  some.samples[1].reading.pressure[3] = std::nanf("");
  some.samples[2].reading.status = ControllerStatus::no_contact;
  TrainReport rep;
  const Map m = Map::train(some, {}, &rep);
  CHECK(rep.skipped_undescribable == 2);
  CHECK(rep.skipped_not_converged == 1);
  CHECK(m.readings() == data().samples.size() - 3);
  CHECK(m.summary().calibration.learned);
}

TEST_CASE("map: more clusters than readings, one cluster, MN descriptor") {
  const Dataset tiny = test::synthetic_dataset(2, 3);
  TrainOptions o;
  o.clusters = 25;
  const Map many = Map::train(tiny, o);
  CHECK(many.classes() == 6);
  o.clusters = 1;
  o.descriptor = "mn";
  const Map one = Map::train(tiny, o);
  CHECK(one.classes() == 1);
  CHECK(MapAccess::pair_map(one).appearance.descriptor_size == 64);
  CHECK(MapAccess::pair_map(one).ambiguity == 1.0);
}

TEST_CASE("appearance baseline: histograms and a naive-Bayes posterior that finds the object") {
  const PairMap& m = MapAccess::pair_map(trained());
  const AppearanceBaseline& b = m.baseline;
  REQUIRE(b.n_objects == 3);
  for (std::uint32_t o = 0; o < 3; ++o) {
    double s = 0;
    for (std::uint32_t c = 0; c < b.n_classes; ++c) s += b.class_given_object[o * b.n_classes + c];
    CHECK(s == Approx(1.0));
  }
  // Readings of each object (fresh ones, not the training set) pull the posterior towards it.
  const Dataset test_set = test::synthetic_dataset(3, 15, 1234);
  int right = 0;
  for (std::uint32_t o = 0; o < 3; ++o) {
    std::vector<double> logp;
    for (const auto& s : test_set.samples)
      if (s.object == o) b.update(logp, m.appearance.classify(m.appearance.describe(s.reading)));
    const auto p = AppearanceBaseline::posterior(logp);
    double sum = 0;
    for (double v : p) sum += v;
    CHECK(sum == Approx(1.0));
    right += static_cast<int>(std::max_element(p.begin(), p.end()) - p.begin()) == static_cast<int>(o);
  }
  CHECK(right >= 2);
}

namespace {

// A small closed surface per object: a tetrahedron of `size` mm, counter-clockwise seen from outside.
ObjectSurface tetrahedron(float size) {
  ObjectSurface s;
  s.positions = {{0, 0, 0}, {size, 0, 0}, {0, size, 0}, {0, 0, size}};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return s;
}

}  // namespace

TEST_CASE("map: the objects' surfaces (format 9) round-trip, and a damaged section is refused naming the file") {
  const auto dir = test::temp_dir("map-surfaces");
  TrainOptions o = no_calibration();
  for (int k = 0; k < 3; ++k) o.surfaces.push_back(tetrahedron(20.0f + 10.0f * static_cast<float>(k)));
  const Map m = Map::train(data(), o);
  const MapSummary s = m.summary();
  CHECK(s.surface_objects == 3);
  CHECK(s.surface_triangles == 12);
  CHECK(s.surface_vertices == 12);
  CHECK(s.surface_bytes == 12 * 12 + 12 * 12);  // apart from `bytes`, which the entries divide
  CHECK(s.bytes == trained().summary().bytes);
  m.save(dir / "with.svamap");
  const Map loaded = Map::load(dir / "with.svamap");
  const PairMap& back = MapAccess::pair_map(loaded);
  REQUIRE(back.surfaces.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(back.surfaces[k].positions == o.surfaces[k].positions);
    CHECK(back.surfaces[k].triangles == o.surfaces[k].triangles);
  }
  // A map without them (format 8 and older, or trained with none) loads with none, and says so.
  CHECK(trained().summary().surface_objects == 0);
  write_pair_map(MapAccess::pair_map(trained()), dir / "v8.svamap", 8);
  CHECK(MapAccess::pair_map(Map::load(dir / "v8.svamap")).surfaces.empty());
  CHECK_THROWS_WITH(write_pair_map(MapAccess::pair_map(m), dir / "v8-with.svamap", 8), Contains("version 9"));
  // A surface section a buggy or hostile writer damaged: refused by the loader, naming the file.
  auto damaged = [&](auto&& mutate, const std::string& expect) {
    PairMap bad = MapAccess::pair_map(m);
    mutate(bad);
    write_pair_map(bad, dir / "bad.svamap", kMapVersion);
    CHECK_THROWS_WITH(Map::load(dir / "bad.svamap"), Contains("bad.svamap") && Contains(expect));
  };
  damaged([](PairMap& p) { p.surfaces[1].triangles[2].y = 99; }, "names vertex 99");
  damaged([](PairMap& p) { p.surfaces[0].positions[1].x = NAN; }, "not finite");
  damaged([](PairMap& p) { p.surfaces[2].triangles.clear(); }, "no triangles");
  damaged([](PairMap& p) { p.surfaces[1].positions[3].z = 2e6f; }, "more than 1 km");
  damaged([](PairMap& p) { p.surfaces.pop_back(); },
          "");  // the third object's surface cut off: any fault, the file named
  // Training refuses surfaces that are not one per object.
  TrainOptions two = o;
  two.surfaces.pop_back();
  CHECK_THROWS_WITH(Map::train(data(), two), Contains("2 surfaces") && Contains("3 objects"));
  std::filesystem::remove_all(dir);
}
