// Writes the seed corpora of tests/fuzz/corpus/<harness>/ with the project's own writers (run once, outputs
// committed; scripts/fuzz.sh --make-corpus reruns it). Hand-made broken cases and the assimp test models sit
// beside these files and are not touched.
//   build-fuzz/tests/fuzz/sva_fuzz_make_corpus tests/fuzz/corpus assets/scenes/tiny.json
#include <sva/dataset.hpp>
#include <sva/drivers/calibration.hpp>
#include <sva/drivers/frame.hpp>
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>
#include <sva/scene.hpp>
#include <sva/sim/mesh.hpp>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "map/map_file.hpp"
#include "recognition/batch_sessions.hpp"
#include "recognition/session_file.hpp"

namespace {

using namespace sva;
namespace fs = std::filesystem;

void write_bytes(const fs::path& file, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}
void write_text(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

Reading reading(int i, int elements) {
  Reading r;
  r.position = {10.0 * i, -5.0, 20.0 + i};
  r.normal = glm::normalize(glm::dvec3(0.1 * i, 0.2, 1.0));
  r.x_axis = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), r.normal));
  r.iterations = static_cast<std::uint16_t>(3 + i);
  for (int e = 0; e < elements; ++e) r.pressure.push_back(static_cast<float>((e * 7 + i) % 11) * 1.5f);
  return r;
}

void scenes(const fs::path& out, const std::string& tiny_text) {
  write_text(out / "tiny.json", tiny_text);
  const Scene s = parse_scene(tiny_text, "tiny.json");
  write_text(out / "tiny-written.json", scene_to_json(s));
}

void calibrations(const fs::path& out) {
  write_text(out / "uniform-6x6.json", drivers::Calibration::uniform({6, 6, 2.0}, 0.05f, 100.0f).to_json());
  auto c = drivers::Calibration::uniform({2, 3, 1.5}, 0.1f, 20.0f);
  for (std::size_t i = 0; i < c.gain.size(); ++i) c.gain[i] += 0.01f * static_cast<float>(i);
  c.saturation_counts = 4000;
  write_text(out / "varied-2x3.json", c.to_json());
}

void batch_sessions(const fs::path& out) {
  std::vector<BatchSession> sessions(2);
  sessions[0].id = "first";
  sessions[0].readings = {reading(0, 36), reading(1, 36)};
  sessions[1].id = "with-truth";
  sessions[1].readings = {reading(2, 36)};
  sessions[1].truth = R"({"object":"die"})";
  // The format alone (the fuzz build compiles the parsers, not recognition): the public writer writes these bytes.
  write_text(out / "two.jsonl", batch::format_sessions(sessions));
}

void datasets(const fs::path& out, const std::string& tiny_text) {
  Dataset d;
  d.scene = parse_scene(tiny_text, "tiny.json");
  d.split = "train";
  d.seed = 7;
  for (int i = 0; i < 3; ++i) {
    Sample s;
    s.reading = reading(i, d.scene.sensor.elements());
    s.truth = {s.reading.position, s.reading.normal, s.reading.x_axis, glm::dvec3(0, 0, 1)};
    d.samples.push_back(s);
  }
  save_dataset(d, out / "tiny-3.svad");
}

// The smallest map that validates: 2 classes of a 2 x 2 MN descriptor, 2 distance bins, one object of 3 readings.
PairMap small_map() {
  PairMap m;
  m.scene_name = "fuzz";
  m.scene_hash = 1;
  m.ambiguity = 1.5;
  AppearanceModel& a = m.appearance;
  a.descriptor = DescriptorKind::mn;
  a.mn_size = 2;
  a.descriptor_size = 4;
  a.medoids = {1, 0, 0, 0, 0, 0.6f, 0.8f, 0};
  a.psi = {0.5f, 0.25f};
  m.distance = {2, 10.0, 50.0};
  m.key_space = {2, 2};
  MapObject o;
  o.name = "brick";
  o.symmetry.kind = Symmetry::Kind::discrete;
  o.symmetry.rotations = {glm::dmat3(1.0), glm::dmat3(-1, 0, 0, 0, -1, 0, 0, 0, 1)};
  m.objects = {o};
  for (int i = 0; i < 3; ++i) m.readings.push_back(0, {5.0 * i, 0, 1}, {0, 0, 1}, 0.5f);
  m.baseline.n_objects = 1;
  m.baseline.n_classes = 2;
  m.baseline.class_given_object = {0.25, 0.75};
  m.keys = {1, 6};
  m.offsets = {0, 2, 3};
  m.entry_a = {0, 0, 1};
  m.entry_b = {1, 2, 2};
  m.entry_weight = {1.0f, 0.5f, 0.25f};
  return m;
}

