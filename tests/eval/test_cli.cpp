// sva eval through the CLI on a tiny synthetic scene (two objects, readings on
// spheres with spatially varying pressure patterns): outputs, determinism of
// everything but the timings, and every bad input the issue lists.
#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/map.hpp>

#include <sys/wait.h>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "map/map_access.hpp"
#include "map/map_file.hpp"
#include "test_support.hpp"

using namespace sva;

namespace {

Scene tiny_scene(const std::string& name = "tiny") {
  Scene s;
  s.name = name;
  for (const char* o : {"ball", "pebble"}) {
    SceneObject so;
    so.name = o;
    so.mesh = std::string("/nonexistent/") + o + ".glb";
    so.size_mm = 80.0;
    so.inertial_radius_mm = 40.0;
    s.objects.push_back(so);
  }
  s.appearance.clusters = 6;
  s.appearance.dist_bins = 16;
  s.appearance.dist_min_mm = 10.0;
  s.appearance.dist_max_mm = 80.0;
  return s;
}

// An elliptic pressure blob whose widths depend on where it is on the object
// and on the object, so appearance varies over the surface.
std::vector<float> blob(const glm::dvec3& p, std::uint32_t object, const SensorSpec& sensor) {
  const double a = 1.2 + 1.5 * (0.5 + 0.5 * std::sin(p.z / 12.0 + 1.7 * object));
  const double b = 0.7 + 0.8 * (0.5 + 0.5 * std::cos(p.x / 15.0 - object));
  const double th = std::atan2(p.y, p.x);
  std::vector<float> img(static_cast<std::size_t>(sensor.elements()));
  for (int r = 0; r < sensor.rows; ++r)
    for (int c = 0; c < sensor.cols; ++c) {
      const double x = (c - (sensor.cols - 1) / 2.0) * sensor.pitch_mm,
                   y = (r - (sensor.rows - 1) / 2.0) * sensor.pitch_mm;
      const double u = std::cos(th) * x + std::sin(th) * y, v = -std::sin(th) * x + std::cos(th) * y;
      img[static_cast<std::size_t>(r * sensor.cols + c)] =
          static_cast<float>(30.0 * std::exp(-u * u / (2 * a * a) - v * v / (2 * b * b)));
    }
  return img;
}

// Points on a sphere of radius 40 (a Fibonacci lattice, shifted per split).
Dataset tiny_dataset(const Scene& scene, const std::string& split, int per_object, double shift) {
  Dataset d;
  d.scene = scene;
  d.split = split;
  for (std::uint32_t o = 0; o < scene.objects.size(); ++o)
    for (int i = 0; i < per_object; ++i) {
      const double z = 1.0 - 2.0 * (i + 0.5) / per_object;
      const double phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0)) + shift;
      const glm::dvec3 n(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
      Sample s;
      s.object = o;
      s.reading.position = 40.0 * n;
      s.reading.normal = n;
      s.reading.x_axis = glm::normalize(glm::cross(n, std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
      s.reading.pressure = blob(s.reading.position, o, scene.sensor);
      d.samples.push_back(s);
    }
  return d;
}

struct Fixture {
  std::filesystem::path dir;
  std::string map, test;
  Fixture() : dir(sva::test::temp_dir("eval-cli")) {
    const Scene scene = tiny_scene();
    Dataset train = tiny_dataset(scene, "train", 48, 0.0);
    TrainOptions o;
    o.threads = 1;
    Map::train(train, o).save(dir / "tiny.svam");
    save_dataset(tiny_dataset(scene, "test", 12, 0.05), dir / "test.svad");
    map = (dir / "tiny.svam").string();
    test = (dir / "test.svad").string();
  }
  ~Fixture() { std::filesystem::remove_all(dir); }
  std::string base() const { return "eval --map " + map + " --data " + test + " "; }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

std::string read_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

nlohmann::json without_timing(const std::string& file) {
  auto j = nlohmann::json::parse(read_file(file));
  for (auto& p : j["curve"])
    for (const char* k : {"update_ms", "update_ms_mean", "update_ms_p90", "update_ms_p95"}) p.erase(k);
  return j;
}

}  // namespace

TEST_CASE(
    "sva eval writes the JSON curve, CSV and figure with non-timing fields the same run to run and on 1 or 2 threads") {
  Fixture f;
  std::string out;
  // The CPU reference named: the default (auto) takes a GPU where there is one.
  const std::string common = f.base() + "--backend cpu --trials 4 --max-readings 5 --seed 7 ";
  REQUIRE(sva::test::run_sva(common + "--threads 1 --json " + f.path("a.json") + " --csv " + f.path("a.csv") +
                                 " --plot " + f.path("a.png"),
                             &out) == 0);
  CHECK(out.find("readings") != std::string::npos);
  REQUIRE(sva::test::run_sva(common + "--threads 2 --json " + f.path("b.json"), &out) == 0);

  auto a = without_timing(f.path("a.json")), b = without_timing(f.path("b.json"));
  CHECK(a == b);
  CHECK(a["scene"] == "tiny");
  CHECK(a["backend"] == "cpu");
  CHECK(a["method"] == "sva");
  CHECK(a["trials"] == 4);
  REQUIRE(a["curve"].size() == 5);
  for (const auto& p : a["curve"]) {
    CHECK(p["accuracy"].get<double>() >= 0.0);
    CHECK(p["accuracy"].get<double>() <= 1.0);
    for (const char* key : {"translation_error_mm", "angular_error_deg", "inertial_error_mm", "mssd_mm", "adds_mm"})
      CHECK((p[key].is_null() || p[key].get<double>() >= 0.0));
    // The fixture's scene names no mesh files: no surface errors (docs/pose-errors.md), the others as ever.
    CHECK(p["mssd_mm"].is_null());
    CHECK(p["adds_mm"].is_null());
    CHECK(p["votes_zero"].get<std::uint64_t>() <= p["votes"].get<std::uint64_t>());
  }
  CHECK(a["curve"][0]["votes"] == 0);  // one reading makes no pair
  CHECK(a["curve"][4]["votes"].get<std::uint64_t>() > 0);
  auto full = nlohmann::json::parse(read_file(f.path("a.json")));
  CHECK(full["curve"][4]["update_ms"].is_number());
  CHECK(full["curve"][4]["update_ms_p95"].get<double>() >= full["curve"][4]["update_ms"].get<double>());

  const std::string csv = read_file(f.path("a.csv"));
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 4 * 5);
  CHECK(csv.substr(0, csv.find('\n')).ends_with(",votes,votes_zero,top_probability,p_unknown,known,mssd_mm,adds_mm"));
  const std::string png = read_file(f.path("a.png"));
  REQUIRE(png.size() > 8);
  CHECK(png.substr(1, 3) == "PNG");
  // The reliability diagram beside the figure, and the calibration in the JSON.
  CHECK(read_file(f.path("a_reliability.png")).substr(1, 3) == "PNG");

  // Another seed gives other trials.
  REQUIRE(sva::test::run_sva(f.base() + "--trials 4 --max-readings 5 --seed 8 --json " + f.path("c.json"), &out) == 0);
  auto c = nlohmann::json::parse(read_file(f.path("c.json")));
  CHECK(c["seed"] == 8);
  // --likelihood-cutoff: the same trials, and the matches below it cast no vote.
  REQUIRE(sva::test::run_sva(common + "--likelihood-cutoff 0.4 --json " + f.path("cut.json"), &out) == 0);
  auto cut = nlohmann::json::parse(read_file(f.path("cut.json")));
  CHECK(cut["curve"][4]["votes"].get<std::uint64_t>() < a["curve"][4]["votes"].get<std::uint64_t>());
}

TEST_CASE(
    "sva eval --evidence writes what each posterior was made of, which weighed as the estimate weighs it names "
    "the estimate's object") {
  Fixture f;
  std::string out;
  REQUIRE(sva::test::run_sva(
              f.base() + "--backend cpu --trials 4 --max-readings 8 --seed 7 --evidence " + f.path("ev.jsonl"), &out) ==
          0);
  std::istringstream lines(read_file(f.path("ev.jsonl")));
  std::size_t rows = 0, weighed = 0, surfaces = 0;
  for (std::string line; std::getline(lines, line); ++rows) {
    const auto j = nlohmann::json::parse(line);
    INFO(line.substr(0, 300));
    CHECK(j["readings"].get<std::size_t>() == rows % 8 + 1);
    CHECK(j["trial"].get<std::size_t>() == rows / 8);
    REQUIRE(j["map_object"].is_number());  // every test object is in the map
    CHECK(j["correct"].get<bool>() == (j["map_object"] == j["estimated_object"]));
    const auto pairs = j["pairs_log2_mass"].get<std::vector<double>>();
    const auto surface = j["surface_log2_fit"].get<std::vector<double>>();
    REQUIRE(pairs.size() == 2);  // the tiny scene's objects
    CHECK((surface.empty() || surface.size() == pairs.size()));
    if (pairs[0] == pairs[1]) continue;  // one reading: no pair has voted
    // The estimate's own weighing (docs/recognition.md, "What the posterior is made of") names its object.
    std::vector<double> q(2);
    for (std::size_t o = 0; o < 2; ++o)
      q[o] = j["temperature"].get<double>() * pairs[o] +
             (surface.empty() ? 0.0 : j["surface_weight"].get<double>() * surface[o]);
    CHECK((q[1] > q[0] ? 1u : 0u) == j["estimated_object"].get<unsigned>());
    ++weighed;
    surfaces += !surface.empty();
  }
  CHECK(rows == 4 * 8);
  CHECK(weighed >= 4 * 6);  // not vacuous: the pairs and, from the fine pose on, the surfaces weighed
  CHECK(surfaces > 0);
  // A file that cannot be written is refused before any trial runs, naming the option.
  CHECK(sva::test::run_sva(f.base() + "--trials 1 --max-readings 2 --evidence /nonexistent/dir/ev.jsonl", &out) != 0);
  CHECK(out.find("--evidence") != std::string::npos);
}

TEST_CASE("sva eval --estimate light: the full curve until the fits start, recorded and printed, bad depths named") {
  Fixture f;
  std::string out;
  const std::string common = f.base() + "--backend cpu --trials 4 --max-readings 8 --seed 7 ";
  REQUIRE(sva::test::run_sva(common + "--json " + f.path("full.json"), &out) == 0);
  CHECK(out.find("light estimates") == std::string::npos);
  REQUIRE(sva::test::run_sva(common + "--estimate light --json " + f.path("light.json"), &out) == 0);
  CHECK(out.find("backend cpu, light estimates, 4 trials") != std::string::npos);
  auto full = without_timing(f.path("full.json")), light = without_timing(f.path("light.json"));
  CHECK(full["estimate"] == "full");
  CHECK(light["estimate"] == "light");
  REQUIRE(light["curve"].size() == 8);
  // Before the fine pose (6 readings on this map) the two depths compute the same stages: the same points.
  for (std::size_t i = 0; i < 5; ++i) CHECK(light["curve"][i] == full["curve"][i]);
  bool differs = false;  // from 6 on the full estimate's fine pose moves the errors
  for (std::size_t i = 5; i < 8; ++i) differs = differs || light["curve"][i] != full["curve"][i];
  CHECK(differs);
  CHECK(out.find("no light calibration") == std::string::npos);  // this build's map has its own
  // A map of format 9 has none: its light estimates read the full calibration's evidence regime, and eval says so.
  const Map map = Map::load(f.map);
  REQUIRE(map.summary().calibration.light_from == 6);
  sva::PairMap v9 = sva::MapAccess::pair_map(map);
  v9.calibration.light = {};
  sva::write_pair_map(v9, f.path("v9.svam"), 9);
  REQUIRE(sva::test::run_sva("eval --map " + f.path("v9.svam") + " --data " + f.test +
                                 " --backend cpu --trials 2 --max-readings 3 --estimate light",
                             &out) == 0);
  CHECK(out.find("v9.svam has no light calibration") != std::string::npos);
  for (const std::string bad : {"--estimate fine", "--estimate "}) {
    INFO(bad);
    CHECK(sva::test::run_sva(common + bad, &out) != 0);
    CHECK(out.find("--estimate") != std::string::npos);
    CHECK(out.find("internal error") == std::string::npos);
  }
}

TEST_CASE("sva recognize --estimate light: each session's answer without the host's fits, said, bad depths named") {
  Fixture f;
  std::string out;
  REQUIRE(sva::test::run_sva("recognize --write-sessions " + f.path("s.jsonl") + " --map " + f.map + " --data " +
                                 f.test + " --trials 3 --max-readings 8",
                             &out) == 0);
  const std::string run = "recognize --map " + f.map + " --batch " + f.path("s.jsonl") + " --backend cpu --out ";
  REQUIRE(sva::test::run_sva(run + f.path("full.jsonl"), &out) == 0);
  CHECK(out.find("full estimates") != std::string::npos);
  REQUIRE(sva::test::run_sva(run + f.path("light.jsonl") + " --estimate light", &out) == 0);
  CHECK(out.find("light estimates") != std::string::npos);
  const std::string full = read_file(f.path("full.jsonl")), light = read_file(f.path("light.jsonl"));
  CHECK(std::count(light.begin(), light.end(), '\n') == 3);
  CHECK(light != full);  // 8 readings: the full estimates' fine pose moved the poses
  CHECK(sva::test::run_sva(run + f.path("bad.jsonl") + " --estimate fine", &out) != 0);
  CHECK(out.find("--estimate expects full or light, got \"fine\"") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(f.dir / "bad.jsonl"));
}

TEST_CASE("sva eval overlays another method's curve with --compare") {
  Fixture f;
  std::string out;
  const std::string common = f.base() + "--trials 2 --max-readings 4 ";
  REQUIRE(sva::test::run_sva(common + "--method appearance --json " + f.path("app.json"), &out) == 0);
  auto app = nlohmann::json::parse(read_file(f.path("app.json")));
  CHECK(app["method"] == "appearance");
  for (const auto& p : app["curve"]) CHECK(p["translation_error_mm"].is_null());  // the baseline has no pose
  REQUIRE(sva::test::run_sva(common + "--plot " + f.path("fig.png") + " --compare " + f.path("app.json"), &out) == 0);
  CHECK(std::filesystem::file_size(f.path("fig.png")) > 1000);
  CHECK(sva::test::run_sva(common + "--compare " + f.path("app.json"), &out) != 0);
  CHECK(out.find("--plot") != std::string::npos);
  CHECK(sva::test::run_sva(common + "--plot " + f.path("x.png") + " --compare " + f.path("nope.json"), &out) != 0);
  CHECK(out.find("nope.json") != std::string::npos);
}

TEST_CASE("sva eval refuses bad options with the value named") {
  Fixture f;
  std::string out;
  struct Case {
    std::string args, expect;
  };
  for (const Case& c :
       {Case{"--trials 0", "--trials 0"}, Case{"--max-readings 0", "--max-readings 0"},
        Case{"--trials -3", "--trials -3"}, Case{"--max-readings x", "--max-readings"}, Case{"--backend cuda", "cuda"},
        Case{"--method geometry", "geometry"}, Case{"--json /nonexistent-dir/a.json", "/nonexistent-dir"},
        Case{"--max-pairs -2", "--max-pairs"}, Case{"--likelihood-cutoff -1", "--likelihood-cutoff"},
        Case{"--likelihood-cutoff 1e9", "--likelihood-cutoff 1e9 is out of range [0, 128]"},
        Case{"--unknown-prior 1", "--unknown-prior 1 is out of range [1e-09, 0.999999999]"}}) {
    INFO(c.args);
    CHECK(sva::test::run_sva(f.base() + c.args, &out) != 0);
    CHECK(out.find(c.expect) != std::string::npos);
    CHECK(out.find("internal error") == std::string::npos);
  }
  CHECK(sva::test::run_sva("eval --data " + f.test, &out) != 0);
  CHECK(out.find("--map") != std::string::npos);
  CHECK(sva::test::run_sva("eval --map " + f.map + " --data " + f.path("missing.svad"), &out) != 0);
  CHECK(out.find("missing.svad") != std::string::npos);
}

TEST_CASE("sva eval refuses test sets that cannot be evaluated against the map") {
  Fixture f;
  std::string out;
  auto run_with = [&](const Dataset& d, const std::string& name) {
    save_dataset(d, f.dir / name);
    const int rc =
        sva::test::run_sva("eval --map " + f.map + " --data " + f.path(name) + " --trials 2 --max-readings 3", &out);
    CHECK(out.find("internal error") == std::string::npos);
    return rc;
  };
  SECTION("another scene") {
    CHECK(run_with(tiny_dataset(tiny_scene("other"), "test", 6, 0.1), "other.svad") != 0);
    CHECK(out.find("different scenes") != std::string::npos);
  }
  SECTION("another sensor, so the descriptors do not compare") {
    Scene s = tiny_scene();
    s.sensor = {4, 4, 2.0};
    CHECK(run_with(tiny_dataset(s, "test", 6, 0.1), "sensor.svad") != 0);
    CHECK(out.find("different sensors") != std::string::npos);
  }
  SECTION("readings with NaN") {
    Dataset d = tiny_dataset(tiny_scene(), "test", 6, 0.1);
    d.samples[3].reading.position.x = std::nan("");
    CHECK(run_with(d, "nan.svad") != 0);
    CHECK(out.find("nan.svad") != std::string::npos);
    CHECK(out.find("sample 3") != std::string::npos);
  }
  SECTION("an empty test set") {
    Dataset d = tiny_dataset(tiny_scene(), "test", 6, 0.1);
    for (auto& s : d.samples) s.reading.status = ControllerStatus::no_contact;
    CHECK(run_with(d, "empty.svad") != 0);
    CHECK(out.find("empty") != std::string::npos);
    d.samples.clear();
    CHECK(run_with(d, "none.svad") != 0);
    CHECK(out.find("empty") != std::string::npos);
  }
}

TEST_CASE("sva eval stops cleanly on Ctrl-C and leaves no output") {
  Fixture f;
  const char* bin = std::getenv("SVA_BIN");
  REQUIRE(bin != nullptr);
  // A run far longer than the 1 s after which timeout sends SIGINT.
  const std::string cmd = "timeout --preserve-status -s INT 1 " + std::string(bin) + " --quiet " + f.base() +
                          "--trials 1000000 --max-readings 30 --json " + f.path("never.json") + " > " +
                          f.path("log.txt") + " 2>&1";
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  // Stopped by the CLI's handler (a kill by the signal would read 130 too).
  CHECK(read_file(f.path("log.txt")).find("interrupted") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(f.path("never.json")));
  for (const auto& e : std::filesystem::directory_iterator(f.dir))
    CHECK(e.path().filename().string().find("never") == std::string::npos);
}

TEST_CASE("sva eval gives the same curve on the Vulkan backend as on the CPU") {
  Fixture f;
  std::string out;
  const std::string common = f.base() + "--trials 4 --max-readings 5 --seed 3 ";
  REQUIRE(sva::test::run_sva(common + "--backend cpu --json " + f.path("cpu.json"), &out) == 0);
  if (sva::test::run_sva(common + "--backend vulkan --json " + f.path("vk.json"), &out) != 0) {
    if (out.find("ulkan") != std::string::npos && out.find("internal error") == std::string::npos)
      sva::test::skip("no Vulkan device: " + out);
    FAIL(out);
  }
  auto cpu = without_timing(f.path("cpu.json")), vk = without_timing(f.path("vk.json"));
  CHECK(vk["backend"] == "vulkan");
  cpu.erase("backend");
  vk.erase("backend");
  CHECK(cpu == vk);
}

namespace {

// The run of a bench report with this backend and batch size.
const nlohmann::json& bench_run(const nlohmann::json& report, const std::string& backend, std::size_t sessions) {
  for (const auto& r : report["runs"])
    if (r["backend"] == backend && r["sessions_per_submission"] == sessions) return r;
  FAIL("no " << backend << " run of " << sessions << " sessions per submission");
  throw;
}

// Figures every bench run has, whatever its backend: host memory, throughput, zero-mass votes.
void check_bench_run(const nlohmann::json& r, const std::string& backend, std::size_t sessions, std::size_t trials) {
  INFO(backend << ", " << sessions << " per submission");
  CHECK(r["trials"] == trials);
  const auto& m = r["memory"];
  CHECK(m["peak_rss_bytes"].get<std::uint64_t>() > 0);
  CHECK(m["rss_before_bytes"].get<std::uint64_t>() > 0);
  CHECK(m["rss_after_bytes"].get<std::uint64_t>() > 0);
  CHECK(m["rss_increase_bytes"].get<std::int64_t>() ==
        m["rss_after_bytes"].get<std::int64_t>() - m["rss_before_bytes"].get<std::int64_t>());
  if (!m["peak_rss_during_bytes"].is_null()) {  // null only where VmHWM cannot be reset
    CHECK(m["peak_rss_during_bytes"].get<std::uint64_t>() >= m["rss_after_bytes"].get<std::uint64_t>());
    CHECK(m["peak_rss_during_bytes"].get<std::uint64_t>() <= m["peak_rss_bytes"].get<std::uint64_t>());
  }
  CHECK(r["session_updates_per_second"].get<double>() > 0);
  CHECK(r["votes_per_second"].get<double>() > 0);
  CHECK(r["votes"].get<std::uint64_t>() > 0);
  CHECK(r["votes_zero"].get<std::uint64_t>() <= r["votes"].get<std::uint64_t>());
  CHECK(r["votes_zero_fraction"].get<double>() >= 0.0);
  CHECK(r["votes_zero_fraction"].get<double>() <= 1.0);
  REQUIRE(r["curve"].size() == 2);
  for (const auto& p : r["curve"]) {
    CHECK(p["update_ms"].get<double>() > 0);
    CHECK(p["session_updates_per_second"].get<double>() > 0);
    CHECK(p["votes_zero_per_update"].get<double>() >= 0);
    CHECK(p["votes_zero_per_update"].get<double>() <= p["votes_per_update"].get<double>());
    CHECK(p["accuracy"].get<double>() >= 0.0);
  }
}

}  // namespace

TEST_CASE("sva bench reports host memory, zero-mass votes and the throughput of a batched CPU run") {
  Fixture f;
  std::string out;
  const std::string base = "bench --map " + f.map + " --data " + f.test + " --trials 2 ";
  const std::string bench = base + "--readings 2,4 ";
  REQUIRE(sva::test::run_sva(bench + "--backend cpu --batch 4 --json " + f.path("b.json"), &out) == 0);
  INFO(out);
  CHECK(out.find("upd/s") != std::string::npos);
  CHECK(out.find("peak RSS") != std::string::npos);
  CHECK(out.find("votes of mass 0") != std::string::npos);
  const auto j = nlohmann::json::parse(read_file(f.path("b.json")));
  REQUIRE(j["runs"].size() == 2);
  CHECK(j["peak_rss_bytes"].get<std::uint64_t>() > 0);
  check_bench_run(bench_run(j, "cpu", 1), "cpu", 1, 2);
  const auto& batch = bench_run(j, "cpu", 4);
  check_bench_run(batch, "cpu", 4, 4);  // a batch is filled: max(batch, trials) trials
  // With the estimate after every update, as a study that asks an answer after every reading runs: fewer per second.
  for (const auto* run : {&bench_run(j, "cpu", 1), &batch}) {
    CHECK((*run)["session_updates_with_estimates_per_second"].get<double>() > 0.0);
    CHECK((*run)["session_updates_with_estimates_per_second"].get<double>() <
          (*run)["session_updates_per_second"].get<double>());
  }
  CHECK(out.find("with their estimates), ") != std::string::npos);
  CHECK(batch["memory"]["device_bytes"] == 0);
  CHECK(batch["memory"]["map_device_bytes"] == 0);
  CHECK(batch["memory"]["device_held_bytes"] == 0);
  CHECK(j["peak_rss_bytes"].get<std::uint64_t>() >= batch["memory"]["peak_rss_bytes"].get<std::uint64_t>());
  CHECK_FALSE(j.contains("roofline"));  // no device measured
  for (const auto& p : batch["curve"])  // the device's round trips and allocations: none on the CPU, null not 0
    for (const char* key : {"update_device_submissions", "estimate_device_submissions", "update_device_allocations",
                            "estimate_device_allocations"})
      CHECK(p[key].is_null());
  for (const auto& p : batch["curve"]) CHECK(p["update_split_ms"].is_null());
  for (const auto& p : batch["curve"]) CHECK(p["kernel_ms_by_pipeline"].is_null());  // no kernels: null, not {}
  CHECK(out.find("the device's time by kernel") == std::string::npos);

  REQUIRE(sva::test::run_sva(bench + "--backend cpu --batch 0 --json " + f.path("single.json"), &out) == 0);
  const auto single = nlohmann::json::parse(read_file(f.path("single.json")))["runs"];
  REQUIRE(single.size() == 1);
  // --top-k: hypotheses per estimate (1 by default). More of them cost estimate time, not the first one's answer.
  REQUIRE(sva::test::run_sva(bench + "--backend cpu --batch 0 --top-k 3 --json " + f.path("top3.json"), &out) == 0);
  CHECK(out.find("top 3 per estimate") != std::string::npos);
  const auto top3 = nlohmann::json::parse(read_file(f.path("top3.json")))["runs"];
  REQUIRE(top3.size() == 1);
  CHECK(single[0]["top_k"] == 1);
  CHECK(top3[0]["top_k"] == 3);
  REQUIRE(top3[0]["curve"].size() == single[0]["curve"].size());
  for (std::size_t i = 0; i < single[0]["curve"].size(); ++i)
    for (const char* key : {"accuracy", "translation_error_mm", "votes_per_update"})
      CHECK(top3[0]["curve"][i][key] == single[0]["curve"][i][key]);
  // A single-session run with other estimate options: the summary line names them, and the votes are the same
  // (they change what the estimate reads or fits, never the votes).
  const auto variant = [&](const std::string& options, const std::string& name, const std::string& printed) {
    REQUIRE(sva::test::run_sva(bench + "--backend cpu --batch 0 " + options + " --json " + f.path(name), &out) == 0);
    CHECK(out.find(printed) != std::string::npos);
    const auto runs = nlohmann::json::parse(read_file(f.path(name)))["runs"];
    REQUIRE(runs.size() == 1);
    REQUIRE(runs[0]["curve"].size() == single[0]["curve"].size());
    for (std::size_t i = 0; i < single[0]["curve"].size(); ++i)
      CHECK(runs[0]["curve"][i]["votes_per_update"] == single[0]["curve"][i]["votes_per_update"]);
    return runs[0];
  };
  // --refine off --surface-check off: the estimate's host stages asked for are recorded and printed.
  const auto light =
      variant("--refine off --surface-check off", "light.json", "top 1 per estimate, refine off, surface check off)");
  CHECK(single[0]["refine_pose"] == true);
  CHECK(single[0]["surface_check"] == true);
  CHECK(light["refine_pose"] == false);
  CHECK(light["surface_check"] == false);
  // --estimate light: the belief's answer after every update, no host fits; recorded and printed.
  const auto belief = variant("--estimate light", "belief.json", "top 1 per estimate, light estimates (no host fits))");
  CHECK(single[0]["estimate"] == "full");
  CHECK(belief["estimate"] == "light");
  // --pose-prior: every session gets a camera's prior at its trial's true pose, recorded and printed. It reweights
  // the bins the estimate reads, never the votes: other poses (a 1 mm prior pulls them).
  const auto prior = variant("--pose-prior 1,10", "prior.json", "surface check on, pose prior 1 mm and 10 deg)");
  CHECK(single[0]["pose_prior"].is_null());
  CHECK(prior["pose_prior"]["position_sigma_mm"] == 1.0);
  CHECK(prior["pose_prior"]["rotation_sigma_deg"] == 10.0);
  bool moved = false;
  for (std::size_t i = 0; i < single[0]["curve"].size(); ++i)
    moved = moved || prior["curve"][i]["translation_error_mm"] != single[0]["curve"][i]["translation_error_mm"];
  CHECK(moved);
  // --max-pairs bounds the pairs per update: the new reading with the most recent one only (2 pairs, both orders)
  // casts fewer votes at 6 readings than with all 5 earlier ones, and the report says which ran.
  const std::string six = base + "--readings 2,6 --backend cpu --batch 0 ";
  REQUIRE(sva::test::run_sva(six + "--json " + f.path("exact.json"), &out) == 0);
  REQUIRE(sva::test::run_sva(six + "--max-pairs 2 --json " + f.path("bounded.json"), &out) == 0);
  CHECK(out.find("surface check on, max pairs 2)") != std::string::npos);
  const auto exact = nlohmann::json::parse(read_file(f.path("exact.json")))["runs"][0];
  const auto bounded = nlohmann::json::parse(read_file(f.path("bounded.json")))["runs"][0];
  CHECK(exact["max_pairs_per_update"] == 0);
  CHECK(bounded["max_pairs_per_update"] == 2);
  CHECK(bounded["curve"][0]["votes_per_update"] == exact["curve"][0]["votes_per_update"]);  // 2 readings: 1 pair
  CHECK(bounded["curve"][1]["votes_per_update"].get<double>() < exact["curve"][1]["votes_per_update"].get<double>());
  // The CPU reference counts its work: every bin was probed for at least once in the pair's table and in the
  // belief, every match came from a map entry, and the votes are the curve's.
  for (const auto& point : exact["curve"]) {
    const auto& w = point["work_per_update"];
    REQUIRE(w.is_object());
    CHECK(w["votes"].get<double>() == point["votes_per_update"].get<double>());
    CHECK(w["pairs"].get<double>() >= 1.0);
    CHECK(w["map_entries"].get<double>() >= w["matches"].get<double>());
    CHECK(w["bins"].get<double>() > 0.0);
    CHECK(w["vote_table_probes"].get<double>() >= w["bins"].get<double>());
    CHECK(w["belief_probes"].get<double>() >= w["bins"].get<double>());
    CHECK(w["bytes"]["map"].get<double>() > 0.0);
    // A live session's memory: its belief's tables, which only grow without a budget.
    CHECK(point["belief_bytes_per_session"].get<double>() > 0.0);
    CHECK(point["belief_bytes_per_session_max"].get<double>() >= point["belief_bytes_per_session"].get<double>());
    CHECK(w["vote_table_atomics"].is_null());  // the CPU has none: the model assumes two per vote
    CHECK(point["gpu_model"]["atomics_counted"] == false);
    CHECK(point["gpu_model"]["atomics"].get<double>() >= 2 * w["votes"].get<double>());
  }
  CHECK(exact["curve"][1]["belief_bytes_per_session"].get<double>() >=
        exact["curve"][0]["belief_bytes_per_session"].get<double>());
  CHECK(bounded["curve"][1]["work_per_update"]["pairs"].get<double>() ==
        1.0);  // 2 pairs: one order voted, folded twice
  // --likelihood-cutoff: matches below it cast no vote, so the same pairs cast fewer votes; the report says which ran.
  REQUIRE(sva::test::run_sva(six + "--likelihood-cutoff 0.4 --json " + f.path("cut.json"), &out) == 0);
  CHECK(out.find("surface check on, likelihood cut-off 0.4)") != std::string::npos);
  const auto cut = nlohmann::json::parse(read_file(f.path("cut.json")))["runs"][0];
  CHECK(exact["likelihood_cutoff"] == 0.0);
  CHECK(cut["likelihood_cutoff"].get<double>() == Approx(0.4));
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(cut["curve"][i]["work_per_update"]["pairs"] == exact["curve"][i]["work_per_update"]["pairs"]);
    CHECK(cut["curve"][i]["votes_per_update"].get<double>() < exact["curve"][i]["votes_per_update"].get<double>());
  }
  for (const std::string bad :
       {"--batch -1", "--batch x", "--backend gpu", "--readings 0", "--max-pairs -1", "--top-k 0",
        "--surface-check maybe", "--estimate fine", "--pose-prior 0", "--pose-prior 5,200", "--pose-prior 5,",
        "--pose-prior x", "--likelihood-cutoff -0.1", "--likelihood-cutoff 200", "--likelihood-cutoff x"}) {
    INFO(bad);
    CHECK(sva::test::run_sva(base + bad, &out) != 0);
    CHECK(out.find(bad.substr(bad.find(' ') + 1)) != std::string::npos);
    CHECK(out.find("internal error") == std::string::npos);
  }
}

