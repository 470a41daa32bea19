// The robustness sweep's report (`sva eval --sweep`): levels read from eval
// summaries, checked to be one sweep, tabulated and drawn against the level.
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include <sva/eval/robustness.hpp>
#include <sva/io/text_file.hpp>
#include "test_support.hpp"

using namespace sva;
using namespace sva::eval;

namespace {

// A summary whose accuracy falls and whose errors grow with the level: step n
// has accuracy min(1, n / (4 (1 + level))) and a translation error of (1 + level) / n mm.
Curve synthetic_curve(double level, std::size_t readings, std::size_t trials = 10) {
  Curve c;
  c.scene = "unit";
  c.method = "sva";
  c.backend = "cpu";
  c.trials = trials;
  for (std::size_t n = 1; n <= readings; ++n) {
    CurvePoint p;
    p.readings = n;
    p.accuracy = std::min(1.0, static_cast<double>(n) / (4.0 * (1.0 + level)));
    if (n > 1) {
      const double t = (1.0 + level) / static_cast<double>(n);
      p.translation_mm = {t, 1.5 * t, 2 * t};
      p.angular_deg = {3 * t, 4 * t, 6 * t};
      p.inertial_mm = {2 * t, 3 * t, 4 * t};
    }
    c.points.push_back(p);
  }
  return c;
}

std::string summary_json(const Curve& c) {
  nlohmann::json curve = nlohmann::json::array();
  auto opt = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  for (const auto& p : c.points)
    curve.push_back({{"readings", p.readings},
                     {"accuracy", p.accuracy},
                     {"pose_trials", p.pose_trials},
                     {"translation_error_mm", opt(p.translation_mm.median)},
                     {"translation_error_mm_mean", opt(p.translation_mm.mean)},
                     {"angular_error_deg", opt(p.angular_deg.median)},
                     {"angular_error_deg_mean", opt(p.angular_deg.mean)},
                     {"inertial_error_mm", opt(p.inertial_mm.median)},
                     {"inertial_error_mm_mean", opt(p.inertial_mm.mean)},
                     {"update_ms", 1.0},
                     {"update_ms_p95", 1.0}});
  return nlohmann::json{
      {"scene", c.scene}, {"backend", c.backend}, {"method", c.method}, {"trials", c.trials}, {"curve", curve}}
      .dump();
}

}  // namespace

TEST_CASE("sweep: levels are sorted and tabulated against the error level") {
  std::vector<SweepLevel> levels{
      {2.0, synthetic_curve(2.0, 10)}, {0.0, synthetic_curve(0.0, 10)}, {1.0, synthetic_curve(1.0, 10)}};
  check_sweep(levels, {4, 10});
  REQUIRE(levels[0].scale == 0.0);
  REQUIRE(levels[2].scale == 2.0);
  const std::string t = format_sweep_table(levels, {4, 10});
  CHECK(std::count(t.begin(), t.end(), '\n') == 2 + 3);  // header, rule, one row per level
  CHECK(t.find("| 0 | 100.0% | 100.0% |") != std::string::npos);
  CHECK(t.find("| 2 | 33.3% | 83.3% |") != std::string::npos);
  CHECK(t.find("0.30 mm / 0.90° / 0.60 mm") != std::string::npos);  // level 2 at 10 readings: t = 0.3
  CHECK(t.find("acc 4") != std::string::npos);
}

TEST_CASE("sweep: refuses levels that are not one sweep") {
  std::vector<SweepLevel> none;
  CHECK_THROWS_WITH(check_sweep(none, {5}), Catch::Contains("no levels"));
  std::vector<SweepLevel> twice{{1.0, synthetic_curve(1.0, 10)}, {1.0, synthetic_curve(1.0, 10)}};
  CHECK_THROWS_WITH(check_sweep(twice, {5}), Catch::Contains("level 1 is given twice"));
  std::vector<SweepLevel> other{{0.0, synthetic_curve(0.0, 10)}, {1.0, synthetic_curve(1.0, 10, 20)}};
  CHECK_THROWS_WITH(check_sweep(other, {5}), Catch::Contains("another run"));
  std::vector<SweepLevel> short_curve{{0.0, synthetic_curve(0.0, 10)}, {1.0, synthetic_curve(1.0, 4)}};
  CHECK_THROWS_WITH(check_sweep(short_curve, {5}), Catch::Contains("no point at 5 readings"));
  CHECK_THROWS_WITH(read_sweep_level("1.0"), Catch::Contains("LEVEL=FILE.json"));
  CHECK_THROWS_WITH(read_sweep_level("-1=a.json"), Catch::Contains(">= 0"));
  CHECK_THROWS_WITH(read_sweep_level("x=a.json"), Catch::Contains("\"x\""));
  CHECK_THROWS_WITH(read_sweep_level("1=/nonexistent/a.json"), Catch::Contains("/nonexistent/a.json"));
}

TEST_CASE("sweep: sva eval --sweep prints the table and writes it and the figure") {
  const auto dir = test::temp_dir("sweep");
  std::string args = "eval";
  for (double level : {0.0, 0.5, 4.0}) {
    const auto file = dir / ("level" + std::to_string(level) + ".json");
    io::write_text_file(file, summary_json(synthetic_curve(level, 12)));
    args += " --sweep " + std::to_string(level) + "=" + file.string();
  }
  std::string out;
  REQUIRE(test::run_sva(args + " --sweep-readings 5,12 --table " + (dir / "t.md").string() + " --plot " +
                            (dir / "s.png").string(),
                        &out) == 0);
  CHECK(out.find("| 4 | 25.0% | 60.0% |") != std::string::npos);
  CHECK(std::filesystem::file_size(dir / "s.png") > 1000);
  std::ifstream t(dir / "t.md");
  std::string first;
  std::getline(t, first);
  CHECK(first.rfind("| error level | acc 5 | acc 12 |", 0) == 0);
  CHECK(test::run_sva(args + " --map m.svam", &out) == 1);
  CHECK(out.find("--map does not apply") != std::string::npos);
  CHECK(test::run_sva(args + " --sweep-readings 5,0", &out) == 1);
  CHECK(out.find("--sweep-readings") != std::string::npos);
  CHECK(test::run_sva("eval --table x.md", &out) == 1);
  CHECK(out.find("--table needs --sweep") != std::string::npos);
  std::filesystem::remove_all(dir);
}