void maps(const fs::path& out) {
  const PairMap m = small_map();
  validate_pair_map(m, "corpus map");
  save_pair_map(m, out / "small-v3.svam");
  write_pair_map(m, out / "small-v2.svam", 2);
  PairMap both = m;  // version 1 stored both orders of every pair
  both.offsets = {0, 4, 6};
  both.entry_a = {0, 0, 1, 2, 1, 2};
  both.entry_b = {1, 2, 0, 0, 2, 1};
  both.entry_weight = {1.0f, 0.5f, 1.0f, 0.5f, 0.25f, 0.25f};
  write_pair_map(both, out / "small-v1.svam", 1);
  PairMap calibrated = m;  // a learned calibration with this build's "none of these" model (version 6)
  calibrated.calibration.learned = true;
  calibrated.calibration.unknown.per_readings = {{-1.0, -0.5, -0.25, 2.0, 1.5}, {-0.8, -0.4, -0.3, 1.9, 1.6}};
  write_pair_map(calibrated, out / "small-v6.svam", 6);
  PairMap relabelled = calibrated;  // version 7: the top label too
  relabelled.calibration.top_label = {Calibration::TopLabel{-0.4, 0.4}, Calibration::TopLabel{-0.3, 0.85}};
  save_pair_map(relabelled, out / "small-v7.svam");
  calibrated.calibration.unknown.features = UnknownFeatureSet::evidence_gap_share;  // version 5: three features
  for (UnknownCoefficients& k : calibrated.calibration.unknown.per_readings) k[4] = 0.0;
  write_pair_map(calibrated, out / "small-v5.svam", 5);
}

void session_files(const fs::path& out) {
  io::SessionFile s;
  s.scene_hash = 42;
  s.objects = 2;
  s.scene_name = "tiny";
  s.prior.object_probability = {0.25, 0.75};
  s.prior.object_pose.resize(2);
  s.prior.object_pose[1] = PosePrior{{10.0, 20.0, 30.0}, 5.0, true, glm::dmat3(1.0), 0.2};
  s.readings = {reading(0, 36), reading(1, 36)};
  s.readings[1].time_s = 12.5;
  io::save_session_file(s, out / "two.svas");
  s.prior = {};
  s.readings.resize(1);
  io::save_session_file(s, out / "flat-prior.svas");
}

void frames(const fs::path& out) {
  drivers::TactileFrame f;
  f.rows = f.cols = 6;
  f.sequence = 513;
  for (int i = 0; i < 36; ++i) f.counts.push_back(static_cast<std::uint16_t>(100 + 37 * i));
  write_bytes(out / "6x6.bin", drivers::encode_frame(f));
  f.rows = 1;
  f.cols = 1;
  f.counts = {65535};
  write_bytes(out / "1x1.bin", drivers::encode_frame(f));
  f.rows = 2;
  f.cols = 3;
  f.counts = {0, 1, 2, 3, 4, 5};
  write_bytes(out / "2x3.bin", drivers::encode_frame(f));
}