TEST_CASE("sva bench --warm: the timed sessions start with the tables their group reaches, the same votes and errors") {
  Fixture f;
  std::string out;
  const std::string bench =
      "bench --map " + f.map + " --data " + f.test + " --trials 4 --readings 2,8 --backend cpu --batch 4 ";
  REQUIRE(sva::test::run_sva(bench + "--json " + f.path("cold.json"), &out) == 0);
  CHECK(out.find("warm tables") == std::string::npos);
  REQUIRE(sva::test::run_sva(bench + "--warm on --json " + f.path("warm.json"), &out) == 0);
  INFO(out);
  CHECK(out.find("surface check on, warm tables)") != std::string::npos);
  const auto cold = nlohmann::json::parse(read_file(f.path("cold.json")))["runs"];
  const auto warm = nlohmann::json::parse(read_file(f.path("warm.json")))["runs"];
  REQUIRE(cold.size() == 2);
  REQUIRE(warm.size() == 2);
  for (std::size_t r = 0; r < 2; ++r) {
    CHECK(cold[r]["warm"] == false);
    CHECK(warm[r]["warm"] == true);
    REQUIRE(warm[r]["curve"].size() == 2);
    REQUIRE(cold[r]["curve"].size() == 2);
    for (std::size_t i = 0; i < 2; ++i)  // a reset session's tables change how fast, never what, it answers
      for (const char* key : {"votes_per_update", "accuracy", "translation_error_mm"})
        CHECK(warm[r]["curve"][i][key] == cold[r]["curve"][i][key]);
  }
  // The batch's sessions grow their beliefs between 2 and 8 readings; warm, they hold the size at 2 already.
  const auto bytes = [](const nlohmann::json& run, std::size_t i) {
    return run["curve"][i]["belief_bytes_per_session"].get<double>();
  };
  INFO("belief bytes per session at 2 and 8 readings: cold " << bytes(cold[1], 0) << ", " << bytes(cold[1], 1)
                                                             << "; warm " << bytes(warm[1], 0) << ", "
                                                             << bytes(warm[1], 1));
  // (A belief's bytes are its offset tables and its band's list, which varies by a few hundred bytes.)
  REQUIRE(bytes(cold[1], 1) > 2 * bytes(cold[1], 0));
  CHECK(bytes(warm[1], 0) > 0.99 * bytes(cold[1], 1));
  CHECK(bytes(warm[1], 1) == Approx(bytes(cold[1], 1)).epsilon(0.01));
  CHECK(sva::test::run_sva(bench + "--warm maybe", &out) != 0);
  CHECK(out.find("maybe") != std::string::npos);
}

