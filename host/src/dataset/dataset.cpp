// Dataset files (docs/file-formats.md): the producing scene as JSON, then one
// fixed-size record per sample. The loader validates every value so that
// later stages can trust finite numbers and in-range ids.
#include <sva/dataset.hpp>

#include <cmath>
#include <string>

#include <sva/io/binary_file.hpp>

#include <sva/base/finite.hpp>
#include <sva/base/parallel.hpp>

namespace sva {

namespace {
constexpr char kMagic[] = "SVADATA1";
// Version 2 added the sensor truth to every record; version 1 files still load
// (their truth is the reported pose).
constexpr std::uint32_t kVersion = 2;
constexpr std::uint32_t kOldestVersion = 1;

void put3(io::BinaryWriter& w, const glm::dvec3& v) { w.put_array(&v.x, 3); }
glm::dvec3 get3(io::BinaryReader& r) {
  glm::dvec3 v;
  r.get_array(&v.x, 3);
  return v;
}
template <class Bad>
void read_truth(io::BinaryReader& r, SensorTruth& t, const Bad& bad) {
  t.position = get3(r);
  t.normal = get3(r);
  t.x_axis = get3(r);
  t.surface_normal = get3(r);
  if (!finite(t.position) || !finite(t.normal) || !finite(t.x_axis) || !finite(t.surface_normal))
    bad("non-finite true sensor pose or surface normal");
  if (std::abs(glm::length(t.normal) - 1.0) > 1e-6 || std::abs(glm::length(t.x_axis) - 1.0) > 1e-6)
    bad("true sensor normal and x axis must be unit vectors");
  const double sn = glm::length(t.surface_normal);
  if (sn != 0.0 && std::abs(sn - 1.0) > 1e-6) bad("true surface normal must be a unit vector or zero (unknown)");
}

}  // namespace

Dataset without_objects(const Dataset& data, const std::vector<std::string>& names) {
  std::vector<bool> drop(data.scene.objects.size(), false);
  for (const std::string& n : names) {
    std::size_t o = 0;
    while (o < data.scene.objects.size() && data.scene.objects[o].name != n) ++o;
    if (o == data.scene.objects.size())
      throw Error("exclude objects: scene \"" + data.scene.name + "\" has no object \"" + n + "\"");
    drop[o] = true;
  }
  Dataset out = data;
  out.scene.objects.clear();
  out.samples.clear();
  std::vector<std::uint32_t> id(drop.size(), 0);
  for (std::size_t o = 0; o < drop.size(); ++o) {
    id[o] = static_cast<std::uint32_t>(out.scene.objects.size());
    if (!drop[o]) out.scene.objects.push_back(data.scene.objects[o]);
  }
  if (out.scene.objects.empty()) throw Error("exclude objects: no object of scene \"" + data.scene.name + "\" is left");
  for (const Sample& s : data.samples) {
    if (s.object >= drop.size() || drop[s.object]) continue;
    Sample kept = s;
    kept.object = id[s.object];
    out.samples.push_back(std::move(kept));
  }
  return out;
}

std::size_t Dataset::count_converged() const {
  std::size_t n = 0;
  for (const auto& s : samples) n += s.reading.status == ControllerStatus::converged;
  return n;
}

void save_dataset(const Dataset& d, const std::filesystem::path& file) {
  io::BinaryWriter w;
  w.put_string(scene_to_json(d.scene));
  w.put_string(d.split);
  w.put<std::uint64_t>(d.seed);
  w.put<std::uint64_t>(d.samples.size());
  const auto elements = static_cast<std::size_t>(d.scene.sensor.elements());
  for (const auto& s : d.samples) {
    const Reading& r = s.reading;
    if (r.pressure.size() != elements) throw std::logic_error("save_dataset: pressure image has the wrong size");
    w.put<std::uint32_t>(s.object);
    w.put<std::uint8_t>(static_cast<std::uint8_t>(r.status));
    w.put<std::uint16_t>(r.iterations);
    put3(w, r.position);
    put3(w, r.normal);
    put3(w, r.x_axis);
    w.put_array(&s.object_pose.R[0][0], 9);
    put3(w, s.object_pose.T);
    w.put_array(r.pressure.data(), elements);
    put3(w, s.truth.position);
    put3(w, s.truth.normal);
    put3(w, s.truth.x_axis);
    put3(w, s.truth.surface_normal);
  }
  w.write_file(file, std::string_view(kMagic, 8), kVersion);
}

namespace {

// The payload's fields in the order save_dataset wrote them, each checked as it is read.
Dataset read_dataset(io::BinaryReader& r, const std::filesystem::path& file) {
  const bool has_truth = r.version() >= 2;
  Dataset d;
  std::string scene_json = r.get_string(64 << 20);
  try {
    d.scene = parse_scene(scene_json, file);
  } catch (const Error& e) {
    r.fail(std::string("embedded scene is invalid: ") + e.what());
  }
  d.split = r.get_string();
  d.seed = r.get<std::uint64_t>();
  auto n = r.get<std::uint64_t>();
  const auto elements = static_cast<std::size_t>(d.scene.sensor.elements());
  const std::size_t record = 4 + 1 + 2 + 8 * (3 * 3 + 9 + 3) + 4 * elements + (has_truth ? 8 * 12 : 0);
  if (n > r.remaining() / record) r.fail("sample count " + std::to_string(n) + " exceeds the file size");
  d.samples.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto bad = [&](const std::string& what) { r.fail("sample " + std::to_string(i) + ": " + what); };
    Sample& s = d.samples[i];
    Reading& rd = s.reading;
    s.object = r.get<std::uint32_t>();
    if (s.object >= d.scene.objects.size()) bad("object id " + std::to_string(s.object) + " out of range");
    auto status = r.get<std::uint8_t>();
    if (status > 2) bad("invalid controller status " + std::to_string(status));
    rd.status = static_cast<ControllerStatus>(status);
    rd.iterations = r.get<std::uint16_t>();
    rd.position = get3(r);
    rd.normal = get3(r);
    rd.x_axis = get3(r);
    r.get_array(&s.object_pose.R[0][0], 9);
    s.object_pose.T = get3(r);
    if (!finite(rd.position) || !finite(rd.normal) || !finite(rd.x_axis) || !finite(s.object_pose.T))
      bad("non-finite sensor or object pose");
    if (std::abs(glm::length(rd.normal) - 1.0) > 1e-6 || std::abs(glm::length(rd.x_axis) - 1.0) > 1e-6)
      bad("sensor normal and x axis must be unit vectors");
    if (!finite(s.object_pose.R)) bad("non-finite object rotation");
    rd.pressure.resize(elements);
    r.get_array(rd.pressure.data(), elements);
    rd.rows = d.scene.sensor.rows;
    rd.cols = d.scene.sensor.cols;
    for (float p : rd.pressure)
      if (!std::isfinite(p) || p < 0.0f) bad("pressure image holds a NaN, infinite or negative value");
    if (has_truth)
      read_truth(r, s.truth, bad);
    else
      s.truth = {rd.position, rd.normal, rd.x_axis, glm::dvec3(0.0)};
  }
  r.expect_end();
  return d;
}

}  // namespace

// The checksum runs beside the parse where a second thread may, as a map's does (map/map_file.cpp).
Dataset load_dataset(const std::filesystem::path& file) {
  const io::Checksum when = util::default_threads() > 1 ? io::Checksum::alongside : io::Checksum::first;
  io::BinaryReader r(file, std::string_view(kMagic, 8), kOldestVersion, kVersion, "dataset", when);
  Dataset d;
  r.parse_verified([&] { d = read_dataset(r, file); });
  return d;
}

}  // namespace sva
