#include <sva/eval/session_view.hpp>

#include <sva/base/finite.hpp>
#include <sva/base/progress.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>
#ifdef SVA_HAVE_SIM
#include <sva/sim/mesh.hpp>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ostream>

#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>
#include "eval/metrics.hpp"
#include "recognition/batch_sessions.hpp"

namespace sva::view {

namespace {

using nlohmann::json;

// Base64 (RFC 4648) of raw bytes: the meshes' float32 and uint32 arrays, which the page decodes into typed arrays
// (smaller and faster to parse than JSON numbers for meshes of 100,000 triangles).
std::string base64(const void* data, std::size_t size) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const std::uint32_t v = (std::uint32_t{b[i]} << 16) | (i + 1 < size ? std::uint32_t{b[i + 1]} << 8 : 0u) |
                            (i + 2 < size ? std::uint32_t{b[i + 2]} : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < size ? kAlphabet[v & 63] : '=';
  }
  return out;
}

json reading_json(const Reading& r) {
  return {{"p", {r.position.x, r.position.y, r.position.z}},
          {"n", {r.normal.x, r.normal.y, r.normal.z}},
          {"rows", r.rows},
          {"cols", r.cols},
          {"pressure", r.pressure}};
}

// The scene's object of a map object's name (the map and the scene may hold other objects, or in another order).
const SceneObject* scene_object(const Scene* scene, const std::string& name) {
  if (!scene) return nullptr;
  for (const SceneObject& o : scene->objects)
    if (o.name == name) return &o;
  return nullptr;
}

// One step: the estimate after a reading, and its errors where the truth and a pose of the right object are known.
json step_json(const Estimate& est, double update_ms, const std::optional<SessionTruth>& truth,
               const SceneObject* truth_object) {
  json hypotheses = json::array();
  for (const PoseHypothesis& h : est.hypotheses) {
    json j = batch::pose_value(h.pose);
    j["object"] = h.object;
    j["probability"] = h.probability;
    hypotheses.push_back(j);
  }
  json error = nullptr;
  if (truth && truth_object && est.ready && est.pose_valid && est.object == truth->object) {
    const SceneObject& o = *truth_object;
    const eval::PoseError e = eval::pose_error(truth->pose, est.pose, o.symmetry, o.inertial_radius_mm);
    error = {{"translation_mm", e.translation_mm}, {"angle_deg", e.angular_rad * 180.0 / M_PI}};
  }
  return {{"update_ms", update_ms},
          {"object", est.ready ? json(est.object) : json(nullptr)},
          {"probabilities", est.object_probability},
          {"p_unknown", est.p_unknown},
          {"hypotheses", hypotheses},
          {"error", error}};
}

// The meshes of the objects the page shows (the truth's and every hypothesis'), each loaded once. A mesh that cannot
// be loaded (a dataset made on another machine) leaves its object out of the 3-D view, with a warning: the rest of
// the page still shows the session.
json meshes_json(const Scene& scene, const std::vector<std::string>& names, const json& steps,
                 const std::optional<SessionTruth>& truth, json& warnings) {
  std::vector<std::uint32_t> wanted;
  if (truth) wanted.push_back(truth->object);
  for (const json& s : steps)
    for (const json& h : s["hypotheses"]) wanted.push_back(h["object"].get<std::uint32_t>());
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  json out = json::object();
#ifdef SVA_HAVE_SIM
  for (std::uint32_t o : wanted) {
    const SceneObject* object = o < names.size() ? scene_object(&scene, names[o]) : nullptr;
    if (!object) {
      warnings.push_back("no mesh for " + (o < names.size() ? names[o] : std::to_string(o)) + ": not in scene " +
                         scene.name);
      continue;
    }
    sim::Mesh mesh;
    try {
      mesh = sim::load_object_mesh(*object);
    } catch (const Error& e) {
      warnings.push_back("no mesh for " + object->name + ": " + e.what());
      continue;
    }
    out[std::to_string(o)] = {{"name", object->name},
                              {"triangles", mesh.triangles.size()},
                              {"positions", base64(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3))},
                              {"indices", base64(mesh.triangles.data(), mesh.triangles.size() * sizeof(glm::uvec3))}};
  }
#else
  if (!wanted.empty()) warnings.push_back("no meshes: this build has no simulator (SVA_BUILD_SIM off)");
#endif
  return out;
}

// three.js and its orbit controls: SVA_THREE_JS (a folder laid out as Debian's), else libjs-three's.
std::filesystem::path three_dir() {
  if (const char* env = std::getenv("SVA_THREE_JS"); env && *env) return env;
  return "/usr/share/javascript/three";
}