TEST_CASE("sva bench untimed (SVA_VK_TIMESTAMPS=0) and serial (SVA_VK_SERIAL=1): the same votes, kernels n/a") {
  // The device check's A/B of a batch's passes side by side against one at a time: the wall time without a timestamp
  // between dispatches. Both switches change how the work is recorded, never what it computes.
  Fixture f;
  std::string out;
  const std::string bench = "bench --backend vulkan --map " + f.map + " --data " + f.test +
                            " --readings 2,4 --trials 3 --batch 3 --roofline-votes 4096 --json ";
  if (sva::test::run_sva(bench + f.path("timed.json"), &out) != 0) {
    if (out.find("ulkan") != std::string::npos && out.find("internal error") == std::string::npos)
      sva::test::skip("no Vulkan device: " + out);
    FAIL(out);
  }
  {
    const sva::test::ScopedEnv untimed("SVA_VK_TIMESTAMPS", "0"), serial("SVA_VK_SERIAL", "1");
    REQUIRE(sva::test::run_sva(bench + f.path("untimed.json"), &out) == 0);
  }
  INFO(out);
  const auto timed = nlohmann::json::parse(read_file(f.path("timed.json")));
  const auto untimed = nlohmann::json::parse(read_file(f.path("untimed.json")));
  const auto& a = bench_run(timed, "vulkan", 3)["curve"];
  const auto& b = bench_run(untimed, "vulkan", 3)["curve"];
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i]["votes_per_update"] == b[i]["votes_per_update"]);
    CHECK(a[i]["translation_error_mm"] == b[i]["translation_error_mm"]);
    CHECK(b[i]["update_split_ms"]["kernels"].is_null());
    CHECK(b[i]["kernel_ms_by_pipeline"].is_null());
    CHECK(b[i]["update_ms"].get<double>() > 0.0);
  }
  CHECK(out.find("the device's time by kernel") == std::string::npos);
}

