// Scene JSON: strict parsing. Every field is optional except the objects, but a
// field that is present must have the right type and a sensible value; unknown
// keys are refused so that typos do not silently fall back to defaults.
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>
#include <sva/scene.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include <sva/base/so3.hpp>
#include <sva/io/json.hpp>

#ifndef SVA_SOURCE_ASSETS_DIR
#define SVA_SOURCE_ASSETS_DIR ""
#endif
#ifndef SVA_INSTALL_ASSETS_DIR
#define SVA_INSTALL_ASSETS_DIR ""
#endif

namespace sva {

using nlohmann::json;

namespace {

// A map holds at most 65,536 objects (map/map_file.cpp); a scene of more could never be trained.
constexpr std::size_t kMaxSceneObjects = 1 << 16;

class Ctx {
 public:
  explicit Ctx(std::string origin) : origin_(std::move(origin)) {}
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw Error(origin_ + ": " + (path.empty() ? "" : path + ": ") + what);
  }
  void known_keys(const json& j, const std::string& path, std::initializer_list<const char*> keys) const {
    std::set<std::string> ok(keys.begin(), keys.end());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!ok.count(it.key())) fail(path, "unknown key \"" + it.key() + "\"");
  }
  const json& object(const json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, "expected a JSON object, got " + std::string(j.type_name()));
    return j;
  }
  double number(const json& j, const std::string& path, double lo, double hi) const {
    if (!j.is_number()) fail(path, "expected a number, got " + std::string(j.type_name()));
    double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(path, "value " + io::dump_json(j) + " is out of range [" + fmt(lo) + ", " + fmt(hi) + "]");
    return v;
  }
  int integer(const json& j, const std::string& path, int lo, int hi) const {
    if (!j.is_number_integer()) fail(path, "expected an integer, got " + io::dump_json(j));
    auto v = j.get<long long>();
    if (v < lo || v > hi)
      fail(path,
           "value " + io::dump_json(j) + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string, got " + std::string(j.type_name()));
    return j.get<std::string>();
  }
  // A name (the scene's, an object's, a family's) is shown in terminals, file names, CSV and pages (sva view): any
  // Unicode but the C0 controls and DEL, which a terminal acts on and a page hides. Refused where the scene is read
  // (sva simulate, and sva train through the dataset's copy), so no map or dataset carries one on.
  void check_name(const std::string& name, const std::string& path) const {
    std::size_t character = 0;
    for (const unsigned char b : name) {
      if ((b & 0xC0) != 0x80) ++character;  // each character's first byte (UTF-8's continuation bytes are 10xxxxxx)
      if (b < 0x20 || b == 0x7F) {          // never part of a multi-byte character
        char code[8];
        std::snprintf(code, sizeof code, "U+%04X", b);
        fail(path, "control character " + std::string(code) + " at character " + std::to_string(character) +
                       " of the name (names may hold any other Unicode)");
      }
    }
  }
  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, "expected true or false, got " + io::dump_json(j));
    return j.get<bool>();
  }
  glm::dvec3 unit_vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, "expected an array of 3 numbers");
    glm::dvec3 v(number(j[0], path + "[0]", -1e6, 1e6), number(j[1], path + "[1]", -1e6, 1e6),
                 number(j[2], path + "[2]", -1e6, 1e6));
    if (glm::length(v) < 1e-9) fail(path, "axis has zero length");
    return glm::normalize(v);
  }
  static std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

 private:
  std::string origin_;
};

template <class F>
void opt(const json& j, const char* key, F&& f) {
  if (j.contains(key)) f(j.at(key));
}

