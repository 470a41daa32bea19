// Files valid in form but absurd in content: sizes that would need terabytes, counts that overflow, unsorted map
// keys, a scene of a million objects, a glTF accessor of trillions of elements. Every loader must answer with
// sva::Error naming the file and the fault before it allocates for the claimed size (the test would otherwise
// run out of memory or time).
#include <catch2/catch.hpp>

#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/scene.hpp>

#include <cstdlib>
#include <fstream>
#include <limits>

#include <sva/io/binary_file.hpp>
#include <sva/io/recording_file.hpp>
#include "map/map_file.hpp"
#include "recognition/session_file.hpp"
#include "test_support.hpp"
#if __has_include(<sva/sim/mesh.hpp>)
#include <sva/sim/mesh.hpp>
#define SVA_TEST_HAVE_SIM 1
#endif
#if __has_include(<sva/drivers/session.hpp>)
#include <sva/drivers/calibration.hpp>
#include <sva/drivers/frame.hpp>
#include <sva/drivers/session.hpp>
#define SVA_TEST_HAVE_DRIVERS 1
#endif

namespace fs = std::filesystem;
using sva::io::BinaryWriter;

namespace {

constexpr std::uint64_t kTera = std::uint64_t{1} << 40;
constexpr std::uint64_t kHuge = std::numeric_limits<std::uint64_t>::max() / 4;

std::string tiny_scene_json() {
  std::ifstream in(fs::path(std::getenv("SVA_ASSETS")) / "scenes" / "tiny.json");
  return {std::istreambuf_iterator<char>(in), {}};
}

// The fuzz corpus of the source tree; a bundle for a GPU machine (scripts/bundle.sh) carries only the assets.
fs::path corpus() {
  const auto dir = fs::path(std::getenv("SVA_ASSETS")) / ".." / "tests" / "fuzz" / "corpus";
  if (!fs::is_directory(dir)) sva::test::skip("no fuzz corpus beside the assets (" + dir.string() + ")");
  return dir;
}

}  // namespace

TEST_CASE("absurd dataset: a sample count or scene length that would need terabytes") {
  const auto dir = sva::test::temp_dir("absurd-dataset");
  for (std::uint64_t count : {kTera, kHuge, std::numeric_limits<std::uint64_t>::max()}) {
    BinaryWriter w;
    w.put_string(sva::scene_to_json(sva::parse_scene(tiny_scene_json(), "tiny.json")));
    w.put_string("train");
    w.put<std::uint64_t>(7);
    w.put<std::uint64_t>(count);
    w.write_file(dir / "count.svad", "SVADATA1", 2);
    CHECK_THROWS_WITH(sva::load_dataset(dir / "count.svad"),
                      Catch::Contains("count.svad") && Catch::Contains("sample count " + std::to_string(count)));
  }
  BinaryWriter w;
  w.put<std::uint64_t>(kTera);  // the embedded scene's length
  w.write_file(dir / "scene.svad", "SVADATA1", 2);
  CHECK_THROWS_WITH(sva::load_dataset(dir / "scene.svad"),
                    Catch::Contains("scene.svad") && Catch::Contains("string length"));
}

TEST_CASE("absurd map: huge counts, unsorted keys, entries past the readings") {
  const auto dir = sva::test::temp_dir("absurd-map");
  const sva::PairMap good = *sva::load_pair_map(corpus() / "map" / "small-v3.svam");

  auto m = good;
  std::swap(m.keys[0], m.keys[1]);
  sva::write_pair_map(m, dir / "unsorted.svam", sva::kMapVersion);
  CHECK_THROWS_WITH(sva::load_pair_map(dir / "unsorted.svam"),
                    Catch::Contains("unsorted.svam") && Catch::Contains("keys are not strictly increasing"));

  m = good;
  m.offsets[1] = std::numeric_limits<std::uint32_t>::max();
  sva::write_pair_map(m, dir / "offset.svam", sva::kMapVersion);
  CHECK_THROWS_WITH(sva::load_pair_map(dir / "offset.svam"), Catch::Contains("offset.svam"));
  sva::write_pair_map(m, dir / "offset-v1.svam", 1);
  CHECK_THROWS_WITH(sva::load_pair_map(dir / "offset-v1.svam"), Catch::Contains("offset-v1.svam"));

  m = good;
  m.entry_b[0] = std::numeric_limits<std::uint32_t>::max();
  sva::write_pair_map(m, dir / "entry.svam", sva::kMapVersion);
  CHECK_THROWS_WITH(sva::load_pair_map(dir / "entry.svam"), Catch::Contains("references a reading out of range"));

  m = good;  // k * k * bins past the key space (4096 classes, 65535 bins): the key table cannot be addressed
  m.key_space.n_classes = 4096;
  m.distance.count = m.key_space.n_dist_bins = 65535;
  sva::write_pair_map(m, dir / "space.svam", sva::kMapVersion);
  CHECK_THROWS_WITH(sva::load_pair_map(dir / "space.svam"), Catch::Contains("space.svam"));

  // An array length of a terabyte of floats, at the first array (the medoid table): refused from the file size.
  BinaryWriter w;
  w.put_string("absurd");
  for (int i = 0; i < 3; ++i) w.put<std::uint64_t>(0);  // hash, seed, ambiguity
  w.put<std::uint8_t>(0);
  w.put<std::int32_t>(10);
  w.put<double>(-10);
  w.put<double>(10);
  w.put<std::int32_t>(10);
  w.put<std::uint8_t>(0);
  for (int i = 0; i < 2; ++i) w.put<std::int32_t>(6);
  for (int i = 0; i < 3; ++i) w.put<double>(1);
  for (int i = 0; i < 4; ++i) w.put<std::uint32_t>(2);
  w.put<float>(0.5f);
  w.put<std::uint64_t>(kTera);
  w.write_file(dir / "medoids.svam", sva::kMapMagic, sva::kMapVersion);
  CHECK_THROWS_WITH(sva::load_pair_map(dir / "medoids.svam"),
                    Catch::Contains("medoids.svam") && Catch::Contains("array length " + std::to_string(kTera)));
}