TEST_CASE("sva bench on the Vulkan backend reports device memory (n/a until the backend fills it)") {
  Fixture f;
  std::string out;
  const std::string bench = "bench --map " + f.map + " --data " + f.test + " --readings 2,4 --trials 2 --batch 3 ";
  if (sva::test::run_sva(bench + "--backend vulkan --roofline-votes 4096 --json " + f.path("vk.json"), &out) != 0) {
    if (out.find("ulkan") != std::string::npos && out.find("internal error") == std::string::npos)
      sva::test::skip("no Vulkan device: " + out);
    FAIL(out);
  }
  INFO(out);
  const auto j = nlohmann::json::parse(read_file(f.path("vk.json")));
  REQUIRE(j["runs"].size() == 2);
  check_bench_run(bench_run(j, "vulkan", 1), "vulkan", 1, 2);
  const auto& batch = bench_run(j, "vulkan", 3);
  check_bench_run(batch, "vulkan", 3, 3);
  for (const char* key : {"device_bytes", "map_device_bytes"}) {
    const auto& bytes = batch["memory"][key];
    CHECK((bytes.is_null() || bytes.get<std::uint64_t>() > 0));  // null: not reported, never "0 bytes"
  }
  if (batch["memory"]["device_bytes"].is_null()) CHECK(out.find("device: n/a") != std::string::npos);
  // The memory pool's allocations hold every buffer, the map's included, and the blocks' free ranges.
  if (!batch["memory"]["device_bytes"].is_null())
    CHECK(batch["memory"]["device_held_bytes"].get<std::uint64_t>() >=
          batch["memory"]["device_bytes"].get<std::uint64_t>());
  CHECK(out.find("allocations hold") != std::string::npos);
  CHECK(j["roofline"]["votes_per_second"].get<double>() > 0);
  CHECK(j["roofline"]["vote_math"]["exact_agrees_with_cpu"] == true);  // the math alone, the engine's bits
  CHECK(j["roofline"]["vote_math"]["samples"].get<std::uint64_t>() > 0);
  // A kernel's result read by the host in place and from a host-cached copy: the same words, each pass timed.
  const auto& host_reads = j["roofline"]["host_reads"];
  CHECK(host_reads["sums_agree"] == true);
  CHECK(host_reads["loads"].get<std::uint64_t>() > 0);
  CHECK(host_reads["mapped_ns_per_load"].get<double>() > 0.0);
  CHECK(host_reads["readback_ns_per_load"].get<double>() > 0.0);
  CHECK(out.find("host reads of a kernel's result") != std::string::npos);
  // Round trips and memory allocations per session, counted: the batch's first updates make its vote tables, input
  // buffers and, after the sessions' first estimates, the buffers of the estimates' reads made in the update, as
  // ranges of the memory pool's blocks: at most a block a session (tests/backends/vulkan count the blocks).
  for (const auto& point : batch["curve"])
    for (const char* key : {"update_device_submissions", "estimate_device_submissions", "update_device_allocations",
                            "estimate_device_allocations"})
      CHECK(point[key].get<double>() >= 0.0);
  CHECK(batch["curve"][0]["update_device_allocations"].get<double>() <= 1.0);
  // An update's time by part: every update records and waits for its submissions; the parts that need the device's
  // timestamps are null without them, never negative.
  for (const auto& point : batch["curve"]) {
    const auto& u = point["update_split_ms"];
    REQUIRE(u.is_object());
    if (u["device_between_kernels"].is_null())
      CHECK(u["kernels"].is_null());  // untimed: in no part, not 0 ms
    else
      CHECK(u["kernels"].get<double>() > 0.0);
    CHECK(u["recording"].get<double>() > 0.0);
    for (const char* key : {"host_outside_submissions", "belief_growth"}) CHECK(u[key].get<double>() >= 0.0);
    for (const char* key : {"device_between_kernels", "wait_past_device"})
      CHECK((u[key].is_null() || u[key].get<double>() >= 0.0));
  }
  CHECK(out.find("an update's time by part") != std::string::npos);
  // The device's time by kernel: per pipeline, the votes and the fold in every update, a dispatch at least; null
  // where the device has no timestamps (as the split's device parts).
  for (const auto& point : batch["curve"]) {
    const auto& k = point["kernel_ms_by_pipeline"];
    if (point["update_split_ms"]["device_between_kernels"].is_null()) {
      CHECK(k.is_null());
      continue;
    }
    REQUIRE(k.is_object());
    CHECK((k.contains("match_votes") || k.contains("match_votes_portable")));
    // The fold's passes each under its own name (a batch's fold column is mostly the belief passes read ahead).
    for (const char* pass : {"belief_fold:reserve", "belief_fold:add", "belief_fold:best"}) {
      INFO(pass);
      REQUIRE(k.contains(pass));
      CHECK(k[pass]["ms"].get<double>() > 0.0);
    }
    for (const auto& [name, v] : k.items()) {
      INFO(name);
      CHECK(v["dispatches"].get<double>() > 0.0);
      CHECK(v["ms"].get<double>() >= 0.0);
    }
    CHECK(out.find("the device's time by kernel") != std::string::npos);
    CHECK(out.find("belief_fold:add") != std::string::npos);
  }
  CHECK(out.find("upd. alloc.") != std::string::npos);
  CHECK(out.find("est. alloc.") != std::string::npos);
  // The device counts its work: the vote tables' atomics (a compare-and-swap per probe, an add per pre-aggregated
  // vote), not its belief probes; the model of an H100 reads the device's count.
  for (const auto& point : batch["curve"]) {
    const auto& w = point["work_per_update"];
    REQUIRE(w.is_object());
    CHECK(w["votes"].get<double>() == point["votes_per_update"].get<double>());
    CHECK(w["map_entries"].get<double>() >= w["matches"].get<double>());
    CHECK(w["vote_table_probes"].get<double>() >= w["bins"].get<double>());
    CHECK(w["vote_table_atomics"].get<double>() >= w["vote_table_probes"].get<double>() + w["bins"].get<double>());
    CHECK(w["belief_probes"].is_null());
    const auto& m = point["gpu_model"];
    REQUIRE(m.is_object());
    CHECK(m["atomics_counted"] == true);
    CHECK(m["low_ms"].get<double>() > 0.0);
    CHECK(m["high_ms"].get<double>() >= m["low_ms"].get<double>());
  }
  CHECK(out.find("model of the GPU time per session-update") != std::string::npos);
}