Symmetry parse_symmetry(const Ctx& c, const json& j, const std::string& path) {
  Symmetry s;
  if (j.is_string()) {
    if (j.get<std::string>() != "none")
      c.fail(path, "expected \"none\" or an object {\"type\": \"axis\"|\"cyclic\", ...}");
    return s;
  }
  c.object(j, path);
  c.known_keys(j, path, {"type", "axis", "order", "point"});
  if (!j.contains("type")) c.fail(path, "missing \"type\"");
  std::string type = c.string(j["type"], path + ".type");
  if (type == "none") return s;
  glm::dvec3 axis{0, 0, 1};
  opt(j, "axis", [&](const json& a) { axis = c.unit_vec3(a, path + ".axis"); });
  opt(j, "point", [&](const json& a) {  // a point of the axis (object frame, mm); default the origin
    if (!a.is_array() || a.size() != 3) c.fail(path + ".point", "expected an array of 3 numbers");
    for (int k = 0; k < 3; ++k) s.point[k] = c.number(a[k], path + ".point[" + std::to_string(k) + "]", -1e6, 1e6);
  });
  if (type == "axis") {
    s.kind = Symmetry::Kind::axis;
    s.axis = axis;
  } else if (type == "cyclic") {
    if (!j.contains("order")) c.fail(path, "cyclic symmetry needs \"order\"");
    int order = c.integer(j["order"], path + ".order", 1, 360);
    s.kind = Symmetry::Kind::discrete;
    s.axis = axis;
    for (int k = 0; k < order; ++k) s.rotations.push_back(so3::exp(glm::normalize(axis) * (2.0 * M_PI * k / order)));
  } else {
    c.fail(path + ".type", "unknown symmetry type \"" + type + "\" (none, axis, cyclic)");
  }
  return s;
}

json symmetry_to_json(const Symmetry& s) {
  json j;
  switch (s.kind) {
    case Symmetry::Kind::none:
      return "none";
    case Symmetry::Kind::axis:
      j = {{"type", "axis"}, {"axis", {s.axis.x, s.axis.y, s.axis.z}}};
      break;
    case Symmetry::Kind::discrete:
      j = {{"type", "cyclic"}, {"axis", {s.axis.x, s.axis.y, s.axis.z}}, {"order", s.rotations.size()}};
      break;
  }
  // Only when set, so that the scenes (and scene hashes) of axes through the origin stay as they were.
  if (s.point != glm::dvec3(0.0)) j["point"] = {s.point.x, s.point.y, s.point.z};
  return j;
}

// The "errors" block (docs/scene-format.md). Cross-checks against the skin run
// after the whole scene is read, so the order of the blocks does not matter.
ErrorModel parse_errors(const Ctx& c, const json& v) {
  c.object(v, "errors");
  c.known_keys(v, "errors",
               {"comment", "position_sigma_mm", "normal_sigma_deg", "gain_spread", "offset_kpa", "noise_kpa",
                "full_scale_kpa", "crosstalk", "crosstalk_diagonal", "train_sensor", "test_sensor"});
  ErrorModel e;
  auto num = [&](const char* key, double& out, double hi) {
    opt(v, key, [&](const json& x) { out = c.number(x, std::string("errors.") + key, 0.0, hi); });
  };
  num("position_sigma_mm", e.position_sigma_mm, 100.0);
  num("normal_sigma_deg", e.normal_sigma_deg, 45.0);
  num("gain_spread", e.gain_spread, 0.3);  // gains stay positive: they are clipped at 3 sigma
  num("offset_kpa", e.offset_kpa, 1e6);
  num("noise_kpa", e.noise_kpa, 1e6);
  num("full_scale_kpa", e.full_scale_kpa, 1e9);
  num("crosstalk", e.crosstalk, 0.2);
  num("crosstalk_diagonal", e.crosstalk_diagonal, 0.2);
  if (4.0 * (e.crosstalk + e.crosstalk_diagonal) >= 1.0)
    c.fail("errors.crosstalk", "the 8 neighbours together would read at least the element's own pressure (4 * (" +
                                   Ctx::fmt(e.crosstalk) + " + " + Ctx::fmt(e.crosstalk_diagonal) + ") >= 1)");
  opt(v, "comment", [&](const json& x) { c.string(x, "errors.comment"); });
  opt(v, "train_sensor", [&](const json& x) {
    e.train_sensor = static_cast<std::uint32_t>(c.integer(x, "errors.train_sensor", 0, 2147483647));
  });
  opt(v, "test_sensor", [&](const json& x) {
    e.test_sensor = static_cast<std::uint32_t>(c.integer(x, "errors.test_sensor", 0, 2147483647));
  });
  return e;
}

void check_errors_against_skin(const Ctx& c, const ErrorModel& e, const SkinModel& skin) {
  if (e.full_scale_kpa > 0 && e.full_scale_kpa <= skin.target_pressure_kpa)
    c.fail("errors.full_scale_kpa", "value " + Ctx::fmt(e.full_scale_kpa) +
                                        " must be above skin.target_pressure_kpa (" +
                                        Ctx::fmt(skin.target_pressure_kpa) + "), or 0 for no saturation");
}