void replace_once(std::string& page, const std::string& token, const std::string& with) {
  const auto at = page.find(token);
  if (at == std::string::npos) throw Error("assets/view/viewer.html: no " + token + " in the page template");
  page.replace(at, token.size(), with);
}

// A script's text inside <script>: "</script" would end it early.
std::string script(const std::string& text, const std::string& attributes = "") {
  std::string safe;
  safe.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') {
      safe += "<\\/";
      ++i;
    } else {
      safe += text[i];
    }
  }
  return "<script" + attributes + ">\n" + safe + "\n</script>";
}

// The data as JSON that is safe inside <script>: names come from files (a map, a dataset, a sessions file), and
// "</script>" or "<!--<script>" in one would end the element early or keep it open past its end tag. '<', '>' and
// '&' occur in JSON text only inside strings, where \u003c and the rest decode to the same characters. A name that
// is not UTF-8 (a map file's bytes are not checked) shows with U+FFFD instead of failing the page.
std::string script_json(const json& data) {
  const std::string text = io::dump_json(data, -1, /*replace_invalid_utf8=*/true);
  std::string safe;
  safe.reserve(text.size());
  for (char c : text) {
    if (c == '<')
      safe += "\\u003c";
    else if (c == '>')
      safe += "\\u003e";
    else if (c == '&')
      safe += "\\u0026";
    else
      safe += c;
  }
  return safe;
}

}  // namespace

json session_view_data(const Map& map, const Scene* scene, std::span<const Reading> readings,
                       const std::optional<SessionTruth>& truth, const SessionViewSpec& spec) {
  if (readings.empty()) throw Error("sva view: the session has no readings");
  if (truth && truth->object >= map.objects())
    throw Error("sva view: the true object " + std::to_string(truth->object) + " is not one of the map's " +
                std::to_string(map.objects()));
  // A batch of one (sva::Recognizer's estimates, and the backend's description for the page).
  BatchRecognizer rec(map, map.pose_space(), 1, spec.options);
  const std::vector<std::string> names = map.object_names();
  const SceneObject* truth_object = truth ? scene_object(scene, names[truth->object]) : nullptr;
  const std::size_t session = 0;
  json steps = json::array(), shown = json::array();
  std::vector<double> times;
  std::optional<util::Progress> progress;
  if (spec.progress) progress.emplace("view", readings.size());
  for (const Reading& r : readings) {
    const auto start = std::chrono::steady_clock::now();
    rec.add_readings(std::span<const std::size_t>(&session, 1), std::span<const Reading>(&r, 1));
    const Estimate est = rec.estimate(session, spec.top_k);
    times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    steps.push_back(step_json(est, times.back(), truth, truth_object));
    shown.push_back(reading_json(r));
    if (progress) progress->advance();
  }
  if (progress) progress->finish();
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const double median =
      sorted.size() % 2 ? sorted[sorted.size() / 2] : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
  json j = {{"title", spec.title},
            {"source", spec.source},
            {"map", spec.map_name},
            {"scene", map.scene_name()},
            {"backend", rec.backend_description()},
            {"update_ms_median", median},
            {"objects", names},
            {"readings", shown},
            {"steps", steps},
            {"truth", nullptr},
            {"meshes", json::object()},
            {"warnings", json::array()}};
  if (truth) {
    j["truth"] = batch::pose_value(truth->pose);
    j["truth"]["object"] = truth->object;
  }
  if (scene) j["meshes"] = meshes_json(*scene, names, steps, truth, j["warnings"]);
  return j;
}

void write_session_page(const std::filesystem::path& out, const json& data) {
  const std::filesystem::path assets = assets_dir() / "view";
  std::string page = io::read_text_file(assets / "viewer.html", "cannot read the viewer's page template (SVA_ASSETS)");
  const std::filesystem::path three = three_dir();
  const std::string missing = " (install Debian's libjs-three: scripts/setup.sh does; or set SVA_THREE_JS)";
  replace_once(page, "<!--SVA_THREE-->",
               script(io::read_text_file(three / "three.min.js", "cannot read three.js" + missing)) + "\n" +
                   script(io::read_text_file(three / "examples/js/controls/OrbitControls.js",
                                             "cannot read three.js' OrbitControls" + missing)));
  replace_once(page, "<!--SVA_DATA-->", script(script_json(data), " id=\"sva-data\" type=\"application/json\""));
  replace_once(page, "<!--SVA_VIEWER-->",
               script(io::read_text_file(assets / "viewer.js", "cannot read the viewer (SVA_ASSETS)")));
  io::write_text_file(out, page);
}

}  // namespace sva::view