TEST_CASE("sva eval --policy: random is the default bit for bit, active plans each touch, the same on 1 or 2 threads") {
  Fixture f;
  std::string out;
  const std::string common = f.base() + "--trials 4 --max-readings 6 --seed 3 ";
  REQUIRE(sva::test::run_sva(common + "--json " + f.path("default.json"), &out) == 0);
  CHECK(out.find("policy random: readings until the true object holds >= 95%") != std::string::npos);
  REQUIRE(sva::test::run_sva(common + "--policy random --json " + f.path("random.json"), &out) == 0);
  auto def = without_timing(f.path("default.json")), rnd = without_timing(f.path("random.json"));
  CHECK(def == rnd);
  CHECK(rnd["policy"] == "random");
  CHECK(rnd["plan_ms_median"].is_null());

  REQUIRE(sva::test::run_sva(common + "--policy active --threads 1 --json " + f.path("a1.json") + " --plot " +
                                 f.path("ar.png") + " --compare " + f.path("random.json"),
                             &out) == 0);
  CHECK(out.find("policy active") != std::string::npos);
  CHECK(std::filesystem::file_size(f.path("ar.png")) > 1000);
  REQUIRE(sva::test::run_sva(common + "--policy active --threads 2 --json " + f.path("a2.json"), &out) == 0);
  auto a1 = without_timing(f.path("a1.json")), a2 = without_timing(f.path("a2.json"));
  a1.erase("plan_ms_median");
  a2.erase("plan_ms_median");
  CHECK(a1 == a2);
  CHECK(a1["policy"] == "active");
  // The first reading is the random policy's own; the plans start once the estimate has a pose.
  CHECK(a1["curve"][0] == rnd["curve"][0]);
  const auto& c = a1["readings_to_95"];
  CHECK(c["trials"] == 4);
  CHECK(c["mean"].get<double>() >= 1.0);
  CHECK(c["mean"].get<double>() <= 7.0);
  CHECK(nlohmann::json::parse(read_file(f.path("a1.json")))["plan_ms_median"].get<double>() > 0.0);

  // Candidates sampled on the hypotheses' surfaces and the second touch at random: the first two readings are the
  // random policy's, so the curve's first two points are its own.
  REQUIRE(sva::test::run_sva(common +
                                 "--policy active --candidates-from hypotheses --candidates 30 --plan-second 0 "
                                 "--json " +
                                 f.path("h.json"),
                             &out) == 0);
  auto h = without_timing(f.path("h.json"));
  CHECK(h["curve"][0] == rnd["curve"][0]);
  CHECK(h["curve"][1] == rnd["curve"][1]);
}

