#include "map/map_file.hpp"

#include <sva/base/finite.hpp>
#include <sva/base/parallel.hpp>
#include <sva/error.hpp>
#include <sva/io/binary_file.hpp>

#include <cmath>
#include <limits>
#include <string_view>

#include "appearance/descriptor.hpp"

namespace sva {

namespace {

constexpr std::size_t kMaxObjects = 1 << 16;
constexpr std::uint32_t kMaxClasses = 4096;
constexpr std::uint32_t kMaxBins = 100000;

void put_symmetry(io::BinaryWriter& w, const Symmetry& s, std::uint32_t version) {
  w.put<std::uint8_t>(static_cast<std::uint8_t>(s.kind));
  w.put_array(&s.axis.x, 3);
  if (version >= 3) w.put_array(&s.point.x, 3);
  w.put<std::uint64_t>(s.rotations.size());
  for (const auto& m : s.rotations) w.put_array(&m[0][0], 9);
}

Symmetry get_symmetry(io::BinaryReader& r) {
  Symmetry s;
  const auto kind = r.get<std::uint8_t>();
  if (kind > 2) r.fail("invalid symmetry kind " + std::to_string(kind));
  s.kind = static_cast<Symmetry::Kind>(kind);
  r.get_array(&s.axis.x, 3);
  if (r.version() >= 3) r.get_array(&s.point.x, 3);  // older maps: axes through the origin
  const auto n = r.get<std::uint64_t>();
  if (n > 4096 || n > r.remaining() / (9 * sizeof(double)))
    r.fail("symmetry group size " + std::to_string(n) + " is invalid");
  s.rotations.resize(n);
  for (auto& m : s.rotations) r.get_array(&m[0][0], 9);
  return s;
}

// The "none of these" model's feature count in the file: 3 for the features of map versions 4 and 5, 4 for this
// build's (version 6 on).
std::uint32_t unknown_feature_count(UnknownFeatureSet set) {
  return set == UnknownFeatureSet::evidence_gap_share ? 3 : static_cast<std::uint32_t>(kUnknownFeatures);
}

// The unknown model after the session counts: its feature count, then its rows.
void put_unknown_model(io::BinaryWriter& w, const UnknownModel& model, std::uint32_t version) {
  const std::uint32_t features = unknown_feature_count(model.features);
  w.put<std::uint32_t>(version < 6 ? 3 : features);
  w.put<std::uint64_t>(model.per_readings.size());
  for (const UnknownCoefficients& k : model.per_readings) w.put_array(k.data(), features + 1);
}

// Version 10: the light estimates' calibration after the unknown model: its first reading count (0: none, and
// nothing follows), then its temperature, top label and unknown model.
void put_light_calibration(io::BinaryWriter& w, const LightCalibration& light) {
  w.put<std::uint32_t>(light.from);
  if (light.empty()) return;
  w.put<double>(light.temperature_scale);
  w.put<double>(light.temperature_power);
  w.put_array(light.top_label.data(), light.top_label.size());
  put_unknown_model(w, light.unknown, 10);
}

// Version 4: the calibration (calibration/calibration.hpp), after the entries.
// Version 5: the surface check's weight after the temperature.
// Version 6: the unknown model may read this build's features (evidence, then the fit).
// Version 7: the top label (before the fine pose, from it on) after the surface weight.
// Version 8: the fine pose's first reading count after the top label (PairMap::fine_pose_from: the pose space's
// default when the calibration says 0); older versions mean that default and hold no other.
void put_calibration(io::BinaryWriter& w, const PairMap& m, std::uint32_t version) {
  const Calibration& c = m.calibration;
  if (version < 6 && unknown_feature_count(c.unknown.features) != 3 && !c.unknown.empty())
    throw Error("map version " + std::to_string(version) +
                " cannot hold this build's \"none of these\" model (its features need version 6)");
  if (version < 7 && c.top_label != Calibration{}.top_label)
    throw Error("map version " + std::to_string(version) +
                " cannot hold the top label's recalibration (it needs version 7)");
  const std::uint32_t fine_pose_from = m.fine_pose_from();
  if (version < 8 &&
      fine_pose_from != Calibration::fine_pose_start(0, m.pose_space.kind == PoseSpaceSpec::Kind::planar))
    throw Error("map version " + std::to_string(version) + " cannot hold a fine pose from " +
                std::to_string(fine_pose_from) + " readings (it needs version 8)");
  w.put<std::uint8_t>(c.learned ? 1 : 0);
  w.put<double>(c.temperature_scale);
  w.put<double>(c.temperature_power);
  if (version >= 5) w.put<double>(c.surface_weight);
  if (version >= 7)
    for (const Calibration::TopLabel& t : c.top_label) w.put_array(t.data(), t.size());
  if (version >= 8) w.put<std::uint32_t>(fine_pose_from);
  w.put<std::uint32_t>(c.known_sessions);
  w.put<std::uint32_t>(c.unknown_sessions);
  w.put<std::uint32_t>(c.session_readings);
  put_unknown_model(w, c.unknown, version);
  if (version < 10 && !c.light.empty())
    throw Error("map version " + std::to_string(version) +
                " cannot hold the light estimates' calibration (it needs version 10)");
  if (version >= 10) put_light_calibration(w, c.light);
}

// The unknown model after the session counts: its feature count, then its rows.
void get_unknown_model(io::BinaryReader& r, UnknownModel* model) {
  const auto features = r.get<std::uint32_t>();
  if (features == 3) {
    model->features = UnknownFeatureSet::evidence_gap_share;
  } else if (features != kUnknownFeatures || r.version() < 6) {
    r.fail("calibration: the unknown model reads " + std::to_string(features) + " features; a version " +
           std::to_string(r.version()) + " map holds 3" + (r.version() < 6 ? "" : " or 4"));
  }
  const auto n = r.get<std::uint64_t>();
  if (n > 1000) r.fail("calibration: " + std::to_string(n) + " unknown models (at most 1000)");
  model->per_readings.assign(n, UnknownCoefficients{});  // a 3-feature row leaves the fourth weight 0
  for (UnknownCoefficients& k : model->per_readings) {
    r.get_array(k.data(), features + 1);
    for (double v : k)
      if (!std::isfinite(v)) r.fail("calibration: an unknown-model coefficient is not finite");
  }
}

// A top label's {a, b}, within Calibration's bounds; `what` names the section.
void get_top_label(io::BinaryReader& r, const char* what, Calibration::TopLabel* t) {
  r.get_array(t->data(), t->size());
  if (!Calibration::valid_bias((*t)[0]))
    r.fail(std::string(what) + ": top-label bias " + std::to_string((*t)[0]) + " is not in [-1000, 1000]");
  if (!Calibration::valid_slope((*t)[1]))
    r.fail(std::string(what) + ": top-label slope " + std::to_string((*t)[1]) + " is not in [0, 100]");
}

// A temperature's scale and power, within the bounds every map has held.
void get_temperature(io::BinaryReader& r, const char* what, double* scale, double* power) {
  *scale = r.get<double>();
  *power = r.get<double>();
  if (!(std::isfinite(*scale) && *scale > 0.0 && *scale <= 1e6))
    r.fail(std::string(what) + ": temperature scale " + std::to_string(*scale) + " is not in (0, 1e6]");
  if (!(std::isfinite(*power) && *power >= 0.0 && *power <= 10.0))
    r.fail(std::string(what) + ": temperature power " + std::to_string(*power) + " is not in [0, 10]");
}

// A reading count from which the fine pose (or the light calibration) applies, read as `from`.
std::uint32_t check_fine_pose_from(const io::BinaryReader& r, std::uint32_t from, const char* what) {
  if (from < Calibration::kMinFinePoseFrom || from > Calibration::kMaxFinePoseFrom)
    r.fail(std::string(what) + " " + std::to_string(from) + " readings is not in [" +
           std::to_string(Calibration::kMinFinePoseFrom) + ", " + std::to_string(Calibration::kMaxFinePoseFrom) + "]");
  return from;
}

// Version 10: the light estimates' calibration (put_light_calibration).
LightCalibration get_light_calibration(io::BinaryReader& r) {
  LightCalibration light;
  const auto from = r.get<std::uint32_t>();
  if (from == 0) return light;  // none
  light.from = check_fine_pose_from(r, from, "light calibration: from");
  get_temperature(r, "light calibration", &light.temperature_scale, &light.temperature_power);
  get_top_label(r, "light calibration", &light.top_label);
  get_unknown_model(r, &light.unknown);
  return light;
}

Calibration get_calibration(io::BinaryReader& r) {
  Calibration c;
  const auto learned = r.get<std::uint8_t>();
  if (learned > 1) r.fail("calibration: invalid learned flag " + std::to_string(learned));
  c.learned = learned == 1;
  get_temperature(r, "calibration", &c.temperature_scale, &c.temperature_power);
  if (r.version() >= 5) {  // older maps: the documented default
    c.surface_weight = r.get<double>();
    if (!(std::isfinite(c.surface_weight) && c.surface_weight >= 0.0 && c.surface_weight <= 16.0))
      r.fail("calibration: surface weight " + std::to_string(c.surface_weight) + " is not in [0, 16]");
  }
  if (r.version() >= 7)  // older maps: the identity
    for (Calibration::TopLabel& t : c.top_label) get_top_label(r, "calibration", &t);
  // Older maps: 0, the pose space's default.
  if (r.version() >= 8)
    c.fine_pose_from = check_fine_pose_from(r, r.get<std::uint32_t>(), "calibration: fine pose from");
  c.known_sessions = r.get<std::uint32_t>();
  c.unknown_sessions = r.get<std::uint32_t>();
  c.session_readings = r.get<std::uint32_t>();
  get_unknown_model(r, &c.unknown);
  if (r.version() >= 10) c.light = get_light_calibration(r);  // older maps: none
  return c;
}

template <class T>
bool all_finite(const std::vector<T>& v) {
  for (const auto& x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// The surfaces' section (version 9): a flag, then per object its vertices (x, y, z) and triangles (3 indices each).
void put_surfaces(io::BinaryWriter& w, const PairMap& m, std::uint32_t version) {
  if (version < 9) {
    if (!m.surfaces.empty())
      throw Error("map version " + std::to_string(version) +
                  " cannot hold the objects' surfaces (they need version 9)");
    return;
  }
  w.put<std::uint8_t>(m.surfaces.empty() ? 0 : 1);
  for (const ObjectSurface& s : m.surfaces) {
    std::vector<float> xyz;
    xyz.reserve(3 * s.positions.size());
    for (const glm::vec3& v : s.positions) xyz.insert(xyz.end(), {v.x, v.y, v.z});
    std::vector<std::uint32_t> idx;
    idx.reserve(3 * s.triangles.size());
    for (const glm::uvec3& t : s.triangles) idx.insert(idx.end(), {t.x, t.y, t.z});
    w.put_vector(xyz);
    w.put_vector(idx);
  }
}

std::vector<ObjectSurface> get_surfaces(io::BinaryReader& r, std::size_t objects) {
  const auto flag = r.get<std::uint8_t>();
  if (flag > 1) r.fail("surfaces: invalid flag " + std::to_string(flag));
  std::vector<ObjectSurface> out;
  if (flag == 0) return out;
  out.resize(objects);
  for (std::size_t o = 0; o < objects; ++o) {
    const std::vector<float> xyz = r.get_vector<float>();
    const std::vector<std::uint32_t> idx = r.get_vector<std::uint32_t>();
    if (xyz.size() % 3 != 0 || idx.size() % 3 != 0)
      r.fail("surface of object " + std::to_string(o) + ": its arrays are not in threes");
    for (std::size_t i = 0; i < xyz.size(); i += 3) out[o].positions.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
    for (std::size_t i = 0; i < idx.size(); i += 3) out[o].triangles.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
  }
  return out;
}

}  // namespace

void save_pair_map(const PairMap& m, const std::filesystem::path& file) {
  validate_pair_map(m, "map to save");
  write_pair_map(m, file, kMapVersion);
}

void write_pair_map(const PairMap& m, const std::filesystem::path& file, std::uint32_t version) {
  io::BinaryWriter w;
  w.put_string(m.scene_name);
  w.put<std::uint64_t>(m.scene_hash);
  w.put<std::uint64_t>(m.train_seed);
  w.put<double>(m.ambiguity);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(m.pose_space.kind));
  w.put<std::int32_t>(m.pose_space.translation_bins);
  w.put<double>(m.pose_space.translation_min_mm);
  w.put<double>(m.pose_space.translation_max_mm);
  w.put<std::int32_t>(m.pose_space.rotation_bins);

  const AppearanceModel& a = m.appearance;
  w.put<std::uint8_t>(static_cast<std::uint8_t>(a.descriptor));
  w.put<std::int32_t>(a.calibration.sensor.rows);
  w.put<std::int32_t>(a.calibration.sensor.cols);
  w.put<double>(a.calibration.sensor.pitch_mm);
  w.put<double>(a.calibration.stiffness_kpa_per_mm);
  w.put<double>(a.calibration.contact_threshold_kpa);
  w.put<std::uint32_t>(a.mn_size);
  w.put<std::uint32_t>(a.mnti_pad);
  w.put<std::uint32_t>(a.mnti_freqs);
  w.put<std::uint32_t>(a.descriptor_size);
  w.put<float>(a.prune_ratio);
  w.put_vector(a.medoids);
  w.put_vector(a.psi);

  w.put<std::uint32_t>(m.distance.count);
  w.put<double>(m.distance.min_mm);
  w.put<double>(m.distance.max_mm);
  w.put<std::uint32_t>(m.key_space.n_classes);
  w.put<std::uint32_t>(m.key_space.n_dist_bins);

  w.put<std::uint64_t>(m.objects.size());
  for (const auto& o : m.objects) {
    w.put_string(o.name);
    put_symmetry(w, o.symmetry, version);
    w.put<double>(o.inertial_radius_mm);
  }

  const MapReadings& rd = m.readings;
  w.put_vector(rd.object);
  for (const auto* v : {&rd.px, &rd.py, &rd.pz, &rd.nx, &rd.ny, &rd.nz, &rd.norm_conf}) w.put_vector(*v);

  w.put<double>(m.baseline.smoothing);
  w.put_vector(m.baseline.class_given_object);

  w.put_vector(m.keys);
  w.put_vector(m.offsets);
  w.put_vector(m.entry_a);
  w.put_vector(m.entry_b);
  w.put_vector(m.entry_weight);
  if (version >= 4) put_calibration(w, m, version);
  put_surfaces(w, m, version);
  w.write_file(file, std::string_view(kMapMagic, 8), version);
}

namespace {

// The payload's fields in the order write_pair_map wrote them, each checked as it is read; the entries as a whole
// afterwards (validate_pair_map, in load_pair_map).
void read_pair_map(io::BinaryReader& r, PairMap& m) {
  m.scene_name = r.get_string(4096);
  m.scene_hash = r.get<std::uint64_t>();
  m.train_seed = r.get<std::uint64_t>();
  m.ambiguity = r.get<double>();
  const auto kind = r.get<std::uint8_t>();
  if (kind > 1) r.fail("invalid pose space kind " + std::to_string(kind));
  m.pose_space.kind = static_cast<PoseSpaceSpec::Kind>(kind);
  m.pose_space.translation_bins = r.get<std::int32_t>();
  m.pose_space.translation_min_mm = r.get<double>();
  m.pose_space.translation_max_mm = r.get<double>();
  m.pose_space.rotation_bins = r.get<std::int32_t>();

  AppearanceModel& a = m.appearance;
  const auto desc = r.get<std::uint8_t>();
  if (desc > 1) r.fail("invalid descriptor kind " + std::to_string(desc));
  a.descriptor = static_cast<DescriptorKind>(desc);
  a.calibration.sensor.rows = r.get<std::int32_t>();
  a.calibration.sensor.cols = r.get<std::int32_t>();
  a.calibration.sensor.pitch_mm = r.get<double>();
  a.calibration.stiffness_kpa_per_mm = r.get<double>();
  a.calibration.contact_threshold_kpa = r.get<double>();
  a.mn_size = r.get<std::uint32_t>();
  a.mnti_pad = r.get<std::uint32_t>();
  a.mnti_freqs = r.get<std::uint32_t>();
  a.descriptor_size = r.get<std::uint32_t>();
  a.prune_ratio = r.get<float>();
  a.medoids = r.get_vector<float>();
  a.psi = r.get_vector<float>();

  m.distance.count = r.get<std::uint32_t>();
  m.distance.min_mm = r.get<double>();
  m.distance.max_mm = r.get<double>();
  m.key_space.n_classes = r.get<std::uint32_t>();
  m.key_space.n_dist_bins = r.get<std::uint32_t>();

  const auto n_objects = r.get<std::uint64_t>();
  if (n_objects == 0 || n_objects > kMaxObjects) r.fail("object count " + std::to_string(n_objects) + " is invalid");
  m.objects.resize(n_objects);
  for (auto& o : m.objects) {
    o.name = r.get_string(4096);
    o.symmetry = get_symmetry(r);
    o.inertial_radius_mm = r.get<double>();
  }

  MapReadings& rd = m.readings;
  rd.object = r.get_vector<std::uint32_t>();
  for (auto* v : {&rd.px, &rd.py, &rd.pz, &rd.nx, &rd.ny, &rd.nz, &rd.norm_conf}) *v = r.get_vector<float>();

  m.baseline.smoothing = r.get<double>();
  m.baseline.class_given_object = r.get_vector<double>();
  m.baseline.n_objects = static_cast<std::uint32_t>(m.objects.size());
  m.baseline.n_classes = m.key_space.n_classes;

  m.keys = r.get_vector<std::uint32_t>();
  m.offsets = r.get_vector<std::uint32_t>();
  m.entry_a = r.get_vector<std::uint32_t>();
  m.entry_b = r.get_vector<std::uint32_t>();
  m.entry_weight = r.get_vector<float>();
  if (r.version() >= 4) m.calibration = get_calibration(r);              // older maps: the documented default
  if (r.version() >= 9) m.surfaces = get_surfaces(r, m.objects.size());  // older maps: none
  r.expect_end();
  if (r.version() == 1) {
    if (m.entry_b.size() != m.entry_a.size() || m.entry_weight.size() != m.entry_a.size() ||
        m.offsets.size() != m.keys.size() + 1 || m.offsets.front() != 0 || m.offsets.back() != m.entry_a.size())
      r.fail("invalid map: entry columns and offsets do not match");
    // keep_one_order walks every key's range before validate_pair_map runs: each must lie inside the entries.
    for (std::size_t k = 0; k + 1 < m.offsets.size(); ++k)
      if (m.offsets[k + 1] < m.offsets[k]) r.fail("invalid map: offsets decrease at key " + std::to_string(k));
    keep_one_order(m);
  }
}

}  // namespace

// The checksum runs beside the parse where a second thread may (a 112 MB map: 0.42 -> 0.29 s on 2 cores); a corrupt
// file is still named corrupt, before anything its parse or its validation found.
std::shared_ptr<PairMap> load_pair_map(const std::filesystem::path& file) {
  const io::Checksum when = util::default_threads() > 1 ? io::Checksum::alongside : io::Checksum::first;
  io::BinaryReader r(file, std::string_view(kMapMagic, 8), kMapOldestVersion, kMapVersion, "map", when);
  auto mp = std::make_shared<PairMap>();
  r.parse_verified([&] {
    read_pair_map(r, *mp);
    validate_pair_map(*mp, file.string());
  });
  return mp;
}

void keep_one_order(PairMap& m) {
  std::vector<std::uint32_t> keys, offsets{0};
  std::size_t out = 0;
  for (std::size_t k = 0; k < m.keys.size(); ++k) {
    for (std::uint32_t e = m.offsets[k]; e < m.offsets[k + 1]; ++e) {
      if (!(m.entry_a[e] < m.entry_b[e])) continue;
      m.entry_a[out] = m.entry_a[e];
      m.entry_b[out] = m.entry_b[e];
      m.entry_weight[out] = m.entry_weight[e];
      ++out;
    }
    if (out != offsets.back()) {
      keys.push_back(m.keys[k]);
      offsets.push_back(static_cast<std::uint32_t>(out));
    }
  }
  m.entry_a.resize(out);
  m.entry_b.resize(out);
  m.entry_weight.resize(out);
  m.keys = std::move(keys);
  m.offsets = std::move(offsets);
}

namespace {

// Each part of validate_pair_map: throws sva::Error naming the map's origin and the fault.
[[noreturn]] void invalid_map(const std::string& origin, const std::string& what) {
  throw Error(origin + ": invalid map: " + what);
}

// The appearance model: sensor calibration, descriptor, classes, their psi and unit-length medoids.
void validate_appearance(const PairMap& m, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  const AppearanceModel& a = m.appearance;
  const auto& cal = a.calibration;
  if (cal.sensor.rows < 1 || cal.sensor.cols < 1 || cal.sensor.rows > 1024 || cal.sensor.cols > 1024 ||
      !(cal.sensor.pitch_mm > 0) || !std::isfinite(cal.sensor.pitch_mm))
    fail("sensor geometry is invalid");
  if (!(cal.stiffness_kpa_per_mm > 0) || !std::isfinite(cal.stiffness_kpa_per_mm) ||
      !std::isfinite(cal.contact_threshold_kpa))
    fail("sensor calibration is invalid");
  if (a.mn_size < 1 || a.mn_size > 4096) fail("MN size " + std::to_string(a.mn_size) + " is invalid");
  const std::uint32_t expect_size =
      a.descriptor == DescriptorKind::mn ? a.mn_size * a.mn_size : appearance::fourier_magnitude_count(a.mnti_freqs);
  if (a.descriptor == DescriptorKind::mnti &&
      (a.mnti_pad < a.mn_size || a.mnti_pad > 8192 || a.mnti_freqs < 1 || a.mnti_freqs > a.mnti_pad / 2 + 1))
    fail("MNTI parameters are invalid");
  if (a.descriptor_size != expect_size)
    fail("descriptor size " + std::to_string(a.descriptor_size) + " does not match its parameters");
  if (!(a.prune_ratio > 0.0f && a.prune_ratio <= 1.0f)) fail("pruning ratio T_a must lie in (0, 1]");
  const std::uint32_t k = m.key_space.n_classes;
  if (k < 1 || k > kMaxClasses) fail("class count " + std::to_string(k) + " is invalid");
  if (a.psi.size() != k)
    fail("psi has " + std::to_string(a.psi.size()) + " values for " + std::to_string(k) + " classes");
  for (float v : a.psi)
    if (!(v > 0) || !std::isfinite(v)) fail("psi values must be positive and finite");
  if (a.medoids.size() != static_cast<std::size_t>(k) * a.descriptor_size) fail("medoid table has the wrong size");
  if (!all_finite(a.medoids)) fail("medoid table has a non-finite value");
  for (std::uint32_t i = 0; i < k; ++i) {
    const float* row = &a.medoids[static_cast<std::size_t>(i) * a.descriptor_size];
    const double len2 = appearance::affinity(row, row, a.descriptor_size);
    if (std::fabs(len2 - 1.0) > 1e-3) fail("medoid " + std::to_string(i) + " is not unit length");
  }
}

// The distance bins; returns the size of the pair key space they span with the classes.
std::uint64_t validate_key_space(const PairMap& m, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  const std::uint32_t k = m.key_space.n_classes;
  const DistanceBins& d = m.distance;
  if (d.count < 1 || d.count > kMaxBins || d.count != m.key_space.n_dist_bins) fail("distance bin count is invalid");
  if (!std::isfinite(d.min_mm) || !std::isfinite(d.max_mm) || d.min_mm < 0 || d.min_mm >= d.max_mm)
    fail("distance range is invalid");
  const std::uint64_t space = static_cast<std::uint64_t>(k) * k * d.count;
  if (space > kMaxPairKeySpace) fail("key space is too large");
  return space;
}

// The objects' radii and symmetries, and the training readings (grouped by object, finite, unit normals).
void validate_objects_and_readings(const PairMap& m, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  if (m.objects.empty()) fail("no objects");
  for (const auto& o : m.objects) {
    if (!std::isfinite(o.inertial_radius_mm) || o.inertial_radius_mm < 0)
      fail("object \"" + o.name + "\": invalid inertial radius");
    if (!finite(o.symmetry.axis)) fail("object \"" + o.name + "\": invalid symmetry axis");
    if (!finite(o.symmetry.point)) fail("object \"" + o.name + "\": invalid symmetry point");
    for (const auto& R : o.symmetry.rotations)
      for (int c = 0; c < 3; ++c)
        for (int rr = 0; rr < 3; ++rr)
          if (!std::isfinite(R[c][rr])) fail("object \"" + o.name + "\": invalid symmetry rotation");
  }

  const MapReadings& rd = m.readings;
  const std::size_t n = rd.size();
  if (n == 0) fail("no readings");
  if (n > std::numeric_limits<std::uint32_t>::max()) fail("too many readings");
  for (const auto* v : {&rd.px, &rd.py, &rd.pz, &rd.nx, &rd.ny, &rd.nz, &rd.norm_conf})
    if (v->size() != n) fail("reading table columns have different lengths");
  for (std::size_t i = 0; i < n; ++i) {
    if (rd.object[i] >= m.objects.size())
      fail("reading " + std::to_string(i) + " names object " + std::to_string(rd.object[i]) + ", out of range");
    if (i && rd.object[i] < rd.object[i - 1]) fail("reading table is not grouped by object");
    if (!std::isfinite(rd.px[i]) || !std::isfinite(rd.py[i]) || !std::isfinite(rd.pz[i]))
      fail("reading " + std::to_string(i) + ": non-finite position");
    const double len =
        std::sqrt(double(rd.nx[i]) * rd.nx[i] + double(rd.ny[i]) * rd.ny[i] + double(rd.nz[i]) * rd.nz[i]);
    if (!(std::fabs(len - 1.0) <= 1e-3)) fail("reading " + std::to_string(i) + ": normal is not unit length");
    if (!(rd.norm_conf[i] >= 0.0f && rd.norm_conf[i] <= 1.0f))
      fail("reading " + std::to_string(i) + ": normConf outside [0, 1]");
  }
}

constexpr float kMaxSurfaceMm = 1e6f;

// The objects' surfaces: none, or one per object with finite vertices and triangles that index them.
void validate_surfaces(const PairMap& m, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  if (m.surfaces.empty()) return;
  if (m.surfaces.size() != m.objects.size())
    fail(std::to_string(m.surfaces.size()) + " surfaces for " + std::to_string(m.objects.size()) + " objects");
  for (std::size_t o = 0; o < m.surfaces.size(); ++o) {
    const ObjectSurface& s = m.surfaces[o];
    const std::string who = "surface of object \"" + m.objects[o].name + "\": ";
    if (s.triangles.empty()) fail(who + "no triangles");
    if (s.positions.size() > std::numeric_limits<std::uint32_t>::max()) fail(who + "too many vertices");
    for (const glm::vec3& v : s.positions) {
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) fail(who + "a vertex is not finite");
      // An object's frame is centred on it (the scene's size is its largest extent): a vertex a kilometre out is
      // a damaged file, and would make the measurement model's grid absurd.
      if (std::fabs(v.x) > kMaxSurfaceMm || std::fabs(v.y) > kMaxSurfaceMm || std::fabs(v.z) > kMaxSurfaceMm)
        fail(who + "a vertex lies more than 1 km from the object's origin");
    }
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        if (s.triangles[t][k] >= s.positions.size())
          fail(who + "triangle " + std::to_string(t) + " names vertex " + std::to_string(s.triangles[t][k]) + " of " +
               std::to_string(s.positions.size()));
  }
}

// The baseline's class-given-object table.
void validate_baseline(const PairMap& m, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  const std::uint32_t k = m.key_space.n_classes;
  const AppearanceBaseline& b = m.baseline;
  if (!(b.smoothing > 0) || !std::isfinite(b.smoothing)) fail("baseline smoothing must be positive");
  if (b.n_objects != m.objects.size() || b.n_classes != k || b.class_given_object.size() != m.objects.size() * k)
    fail("baseline table has the wrong size");
  for (double v : b.class_given_object)
    if (!(v > 0 && v <= 1)) fail("baseline probabilities must lie in (0, 1]");
}

// The keys, their offsets and the entries under them, as the recognizer's binary search needs them.
void validate_entries(const PairMap& m, std::uint64_t space, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  const MapReadings& rd = m.readings;
  const std::size_t n = rd.size();
  if (m.offsets.size() != m.keys.size() + 1) fail("offsets must have one more element than keys");
  if (m.offsets.front() != 0) fail("offsets must start at 0");
  const std::size_t entries = m.entry_a.size();
  if (m.entry_b.size() != entries || m.entry_weight.size() != entries) fail("entry columns have different lengths");
  if (m.offsets.back() != entries)
    fail("last offset " + std::to_string(m.offsets.back()) + " does not match the " + std::to_string(entries) +
         " entries");
  for (std::size_t i = 0; i < m.keys.size(); ++i) {
    if (m.keys[i] >= space) fail("key " + std::to_string(m.keys[i]) + " is outside the key space");
    if (i && m.keys[i] <= m.keys[i - 1]) fail("keys are not strictly increasing");
    if (m.offsets[i + 1] <= m.offsets[i]) fail("offsets are not strictly increasing (empty or negative key range)");
  }
  for (std::size_t e = 0; e < entries; ++e) {
    if (m.entry_a[e] >= n || m.entry_b[e] >= n)
      fail("entry " + std::to_string(e) + " references a reading out of range");
    if (m.entry_a[e] == m.entry_b[e]) fail("entry " + std::to_string(e) + " pairs a reading with itself");
    if (m.entry_a[e] > m.entry_b[e])
      fail("entry " + std::to_string(e) + " stores its pair in the second order (version 2 keeps entry_a < entry_b)");
    if (rd.object[m.entry_a[e]] != rd.object[m.entry_b[e]])
      fail("entry " + std::to_string(e) + " pairs readings of different objects");
    const float w = m.entry_weight[e];
    if (!(w > 0.0f && w <= 1.0f)) fail("entry " + std::to_string(e) + " has weight outside (0, 1]");
  }
  // The recognizer finds a training pair under a key by binary search.
  for (std::size_t key = 0; key < m.keys.size(); ++key)
    for (std::uint32_t e = m.offsets[key] + 1; e < m.offsets[key + 1]; ++e)
      if (m.entry_a[e] < m.entry_a[e - 1] || (m.entry_a[e] == m.entry_a[e - 1] && m.entry_b[e] <= m.entry_b[e - 1]))
        fail("entries of key " + std::to_string(m.keys[key]) +
             " are not strictly increasing by (reading a, reading b)");
}

}  // namespace

void validate_pair_map(const PairMap& m, const std::string& origin) {
  auto fail = [&](const std::string& what) { invalid_map(origin, what); };
  const auto& ps = m.pose_space;
  if (ps.translation_bins < 1 || ps.rotation_bins < 1 || !std::isfinite(ps.translation_min_mm) ||
      !std::isfinite(ps.translation_max_mm) || ps.translation_min_mm >= ps.translation_max_mm)
    fail("pose space is invalid");
  if (!std::isfinite(m.ambiguity) || m.ambiguity < 0) fail("appearance ambiguity is not a finite non-negative number");

  validate_appearance(m, origin);
  const std::uint64_t space = validate_key_space(m, origin);
  validate_objects_and_readings(m, origin);
  validate_baseline(m, origin);
  validate_entries(m, space, origin);
  validate_surfaces(m, origin);
}

}  // namespace sva