json errors_to_json(const ErrorModel& e) {
  return {{"position_sigma_mm", e.position_sigma_mm},
          {"normal_sigma_deg", e.normal_sigma_deg},
          {"gain_spread", e.gain_spread},
          {"offset_kpa", e.offset_kpa},
          {"noise_kpa", e.noise_kpa},
          {"full_scale_kpa", e.full_scale_kpa},
          {"crosstalk", e.crosstalk},
          {"crosstalk_diagonal", e.crosstalk_diagonal},
          {"train_sensor", e.train_sensor},
          {"test_sensor", e.test_sensor}};
}

}  // namespace

const std::vector<std::string>& builtin_scene_names() {
  static const std::vector<std::string> names = {"paper3d",         "letters2d",   "tiny",        "paper3d-ideal",
                                                 "letters2d-ideal", "household10", "household25", "household50",
                                                 "household100",    "lookalikes"};
  return names;
}

namespace {
std::mutex g_assets_mutex;
std::filesystem::path g_registered_assets;  // set_assets_dir
}  // namespace

void set_assets_dir(const std::filesystem::path& dir) {
  std::lock_guard lock(g_assets_mutex);
  g_registered_assets = dir;
}

std::filesystem::path assets_dir() {
  if (const char* env = std::getenv("SVA_ASSETS"); env && *env) return env;
  {
    std::lock_guard lock(g_assets_mutex);
    if (!g_registered_assets.empty()) return g_registered_assets;
  }
  std::error_code ec;
  std::filesystem::path src = SVA_SOURCE_ASSETS_DIR;
  if (!src.empty() && std::filesystem::exists(src / "scenes", ec)) return src;
  return SVA_INSTALL_ASSETS_DIR;
}