TEST_CASE("sva eval --policy refuses what it cannot run, naming it") {
  Fixture f;
  std::string out;
  CHECK(sva::test::run_sva(f.base() + "--policy greedy", &out) != 0);
  CHECK(out.find("greedy") != std::string::npos);
  CHECK(sva::test::run_sva(f.base() + "--candidates 10", &out) != 0);
  CHECK(out.find("--policy active") != std::string::npos);
  CHECK(sva::test::run_sva(f.base() + "--policy active --candidates-from hypotheses --candidates 0", &out) != 0);
  CHECK(out.find("--candidates") != std::string::npos);
  // Sampled candidates only where they are used; the candidate source by name.
  CHECK(sva::test::run_sva(f.base() + "--policy active --candidates 10", &out) != 0);
  CHECK(out.find("--candidates-from hypotheses") != std::string::npos);
  CHECK(sva::test::run_sva(f.base() + "--policy active --candidates-from camera", &out) != 0);
  CHECK(out.find("camera") != std::string::npos);
  CHECK(sva::test::run_sva(f.base() + "--plan-second 3", &out) != 0);
  CHECK(out.find("--policy active") != std::string::npos);
  // The tiny scene's meshes do not exist: active-sim cannot press its touches.
  CHECK(sva::test::run_sva(f.base() + "--policy active-sim --trials 2 --max-readings 3", &out) != 0);
  CHECK(out.find("active-sim") != std::string::npos);
  CHECK(out.find("ball") != std::string::npos);
  CHECK(out.find("internal error") == std::string::npos);
}