// Control-byte framing of fuzz_sensor_stream.cpp: [dim selector] then (length byte, bytes) transfers.
void streams(const fs::path& out) {
  drivers::TactileFrame f;
  f.rows = f.cols = 6;
  f.counts.assign(36, 500);
  std::vector<std::uint8_t> s{1};  // 6 x 6
  for (std::uint16_t seq = 0; seq < 4; ++seq) {
    f.sequence = static_cast<std::uint16_t>(seq == 3 ? 9 : seq);  // a gap before the last
    auto bytes = drivers::encode_frame(f);
    if (seq == 1) bytes.insert(bytes.begin(), {0x53, 0x00, 0x7f});  // noise before a frame
    const std::size_t half = bytes.size() / 2;                      // each frame split over two transfers
    s.push_back(static_cast<std::uint8_t>(half));
    s.insert(s.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(half));
    s.push_back(static_cast<std::uint8_t>(bytes.size() - half));
    s.insert(s.end(), bytes.begin() + static_cast<std::ptrdiff_t>(half), bytes.end());
    if (seq == 2) s.insert(s.end(), {0x80, 1, 0x80, 2});  // link lost, back
  }
  write_bytes(out / "6x6-split.bin", s);
}

void recordings(const fs::path& out) {
  const fs::path file = out / "short.svar";
  fs::remove(file);
  drivers::SessionSettings settings;
  settings.calibration = drivers::Calibration::uniform({2, 2, 2.0}, 0.05f, 100.0f);
  settings.device = "fuzz corpus";
  drivers::SessionWriter w(file, settings, false);
  drivers::TactileFrame f;
  f.rows = f.cols = 2;
  f.counts = {100, 200, 300, 400};
  w.chunk({drivers::LinkStatus::data, 1000, drivers::encode_frame(f), {}});
  w.chunk({drivers::LinkStatus::disconnected, 2000, {}, "cable pulled"});
  drivers::RecordedPose p;
  p.arrival_ns = 1500;
  p.pose.time = 1.5e-6;
  p.pose.status = ControllerStatus::converged;
  w.pose(p);
  drivers::FormedReading r;
  r.time = 2.0;
  r.sequence = 3;
  r.reading = reading(1, 4);
  w.reading(r);
  w.note({2.5, "contact dropped"});
}

void meshes(const fs::path& out) {
  sim::Mesh m;
  m.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  sim::save_glb(m, out / "tetrahedron.glb");
  sim::save_glb(m, out / "tetrahedron-normals.glb", true);
}

// Every written seed must load: a seed the parser refuses would send the fuzzer off at the first check.
void verify(const fs::path& root) {
  (void)load_dataset(root / "dataset/tiny-3.svad");
  for (const char* v : {"v1", "v2", "v3"}) (void)load_pair_map(root / "map" / (std::string("small-") + v + ".svam"));
  (void)io::load_session_file(root / "session_file/two.svas");
  if (drivers::load_session(root / "recording/short.svar").readings.size() != 1) throw Error("recording lost a record");
  (void)sim::load_mesh(root / "mesh/tetrahedron.glb");
  (void)sim::load_mesh(root / "mesh/tetrahedron-normals.glb");
  (void)batch::parse_sessions(io::read_text_file(root / "batch_sessions/two.jsonl", "cannot read"), "two.jsonl", 1, 0,
                              36);
  (void)drivers::Calibration::load(root / "calibration/varied-2x3.json");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: sva_fuzz_make_corpus CORPUS_DIR TINY_SCENE_JSON\n";
    return 2;
  }
  try {
    const fs::path root = argv[1];
    std::ifstream in(argv[2]);
    std::stringstream tiny;
    tiny << in.rdbuf();
    auto dir = [&](const char* name) {
      fs::create_directories(root / name);
      return root / name;
    };
    scenes(dir("scene"), tiny.str());
    calibrations(dir("calibration"));
    batch_sessions(dir("batch_sessions"));
    datasets(dir("dataset"), tiny.str());
    maps(dir("map"));
    session_files(dir("session_file"));
    frames(dir("frame"));
    streams(dir("sensor_stream"));
    recordings(dir("recording"));
    meshes(dir("mesh"));
    verify(root);
  } catch (const std::exception& e) {
    std::cerr << "sva_fuzz_make_corpus: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
