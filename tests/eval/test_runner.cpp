// The trial runner with a scripted session: errors and correctness are
// recorded per reading, sessions are reset between trials, results and the
// JSON summary do not depend on the thread count, reports read back.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/eval/report.hpp>
#include <sva/eval/trials.hpp>
#include <sva/io/text_file.hpp>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "eval/metrics.hpp"
#include "eval/trial_runner.hpp"
#include "test_support.hpp"

using namespace sva;
using namespace sva::eval;

namespace {

Dataset make_test_set(std::size_t objects, std::size_t per_object) {
  Dataset d;
  d.scene.name = "unit";
  for (std::size_t o = 0; o < objects; ++o) {
    SceneObject so;
    so.name = "obj" + std::to_string(o);
    so.mesh = "/nonexistent/obj.glb";
    so.inertial_radius_mm = 40.0;
    d.scene.objects.push_back(so);
  }
  d.scene.objects[0].symmetry.kind = Symmetry::Kind::axis;  // exercises Eq 22 through the runner
  for (std::size_t o = 0; o < objects; ++o)
    for (std::size_t k = 0; k < per_object; ++k) {
      Sample s;
      s.object = static_cast<std::uint32_t>(o);
      s.reading.iterations = static_cast<std::uint16_t>(o);  // a reading has no ground truth: the script reads it here
      double a = 0.7 * static_cast<double>(k);
      s.reading.position = {30.0 * std::cos(a), 30.0 * std::sin(a), static_cast<double>(k)};
      s.reading.normal = {std::cos(a), std::sin(a), 0.0};
      s.reading.x_axis = {0.0, 0.0, 1.0};
      s.reading.pressure.assign(36, 1.0f);
      d.samples.push_back(s);
    }
  return d;
}

// Wrong object for the first reading of a session, right afterwards (it reads
// the ground-truth id the test data hides in `iterations`); a pose from the second reading on: no rotation, the
// translation is the last contact position. Forgetting reset() between trials
// would make the first step right.
class ScriptedSession final : public Session {
 public:
  explicit ScriptedSession(std::size_t objects) : objects_(objects) {}
  void add_reading(const Reading& r) override {
    if (r.pressure.empty()) throw Error("cannot describe");
    ++count_;
    last_ = r;
  }
  Estimate estimate() const override {
    Estimate e;
    e.readings = count_;
    const std::uint32_t truth = last_.iterations;  // the test data carries the object id in `iterations`
    e.object = count_ >= 2 ? truth : static_cast<std::uint32_t>((truth + 1) % objects_);
    e.object_probability.assign(objects_, 0.0);
    e.object_probability[e.object] = 1.0;
    e.pose_valid = count_ >= 2;
    e.pose.T = last_.position;
    return e;
  }
  void reset() override { count_ = 0; }

 private:
  std::size_t objects_;
  std::size_t count_ = 0;
  Reading last_;
};

TrialSetup setup_for(std::size_t trials, std::size_t readings, unsigned threads) {
  TrialSetup s;
  s.trials = trials;
  s.max_readings = readings;
  s.seed = 99;
  s.threads = threads;
  s.progress = false;
  s.backend = "cpu";
  s.method = "scripted";
  return s;
}

nlohmann::json without_timing(const std::string& text) {
  auto j = nlohmann::json::parse(text);
  for (auto& p : j["curve"])
    for (const char* k : {"update_ms", "update_ms_mean", "update_ms_p90", "update_ms_p95"}) {
      REQUIRE(p.contains(k));
      p.erase(k);
    }
  return j;
}

}  // namespace

TEST_CASE("runner records correctness and pose errors of every reading") {
  Dataset d = make_test_set(3, 10);
  const TrialSetup setup = setup_for(6, 5, 2);
  EvalResult r = run_trials(d, setup, [] { return std::make_unique<ScriptedSession>(3); });
  REQUIRE(r.trials.size() == 6);
  TrialGenerator gen(d, setup.pose_space, setup.seed, setup.max_readings);
  for (std::size_t t = 0; t < 6; ++t) {
    const Trial expect = gen.make(t);
    const TrialResult& got = r.trials[t];
    CHECK(got.object == t % 3);
    CHECK(got.samples == expect.samples);
    REQUIRE(got.steps.size() == 5);
    CHECK_FALSE(got.steps[0].correct);
    CHECK(got.steps[0].true_object_probability == 0.0);
    for (std::size_t k = 1; k < 5; ++k) {
      const StepResult& s = got.steps[k];
      CHECK(s.correct);
      CHECK(s.true_object_probability == 1.0);
      REQUIRE(s.has_pose_error());
      RigidPose est{glm::dmat3(1.0), expect.readings[k].position};
      const SceneObject& obj = d.scene.objects[expect.object];
      PoseError e = pose_error(expect.pose, est, obj.symmetry, obj.inertial_radius_mm);
      CHECK(s.translation_error_mm == Approx(e.translation_mm));
      CHECK(s.angular_error_rad == Approx(e.angular_rad));
      CHECK(s.inertial_error_mm == Approx(e.inertial_mm));
      CHECK(s.update_ms >= 0.0);
    }
  }
  Curve c = summarize(r);
  REQUIRE(c.points.size() == 5);
  CHECK(c.points[0].accuracy == 0.0);
  CHECK(c.points[0].pose_trials == 0);
  CHECK_FALSE(c.points[0].translation_mm.median.has_value());
  CHECK(c.points[0].update_ms.median.has_value());
  CHECK(c.points[3].accuracy == 1.0);
  CHECK(c.points[3].pose_trials == 6);
  std::vector<double> t3;
  for (const auto& t : r.trials) t3.push_back(t.steps[3].translation_error_mm);
  CHECK(*c.points[3].translation_mm.median == Approx(*median(t3)));
}