TEST_CASE("sva eval reports the calibration and the decisions at --stop-at, and names bad values") {
  Fixture f;
  std::string out;
  const std::string common = f.base() + "--trials 4 --max-readings 5 --seed 7 ";
  REQUIRE(sva::test::run_sva(
              common + "--stop-at 0.9 --reliability " + f.path("rel.png") + " --json " + f.path("s.json"), &out) == 0);
  CHECK(out.find("calibration: ECE") != std::string::npos);
  CHECK(out.find("stop at 0.9:") != std::string::npos);
  CHECK(read_file(f.path("rel.png")).substr(1, 3) == "PNG");
  const auto j = nlohmann::json::parse(read_file(f.path("s.json")));
  CHECK(j["calibration"]["trial_readings"] == 4 * 4);
  CHECK(j["calibration"]["reliability"].size() == 10);
  CHECK(out.find("  by readings: 2-5 ECE") != std::string::npos);
  REQUIRE(j["calibration"]["by_readings"].size() == 1);  // 5 readings: the first range alone
  CHECK(j["calibration"]["by_readings"][0]["readings"] == nlohmann::json::array({2, 5}));
  CHECK(j["calibration"]["by_readings"][0]["trial_readings"] == 4 * 4);
  CHECK(j["calibration"]["by_readings"][0]["ece"] == j["calibration"]["ece"]);
  CHECK(j["stop"]["threshold"] == 0.9);
  CHECK(j["stop"]["trials"] == 4);
  CHECK_FALSE(j.contains("unknown_objects"));  // every test object is the map's
  // Raw Eq 5: p_unknown is 0 and the decisions come no later than calibrated ones.
  REQUIRE(sva::test::run_sva(common + "--calibration off --stop-at 0.9 --json " + f.path("raw.json"), &out) == 0);
  const auto raw = nlohmann::json::parse(read_file(f.path("raw.json")));
  CHECK(raw["stop"]["decided"].get<int>() >= j["stop"]["decided"].get<int>());
  // Bad values are named.
  CHECK(sva::test::run_sva(common + "--stop-at 0.2", &out) != 0);
  CHECK(out.find("--stop-at") != std::string::npos);
  CHECK(sva::test::run_sva(common + "--unknown-prior 1", &out) != 0);
  CHECK(out.find("--unknown-prior") != std::string::npos);
  // One reading per trial has no trial-reading from 2 on to draw.
  CHECK(sva::test::run_sva(f.base() + "--trials 2 --max-readings 1 --reliability " + f.path("none.png"), &out) != 0);
  CHECK(out.find("none.png") != std::string::npos);
}