namespace {

// "objects": each object's mesh (relative to the scene file's folder), name, size and the rest.
std::vector<SceneObject> parse_objects(const Ctx& c, const json& objs, const std::filesystem::path& origin) {
  std::vector<SceneObject> out;
  auto base = origin.has_parent_path() ? origin.parent_path() : std::filesystem::path(".");
  std::set<std::string> names;
  for (std::size_t i = 0; i < objs.size(); ++i) {
    std::string p = "objects[" + std::to_string(i) + "]";
    const json& o = c.object(objs[i], p);
    c.known_keys(o, p, {"name", "mesh", "size_mm", "center", "symmetry", "family", "inertial_radius_mm"});
    SceneObject so;
    if (!o.contains("mesh")) c.fail(p, "missing \"mesh\"");
    std::filesystem::path mesh = c.string(o["mesh"], p + ".mesh");
    if (mesh.empty()) c.fail(p + ".mesh", "empty path");
    so.mesh = mesh.is_absolute() ? mesh : std::filesystem::absolute(base / mesh).lexically_normal();
    so.name = mesh.stem().string();
    opt(o, "name", [&](const json& v) { so.name = c.string(v, p + ".name"); });
    if (so.name.empty()) c.fail(p + ".name", "empty name");
    c.check_name(so.name, p + ".name");  // the mesh file's stem too, when the key is left out
    if (!names.insert(so.name).second) c.fail(p + ".name", "duplicate object name \"" + so.name + "\"");
    opt(o, "size_mm", [&](const json& v) { so.size_mm = c.number(v, p + ".size_mm", 0.0, 1e5); });
    opt(o, "center", [&](const json& v) { so.center = c.boolean(v, p + ".center"); });
    opt(o, "symmetry", [&](const json& v) { so.symmetry = parse_symmetry(c, v, p + ".symmetry"); });
    opt(o, "family", [&](const json& v) {
      so.family = c.string(v, p + ".family");
      if (so.family.empty()) c.fail(p + ".family", "empty family name (leave the key out for none)");
      c.check_name(so.family, p + ".family");
    });
    so.inertial_radius_mm = so.size_mm > 0 ? so.size_mm / 2 : 40.0;
    opt(o, "inertial_radius_mm",
        [&](const json& v) { so.inertial_radius_mm = c.number(v, p + ".inertial_radius_mm", 1e-3, 1e5); });
    out.push_back(std::move(so));
  }
  return out;
}

SensorSpec parse_sensor(const Ctx& c, const json& v) {
  SensorSpec sensor;
  c.object(v, "sensor");
  c.known_keys(v, "sensor", {"rows", "cols", "pitch_mm"});
  opt(v, "rows", [&](const json& x) { sensor.rows = c.integer(x, "sensor.rows", 1, 64); });
  opt(v, "cols", [&](const json& x) { sensor.cols = c.integer(x, "sensor.cols", 1, 64); });
  opt(v, "pitch_mm", [&](const json& x) { sensor.pitch_mm = c.number(x, "sensor.pitch_mm", 0.01, 100.0); });
  return sensor;
}

SkinModel parse_skin(const Ctx& c, const json& v) {
  SkinModel k;
  c.object(v, "skin");
  c.known_keys(v, "skin",
               {"stiffness_kpa_per_mm", "spread_mm", "rays_per_axis", "noise_kpa", "contact_threshold_kpa",
                "target_pressure_kpa"});
  opt(v, "stiffness_kpa_per_mm",
      [&](const json& x) { k.stiffness_kpa_per_mm = c.number(x, "skin.stiffness_kpa_per_mm", 1e-3, 1e6); });
  opt(v, "spread_mm", [&](const json& x) { k.spread_mm = c.number(x, "skin.spread_mm", 0.0, 100.0); });
  opt(v, "rays_per_axis", [&](const json& x) { k.rays_per_axis = c.integer(x, "skin.rays_per_axis", 1, 16); });
  opt(v, "noise_kpa", [&](const json& x) { k.noise_kpa = c.number(x, "skin.noise_kpa", 0.0, 1e6); });
  opt(v, "contact_threshold_kpa",
      [&](const json& x) { k.contact_threshold_kpa = c.number(x, "skin.contact_threshold_kpa", 0.0, 1e6); });
  opt(v, "target_pressure_kpa",
      [&](const json& x) { k.target_pressure_kpa = c.number(x, "skin.target_pressure_kpa", 1e-3, 1e6); });
  if (k.contact_threshold_kpa >= k.target_pressure_kpa)
    c.fail("skin", "contact_threshold_kpa must be below target_pressure_kpa");
  return k;
}

PoseSpaceSpec parse_pose_space(const Ctx& c, const json& v) {
  PoseSpaceSpec ps;
  c.object(v, "pose_space");
  c.known_keys(v, "pose_space", {"kind", "translation_bins", "translation_range_mm", "rotation_bins"});
  opt(v, "kind", [&](const json& x) {
    std::string k = c.string(x, "pose_space.kind");
    if (k == "spatial")
      ps.kind = PoseSpaceSpec::Kind::spatial;
    else if (k == "planar")
      ps.kind = PoseSpaceSpec::Kind::planar;
    else
      c.fail("pose_space.kind", "expected \"spatial\" (6-DOF) or \"planar\" (x, y, angle), got \"" + k + "\"");
  });
  opt(v, "translation_bins",
      [&](const json& x) { ps.translation_bins = c.integer(x, "pose_space.translation_bins", 1, 4096); });
  opt(v, "rotation_bins", [&](const json& x) { ps.rotation_bins = c.integer(x, "pose_space.rotation_bins", 1, 4096); });
  opt(v, "translation_range_mm", [&](const json& x) {
    if (!x.is_array() || x.size() != 2) c.fail("pose_space.translation_range_mm", "expected [min, max]");
    ps.translation_min_mm = c.number(x[0], "pose_space.translation_range_mm[0]", -1e6, 1e6);
    ps.translation_max_mm = c.number(x[1], "pose_space.translation_range_mm[1]", -1e6, 1e6);
    if (ps.translation_min_mm >= ps.translation_max_mm)
      c.fail("pose_space.translation_range_mm", "min must be below max");
  });
  return ps;
}

// Overrides the fields "appearance" names in a (the pose space's defaults).
void parse_appearance(const Ctx& c, const json& v, AppearanceSpec& a) {
  c.object(v, "appearance");
  c.known_keys(v, "appearance", {"descriptor", "clusters", "dist_bins", "dist_range_mm", "pair_readings"});
  opt(v, "descriptor", [&](const json& x) {
    a.descriptor = c.string(x, "appearance.descriptor");
    if (a.descriptor != "mn" && a.descriptor != "mnti")
      c.fail("appearance.descriptor", "expected \"mn\" or \"mnti\", got \"" + a.descriptor + "\"");
  });
  opt(v, "clusters", [&](const json& x) { a.clusters = c.integer(x, "appearance.clusters", 1, 4096); });
  opt(v, "dist_bins", [&](const json& x) { a.dist_bins = c.integer(x, "appearance.dist_bins", 1, 65535); });
  opt(v, "pair_readings", [&](const json& x) {
    a.pair_readings = c.integer(x, "appearance.pair_readings", 0, 100000000);
    if (a.pair_readings == 1) c.fail("appearance.pair_readings", "1: a pair needs two readings (0 pairs them all)");
  });
  opt(v, "dist_range_mm", [&](const json& x) {
    if (!x.is_array() || x.size() != 2) c.fail("appearance.dist_range_mm", "expected [min, max]");
    a.dist_min_mm = c.number(x[0], "appearance.dist_range_mm[0]", 0.0, 1e6);
    a.dist_max_mm = c.number(x[1], "appearance.dist_range_mm[1]", 0.0, 1e6);
    if (a.dist_min_mm >= a.dist_max_mm) c.fail("appearance.dist_range_mm", "min must be below max");
  });
}

ProtocolSpec parse_protocol(const Ctx& c, const json& v) {
  ProtocolSpec p;
  c.object(v, "protocol");
  c.known_keys(v, "protocol",
               {"kind", "train_per_object", "test_per_object", "approach_mm", "tilt_deg", "grid", "grid_spacing_mm",
                "orientations", "max_iterations"});
  opt(v, "kind", [&](const json& x) {
    p.kind = c.string(x, "protocol.kind");
    if (p.kind != "paper3d" && p.kind != "letters2d")
      c.fail("protocol.kind", "expected \"paper3d\" or \"letters2d\", got \"" + p.kind + "\"");
  });
  opt(v, "train_per_object",
      [&](const json& x) { p.train_per_object = c.integer(x, "protocol.train_per_object", 0, 1000000); });
  opt(v, "test_per_object",
      [&](const json& x) { p.test_per_object = c.integer(x, "protocol.test_per_object", 0, 1000000); });
  opt(v, "approach_mm", [&](const json& x) { p.approach_mm = c.number(x, "protocol.approach_mm", 0.0, 100.0); });
  opt(v, "tilt_deg", [&](const json& x) { p.tilt_deg = c.number(x, "protocol.tilt_deg", 0.0, 60.0); });
  opt(v, "grid", [&](const json& x) { p.grid = c.integer(x, "protocol.grid", 1, 100); });
  opt(v, "grid_spacing_mm",
      [&](const json& x) { p.grid_spacing_mm = c.number(x, "protocol.grid_spacing_mm", 0.0, 1000.0); });
  opt(v, "orientations", [&](const json& x) { p.orientations = c.integer(x, "protocol.orientations", 1, 360); });
  opt(v, "max_iterations",
      [&](const json& x) { p.max_iterations = c.integer(x, "protocol.max_iterations", 1, 10000); });
  return p;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::filesystem::path& origin) {
  Ctx c(origin.string());
  if (io::json_depth(text) > io::kMaxJsonDepth) c.fail("", io::json_too_deep_message());
  json j;
  try {
    j = io::parse_json(text);
  } catch (const json::exception& e) {  // syntax, and numbers out of a double's range
    c.fail("", std::string("invalid JSON: ") + e.what());
  }
  c.object(j, "");
  c.known_keys(j, "",
               {"name", "objects", "sensor", "skin", "errors", "pose_space", "appearance", "protocol", "comment"});
  Scene s;
  s.file = origin;
  s.name = origin.stem().string();
  opt(j, "name", [&](const json& v) { s.name = c.string(v, "name"); });
  c.check_name(s.name, "name");
  if (!j.contains("objects")) c.fail("", "missing \"objects\"");
  const json& objs = j["objects"];
  if (!objs.is_array() || objs.empty()) c.fail("objects", "expected a non-empty array of objects");
  if (objs.size() > kMaxSceneObjects)
    c.fail("objects", std::to_string(objs.size()) + " objects, more than the " + std::to_string(kMaxSceneObjects) +
                          " a map can hold");
  s.objects = parse_objects(c, objs, origin);
  opt(j, "sensor", [&](const json& v) { s.sensor = parse_sensor(c, v); });
  opt(j, "skin", [&](const json& v) { s.skin = parse_skin(c, v); });
  // No "errors" block is the ideal world, so scenes written before it keep their meaning.
  opt(j, "errors", [&](const json& v) { s.errors = parse_errors(c, v); });
  check_errors_against_skin(c, s.errors, s.skin);
  opt(j, "pose_space", [&](const json& v) { s.pose_space = parse_pose_space(c, v); });
  if (s.pose_space.kind == PoseSpaceSpec::Kind::planar) {  // the letters defaults (paper Sec 5.2); overridden below
    s.appearance = {"mn", 100, 100, 3.0, 20.0};
  }
  opt(j, "appearance", [&](const json& v) { parse_appearance(c, v, s.appearance); });
  opt(j, "protocol", [&](const json& v) { s.protocol = parse_protocol(c, v); });
  return s;
}

Scene load_scene(const std::string& name_or_file) {
  std::filesystem::path file = name_or_file;
  std::error_code ec;
  // A bare name (no directory, no .json) is a built-in scene, whatever files
  // the current directory holds.
  const bool bare = file.extension() != ".json" && !file.has_parent_path();
  if (bare) {
    const auto& names = builtin_scene_names();
    auto builtin = assets_dir() / "scenes" / (name_or_file + ".json");
    if (!std::filesystem::exists(builtin, ec)) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw Error("scene \"" + name_or_file + "\": no built-in scene of that name (built-ins: " + list +
                  "; or give a .json file)");
    }
    file = builtin;
  }
  if (std::filesystem::is_directory(file, ec)) throw Error(file.string() + ": cannot read scene file");
  const std::string text = io::read_text_file(file, "cannot read scene file");
  if (text.empty()) throw Error(file.string() + ": empty scene file");
  return parse_scene(text, std::filesystem::absolute(file));
}