TEST_CASE("runner results and JSON do not depend on the thread count") {
  Dataset d = make_test_set(4, 12);
  auto run = [&](unsigned threads) {
    EvalResult r = run_trials(d, setup_for(16, 8, threads), [] { return std::make_unique<ScriptedSession>(4); });
    return to_json(r, summarize(r));
  };
  const std::string one = run(1), two = run(2);
  CHECK(without_timing(one) == without_timing(two));
  auto j = nlohmann::json::parse(one);
  CHECK(j["scene"] == "unit");
  CHECK(j["backend"] == "cpu");
  CHECK(j["method"] == "scripted");
  CHECK(j["trials"] == 16);
  REQUIRE(j["curve"].size() == 8);
  for (const char* key : {"readings", "accuracy", "translation_error_mm", "angular_error_deg", "inertial_error_mm",
                          "update_ms", "update_ms_p95"})
    CHECK(j["curve"][2].contains(key));
  CHECK(j["curve"][0]["translation_error_mm"].is_null());
  CHECK(j["curve"][2]["translation_error_mm"].is_number());
}

TEST_CASE("runner refuses zero trials and reports a failing reading with its trial") {
  Dataset d = make_test_set(2, 4);
  auto factory = [] { return std::make_unique<ScriptedSession>(2); };
  CHECK_THROWS_WITH(run_trials(d, setup_for(0, 5, 1), factory), Catch::Contains("trials"));
  CHECK_THROWS_WITH(run_trials(d, setup_for(2, 0, 1), factory), Catch::Contains("readings"));
  d.samples[5].reading.pressure.clear();  // the scripted session cannot describe it
  d.scene.sensor = {0, 0, 2.0};           // so the generator accepts empty images
  for (auto& s : d.samples)
    if (&s != &d.samples[5]) s.reading.pressure.clear();
  auto setup = setup_for(2, 4, 1);
  setup.source = "t.svad";
  CHECK_THROWS_WITH(run_trials(d, setup, factory), Catch::Contains("t.svad") && Catch::Contains("trial 0"));
}

TEST_CASE("CSV has one row per trial and reading and JSON summaries read back") {
  Dataset d = make_test_set(2, 6);
  EvalResult r = run_trials(d, setup_for(4, 3, 2), [] { return std::make_unique<ScriptedSession>(2); });
  const std::string csv = to_csv(r);
  std::istringstream lines(csv);
  std::string line;
  std::size_t rows = 0;
  std::getline(lines, line);
  CHECK(line.rfind("trial,object,object_name,readings", 0) == 0);
  const auto columns = std::count(line.begin(), line.end(), ',');
  while (std::getline(lines, line)) {
    ++rows;
    CHECK(std::count(line.begin(), line.end(), ',') == columns);
  }
  CHECK(rows == 4 * 3);

  Curve c = summarize(r);
  auto dir = sva::test::temp_dir("eval-report");
  io::write_text_file(dir / "a.json", to_json(r, c));
  Curve back = read_curve_json(dir / "a.json");
  CHECK(back.method == "scripted");
  CHECK(back.trials == 4);
  REQUIRE(back.points.size() == 3);
  CHECK(back.points[1].accuracy == c.points[1].accuracy);
  CHECK(*back.points[2].inertial_mm.median == Approx(*c.points[2].inertial_mm.median));
  CHECK(*back.points[2].inertial_mm.mean == Approx(*c.points[2].inertial_mm.mean));
  CHECK(*back.points[2].angular_deg.p90 == Approx(*c.points[2].angular_deg.p90));
  CHECK(*back.points[2].update_ms.p90 == Approx(*c.points[2].update_ms.p90));
  CHECK_FALSE(back.points[0].translation_mm.median.has_value());
  CHECK_FALSE(back.points[0].translation_mm.mean.has_value());

  std::ofstream(dir / "bad.json") << "{\"scene\": \"x\"}";
  CHECK_THROWS_WITH(read_curve_json(dir / "bad.json"), Catch::Contains("bad.json"));
  CHECK_THROWS_WITH(read_curve_json(dir / "missing.json"), Catch::Contains("missing.json"));
  const std::string table = format_table(c);
  CHECK(table.find("readings") != std::string::npos);
  // Title, two header lines, one row per point, the readings-to-95% line, the calibration's three lines.
  CHECK(std::count(table.begin(), table.end(), '\n') == 3 + 3 + 1 + 3);
  CHECK(table.find("calibration: ECE") != std::string::npos);
  CHECK(table.find("ECE over resampled trials") != std::string::npos);
  CHECK(table.find("policy random: readings until the true object holds >= 95%") != std::string::npos);
  CHECK(back.policy == "random");
  CHECK(back.to_95.trials == c.to_95.trials);
  CHECK(table.find("p90") != std::string::npos);
  std::filesystem::remove_all(dir);
}