TEST_CASE("sva eval --confusion writes the matrices and the figure, prints the per-object table, names bad counts") {
  Fixture f;
  std::string out;
  const std::string common = f.base() + "--trials 4 --max-readings 5 --seed 7 ";
  REQUIRE(sva::test::run_sva(common + "--confusion " + f.path("c.json") + " --confusion-at 2,5", &out) == 0);
  CHECK(out.find("acc@2") != std::string::npos);
  CHECK(out.find("acc@5") != std::string::npos);
  CHECK(read_file(f.path("c.png")).substr(1, 3) == "PNG");
  const auto j = nlohmann::json::parse(read_file(f.path("c.json")));
  REQUIRE(j["confusion"].size() == 2);
  CHECK(j["confusion"][1]["readings"] == 5);
  std::size_t trials = 0;
  for (const auto& row : j["confusion"][1]["counts"])
    for (const auto& n : row) trials += n.get<std::size_t>();
  CHECK(trials == 4);
  // The default counts are 15 and 30 within the run: here its last reading only.
  REQUIRE(sva::test::run_sva(common + "--confusion " + f.path("d.json"), &out) == 0);
  CHECK(nlohmann::json::parse(read_file(f.path("d.json")))["confusion"][0]["readings"] == 5);
  CHECK(sva::test::run_sva(common + "--confusion " + f.path("e.json") + " --confusion-at 9", &out) != 0);
  CHECK(out.find("--confusion-at 9") != std::string::npos);
  CHECK(sva::test::run_sva(common + "--confusion-at 2", &out) != 0);
  CHECK(out.find("needs --confusion") != std::string::npos);
  CHECK(sva::test::run_sva(common + "--confusion " + f.path("no/dir/c.json"), &out) != 0);
  CHECK(out.find("does not exist") != std::string::npos);
  // The pairs alone (the surface check off) on the same trials, and a bad value named.
  REQUIRE(sva::test::run_sva(common + "--surface-check off --confusion " + f.path("off.json"), &out) == 0);
  CHECK(nlohmann::json::parse(read_file(f.path("off.json")))["confusion"][0]["readings"] == 5);
  CHECK(sva::test::run_sva(common + "--surface-check maybe", &out) != 0);
  CHECK(out.find("--surface-check") != std::string::npos);
}

TEST_CASE("sva view writes a trial's page with its data, sva eval --html a page per trial, bad input is named") {
  Fixture f;  // its scene's meshes do not exist: the pages say so and show the session without them
  std::string out;
  const std::string view = "view --map " + f.map + " --data " + f.test + " --max-readings 4 --backend cpu ";
  REQUIRE(sva::test::run_sva(view + "--trial 1 --out " + f.path("t1.html"), &out) == 0);
  CHECK(out.find("no mesh for") != std::string::npos);
  const std::string page = read_file(f.path("t1.html"));
  const auto at = page.find("<script id=\"sva-data\" type=\"application/json\">");
  REQUIRE(at != std::string::npos);
  const auto start = page.find('\n', at) + 1, end = page.find("\n</script>", start);
  const auto data = nlohmann::json::parse(page.substr(start, end - start));
  CHECK(data["readings"].size() == 4);
  CHECK(data["steps"].size() == 4);
  CHECK(data["truth"].is_object());
  CHECK(data["objects"].size() == 2);
  CHECK(page.find("THREE") != std::string::npos);  // three.js inlined: the page needs nothing else
  // Four scripts (three.js, its orbit controls, the data, the viewer), each ended once: no "</" inside them ends one
  // early.
  const auto count = [&](const std::string& s) {
    std::size_t n = 0;
    for (auto p = page.find(s); p != std::string::npos; p = page.find(s, p + 1)) ++n;
    return n;
  };
  CHECK(count("</script>") == 4);
  // A session of a sessions file: --session or --id picks it; bad picks and scene files are named.
  REQUIRE(sva::test::run_sva("recognize --write-sessions " + f.path("s.jsonl") + " --map " + f.map + " --data " +
                                 f.test + " --trials 3 --max-readings 4",
                             &out) == 0);
  const std::string from_sessions = "view --map " + f.map + " --sessions " + f.path("s.jsonl") + " --backend cpu ";
  CHECK(sva::test::run_sva(from_sessions + "--id trial-2 --scene " + f.path("none.json") + " --out " + f.path("x.html"),
                           &out) != 0);
  CHECK(out.find("none.json") != std::string::npos);
  REQUIRE(sva::test::run_sva(from_sessions + "--id trial-2 --out " + f.path("s2.html"), &out) == 0);
  const std::string s2 = read_file(f.path("s2.html"));
  CHECK(s2.find("\"title\":\"session trial-2\"") != std::string::npos);
  CHECK(s2.find("\"truth\":{") != std::string::npos);  // the file's truth: the ghost
  CHECK(sva::test::run_sva(from_sessions + "--session 7 --out " + f.path("x.html"), &out) != 0);
  CHECK(out.find("session 7 out of range (3 sessions)") != std::string::npos);
  CHECK(sva::test::run_sva(from_sessions + "--id nope --out " + f.path("x.html"), &out) != 0);
  CHECK(out.find("no session with id \"nope\"") != std::string::npos);
  REQUIRE(sva::test::run_sva(f.base() + "--trials 2 --max-readings 4 --backend cpu --html " + f.path("pages"), &out) ==
          0);
  for (const char* file : {"index.html", "trial-0.html", "trial-1.html", "accuracy.png", "accuracy.svg"}) {
    INFO(file);
    CHECK(std::filesystem::exists(f.dir / "pages" / file));
  }
  for (const auto& [bad, says] : std::vector<std::pair<std::string, std::string>>{
           {"view --map " + f.map + " --out " + f.path("x.html"), "exactly one of --data"},
           {view + "--sessions s.jsonl --out " + f.path("x.html"), "exactly one of --data"},
           {view + "--trial 1", "--out"},
           {view + "--trial -1 --out " + f.path("x.html"), "--trial"},
           {f.base() + "--trials 2 --max-readings 4 --policy active --html " + f.path("p2"), "--html"}}) {
    INFO(bad);
    CHECK(sva::test::run_sva(bad, &out) != 0);
    CHECK(out.find(says) != std::string::npos);
    CHECK(out.find("internal error") == std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(f.dir / "x.html"));
}