std::string scene_to_json(const Scene& s) {
  json objs = json::array();
  for (const auto& o : s.objects) {
    json jo = {{"name", o.name},
               {"mesh", o.mesh.string()},
               {"size_mm", o.size_mm},
               {"center", o.center},
               {"symmetry", symmetry_to_json(o.symmetry)},
               {"inertial_radius_mm", o.inertial_radius_mm}};
    // Only when set, so that the datasets of scenes without families keep their bytes.
    if (!o.family.empty()) jo["family"] = o.family;
    objs.push_back(std::move(jo));
  }
  json j = {
      {"name", s.name},
      {"objects", objs},
      {"sensor", {{"rows", s.sensor.rows}, {"cols", s.sensor.cols}, {"pitch_mm", s.sensor.pitch_mm}}},
      {"skin",
       {{"stiffness_kpa_per_mm", s.skin.stiffness_kpa_per_mm},
        {"spread_mm", s.skin.spread_mm},
        {"rays_per_axis", s.skin.rays_per_axis},
        {"noise_kpa", s.skin.noise_kpa},
        {"contact_threshold_kpa", s.skin.contact_threshold_kpa},
        {"target_pressure_kpa", s.skin.target_pressure_kpa}}},
      {"errors", errors_to_json(s.errors)},
      {"pose_space",
       {{"kind", s.pose_space.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial"},
        {"translation_bins", s.pose_space.translation_bins},
        {"translation_range_mm", {s.pose_space.translation_min_mm, s.pose_space.translation_max_mm}},
        {"rotation_bins", s.pose_space.rotation_bins}}},
      {"appearance",
       {{"descriptor", s.appearance.descriptor},
        {"clusters", s.appearance.clusters},
        {"dist_bins", s.appearance.dist_bins},
        {"dist_range_mm", {s.appearance.dist_min_mm, s.appearance.dist_max_mm}}}},
      {"protocol",
       {{"kind", s.protocol.kind},
        {"train_per_object", s.protocol.train_per_object},
        {"test_per_object", s.protocol.test_per_object},
        {"approach_mm", s.protocol.approach_mm},
        {"tilt_deg", s.protocol.tilt_deg},
        {"grid", s.protocol.grid},
        {"grid_spacing_mm", s.protocol.grid_spacing_mm},
        {"orientations", s.protocol.orientations},
        {"max_iterations", s.protocol.max_iterations}}},
  };
  // Only when set, so that the datasets of scenes that pair every reading keep their bytes.
  if (s.appearance.pair_readings > 0) j["appearance"]["pair_readings"] = s.appearance.pair_readings;
  return io::dump_json(j, 2);
}

}  // namespace sva
