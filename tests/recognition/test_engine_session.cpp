// Engines shared by recognizers, recognizers used from several threads, and sessions saved and restored.
#include <catch2/catch.hpp>

#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <filesystem>
#include <fstream>
#include <thread>

#include "map/map_access.hpp"
#include "test_support.hpp"
#include "trained_map.hpp"

using namespace sva;
using namespace sva::test;

namespace {

std::vector<Reading> readings_of(std::uint32_t object, std::uint64_t seed, int count) {
  return readings_at(object, random_pose(seed, 100.0), util::Rng(seed, 7), count);
}

void require_same(const Estimate& a, const Estimate& b) {
  CHECK(a.readings == b.readings);
  CHECK(a.object == b.object);
  CHECK(a.object_probability == b.object_probability);
  CHECK(a.pose_valid == b.pose_valid);
  for (int k = 0; k < 3; ++k) CHECK(a.pose.T[k] == b.pose.T[k]);
  REQUIRE(a.hypotheses.size() == b.hypotheses.size());
  for (std::size_t i = 0; i < a.hypotheses.size(); ++i) {
    CHECK(a.hypotheses[i].probability == b.hypotheses[i].probability);
    CHECK(a.hypotheses[i].covariance == b.hypotheses[i].covariance);
  }
}

}  // namespace

TEST_CASE("Engine: recognizers sharing one engine answer as recognizers with their own") {
  const Trained& t = trained();
  EngineOptions eo;
  eo.backend = BackendKind::cpu;
  const Engine engine(t.map, eo);
  CHECK(engine.backend() == BackendKind::cpu);
  CHECK(MapAccess::shared(engine.map()) == MapAccess::shared(t.map));  // the host map is the caller's, not a copy
  Recognizer a(engine, paper_space()), b(engine, paper_space());
  Recognizer own(t.map, paper_space(), RecognizerOptions{.backend = BackendKind::cpu});
  for (const Reading& r : readings_of(0, 640, 8)) {
    a.add_reading(r);
    own.add_reading(r);
  }
  for (const Reading& r : readings_of(2, 641, 8)) b.add_reading(r);
  require_same(a.estimate(), own.estimate());
  CHECK(b.estimate().object == 2);
  CHECK_THROWS_WITH(Engine(Map{}), Catch::Contains("map is empty"));
}

TEST_CASE("Engine: recognizers of one engine run on two threads at once, and one recognizer is safe to share") {
  const Trained& t = trained();
  EngineOptions eo;
  eo.backend = BackendKind::cpu;
  const Engine engine(t.map, eo);
  RecognizerOptions ro;
  ro.threads = 1;
  // The references have engines of their own, on the same backend (auto would take a GPU where there is one).
  const Engine own_a(t.map, eo), own_b(t.map, eo);
  Recognizer a(engine, paper_space(), ro), b(engine, paper_space(), ro), ref_a(own_a, paper_space(), ro),
      ref_b(own_b, paper_space(), ro);
  const std::vector<Reading> ra = readings_of(1, 650, 8), rb = readings_of(2, 651, 8);
  for (const Reading& r : ra) ref_a.add_reading(r);
  for (const Reading& r : rb) ref_b.add_reading(r);
  std::thread ta([&] {
    for (const Reading& r : ra) a.add_reading(r);
  });
  std::thread tb([&] {
    for (const Reading& r : rb) b.add_reading(r);
  });
  ta.join();
  tb.join();
  require_same(a.estimate(), ref_a.estimate());
  require_same(b.estimate(), ref_b.estimate());
  // One recognizer, estimates read on one thread while another adds readings: calls take turns.
  Recognizer shared(engine, paper_space(), ro);
  std::thread writer([&] {
    for (const Reading& r : ra) shared.add_reading(r);
  });
  for (int i = 0; i < 20; ++i) {
    const Estimate e = shared.estimate(2);
    double sum = 0.0;
    for (double p : e.object_probability) sum += p;
    CHECK(sum == Approx(1.0));
  }
  writer.join();
  require_same(shared.estimate(), ref_a.estimate());
}

TEST_CASE("Session: saved and restored, a session resumes where it stopped, bit for bit") {
  const Trained& t = trained();
  const std::filesystem::path dir = temp_dir("session-resume");
  const std::filesystem::path file = dir / "session.svas";
  const std::vector<Reading> all = readings_of(1, 660, 10);
  Recognizer original(t.map, paper_space());
  original.set_prior({{0.3, 0.5, 0.2}});
  for (int i = 0; i < 6; ++i) original.add_reading(all[i]);
  original.save_session(file);
  Recognizer resumed(t.map, paper_space());
  resumed.add_reading(all[9]);  // replaced by the restored session
  resumed.restore_session(file);
  require_same(resumed.estimate(), original.estimate());
  for (int i = 6; i < 10; ++i) {
    original.add_reading(all[i]);
    resumed.add_reading(all[i]);
  }
  require_same(resumed.estimate(), original.estimate());
  // Reset keeps nothing of the session.
  resumed.reset();
  CHECK(resumed.reading_count() == 0);
  resumed.save_session(file);
  resumed.restore_session(file);
  CHECK(resumed.reading_count() == 0);
  CHECK(resumed.estimate().object_probability[0] == Approx(1.0 / 3.0));
  std::filesystem::remove_all(dir);
}

TEST_CASE("Session: a missing, damaged or foreign session file is refused with the file's name") {
  const Trained& t = trained();
  const std::filesystem::path dir = temp_dir("session-refused");
  const std::filesystem::path file = dir / "session.svas";
  Recognizer rec(t.map, paper_space());
  CHECK_THROWS_WITH(rec.restore_session(dir / "none.svas"), Catch::Contains("none.svas"));
  for (const Reading& r : readings_of(0, 670, 4)) rec.add_reading(r);
  rec.save_session(file);
  // Another map (another scene): its readings would mean nothing there.
  auto other = std::make_shared<PairMap>(MapAccess::pair_map(t.map));
  other->scene_hash ^= 1;
  other->scene_name = "another";
  Recognizer foreign(MapAccess::wrap(other), paper_space());
  CHECK_THROWS_WITH(foreign.restore_session(file), Catch::Contains("another") && Catch::Contains("session.svas"));
  // A damaged file fails its checksum.
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(60);
    f.put('\x7f');
  }
  CHECK_THROWS_AS(rec.restore_session(file), Error);
  CHECK(rec.reading_count() == 4);  // a refused file leaves the session as it was
  std::filesystem::remove_all(dir);
}