TEST_CASE("absurd saved session: a reading count past the file") {
  const auto dir = sva::test::temp_dir("absurd-session");
  for (std::uint64_t count : {std::uint64_t{100}, kTera, std::numeric_limits<std::uint64_t>::max()}) {
    BinaryWriter w;
    w.put<std::uint64_t>(1);
    w.put<std::uint32_t>(2);
    w.put_string("tiny");
    w.put_vector(std::vector<double>{});
    w.put<std::uint64_t>(count);
    w.put_array(std::vector<std::uint8_t>(200, 0).data(), 200);  // room for 2 readings, not 100
    w.write_file(dir / "s.svas", "SVASESS1", 1);
    CHECK_THROWS_WITH(sva::io::load_session_file(dir / "s.svas"),
                      Catch::Contains("s.svas") && Catch::Contains(std::to_string(count) + " readings exceed"));
  }
}

TEST_CASE("absurd scene: a million objects") {
  std::string text = "{\"objects\": [";
  for (int i = 0; i < 1000000; ++i) text += (i ? ",{\"mesh\":\"m" : "{\"mesh\":\"m") + std::to_string(i) + ".glb\"}";
  text += "]}";
  CHECK_THROWS_WITH(sva::parse_scene(text, "million.json"),
                    Catch::Contains("million.json") && Catch::Contains("1000000 objects"));
}

#ifdef SVA_TEST_HAVE_DRIVERS
TEST_CASE("absurd recording: record sizes and pressure images past the file") {
  const auto dir = sva::test::temp_dir("absurd-recording");
  const auto file = dir / "r.svar";
  {
    sva::drivers::SessionSettings settings;
    settings.calibration = sva::drivers::Calibration::uniform({2, 2, 2.0}, 0.05f, 100.0f);
    sva::drivers::SessionWriter w(file, settings, false);
  }
  {  // a record header claiming 4 GiB: the recording is valid up to it, nothing is allocated for it
    std::ofstream out(file, std::ios::binary | std::ios::app);
    const std::uint32_t type = 2, size = 0xffffffffu;
    out.write(reinterpret_cast<const char*>(&type), 4).write(reinterpret_cast<const char*>(&size), 4);
    out << std::string(64, 'x');
  }
  const auto s = sva::drivers::load_session(file);
  CHECK(s.tail_problem.find("truncated record") != std::string::npos);
  CHECK(s.chunks.empty());

  // A reading record whose pressure image claims 2^32 - 1 values.
  sva::io::RecordingWriter w(dir / "p.svar", false);
  const std::string settings =
      "{\"calibration\": " + sva::drivers::Calibration::uniform({2, 2, 2.0}, 1, 0).to_json() + ", \"settle\": {}}";
  w.write(sva::io::RecordType::settings, {settings.begin(), settings.end()});
  BinaryWriter r;
  r.put<double>(1.0);
  r.put<std::uint16_t>(0);
  for (int i = 0; i < 9; ++i) r.put<double>(0.0);
  r.put<std::uint8_t>(0);
  r.put<std::uint16_t>(0);
  r.put<std::uint32_t>(0xffffffffu);
  w.write(sva::io::RecordType::reading, r.bytes());
  CHECK_THROWS_WITH(sva::drivers::load_session(dir / "p.svar"),
                    Catch::Contains("p.svar") && Catch::Contains("4294967295 values exceeds its record"));
}

TEST_CASE("absurd calibration and frame sizes") {
  CHECK_THROWS_WITH(sva::drivers::Calibration::from_json("{\"rows\": 65536, \"cols\": 65536, \"pitch_mm\": 1, "
                                                         "\"gain_kpa_per_count\": [], \"zero_counts\": []}",
                                                         "big.json"),
                    Catch::Contains("big.json") && Catch::Contains("rows/cols must be in [1, 255]"));
  // A 255 x 255 header on 8 bytes: refused from the header, before the counts are read.
  const std::vector<std::uint8_t> frame{'S', 'T', 255, 255, 0, 0, 0, 0};
  CHECK_THROWS_WITH(sva::drivers::parse_frame(frame), Catch::Contains("expected 130058"));
}
#endif

#ifdef SVA_TEST_HAVE_SIM
TEST_CASE("absurd glTF: an accessor of trillions of elements on a 36-byte buffer") {
  const auto dir = sva::test::temp_dir("absurd-gltf");
  for (const char* count : {"4000000000000", "18446744073709551615", "3"}) {
    const std::string stride = std::string(count) == "3" ? ", \"byteStride\": 252" : "";
    std::ofstream(dir / "a.gltf")
        << R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": )"
        << R"("data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],)"
        << R"("bufferViews": [{"buffer": 0, "byteLength": 36)" << stride << R"(}], "accessors": [{"bufferView": 0, )"
        << R"("count": )" << count << R"(, "componentType": 5126, "type": "VEC3"}],)"
        << R"("meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}]})";
    INFO(count);
    CHECK_THROWS_WITH(sva::sim::load_mesh(dir / "a.gltf"), Catch::Contains("a.gltf"));
  }
  // An external buffer naming a device or a directory is not read.
  std::ofstream(dir / "dev.gltf")
      << R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": "/dev/zero"}]})";
  CHECK_THROWS_WITH(sva::sim::load_mesh(dir / "dev.gltf"), Catch::Contains("dev.gltf"));
}
#endif
