// sva recognize: batch recognition of many independent sessions (docs/batch-format.md).
// Sessions are stepped together, so each update of the backend (one GPU
// submission with --backend vulkan) carries one reading of every session.
#include <sva/batch_recognizer.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "args.hpp"
#include "eval/evaluation.hpp"
#include "eval/trials.hpp"
#include "io/text_file.hpp"
#include "map/pair_map.hpp"
#include "recognition/rotation.hpp"
#include "util/interrupt.hpp"
#include "util/progress.hpp"

namespace sva::cli {

namespace {

using nlohmann::json;

struct SessionIn {
  std::string id;
  std::vector<Reading> readings;
  json truth;  // echoed to the output when present
};

glm::dvec3 vec3_of(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw Error(where + ": expected an array of 3 numbers");
  glm::dvec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!j[static_cast<std::size_t>(i)].is_number()) throw Error(where + ": expected an array of 3 numbers");
    v[i] = j[static_cast<std::size_t>(i)].get<double>();
    if (!std::isfinite(v[i])) throw Error(where + ": non-finite value");
  }
  return v;
}

json vec3_json(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

json pose_json(const RigidPose& p) {
  json R = json::array();
  for (int r = 0; r < 3; ++r) R.push_back(json::array({p.R[0][r], p.R[1][r], p.R[2][r]}));  // row-major rows
  return {{"R", R}, {"T", vec3_json(p.T)}, {"rodrigues", vec3_json(rotation::log(p.R))}};
}

std::vector<SessionIn> read_sessions(const std::string& file, int elements) {
  std::ifstream in(file);
  if (!in) throw Error(file + ": cannot read the sessions file");
  std::vector<SessionIn> out;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = file + ":" + std::to_string(line_no);
    json j;
    try {
      j = json::parse(line);
    } catch (const json::exception& e) {
      throw Error(where + ": invalid JSON: " + e.what());
    }
    if (!j.is_object()) throw Error(where + ": expected one JSON object per line");
    SessionIn s;
    s.id = j.contains("id") ? (j["id"].is_string() ? j["id"].get<std::string>() : j["id"].dump()) : std::to_string(out.size());
    if (j.contains("truth")) s.truth = j["truth"];
    if (!j.contains("readings") || !j["readings"].is_array() || j["readings"].empty())
      throw Error(where + ": \"readings\" must be a non-empty array");
    for (std::size_t r = 0; r < j["readings"].size(); ++r) {
      const json& jr = j["readings"][r];
      const std::string w = where + ": readings[" + std::to_string(r) + "]";
      if (!jr.is_object()) throw Error(w + ": expected an object");
      Reading rd;
      for (const char* k : {"position", "normal", "pressure"})
        if (!jr.contains(k)) throw Error(w + ": missing \"" + k + "\"");
      rd.position = vec3_of(jr["position"], w + ".position");
      rd.normal = vec3_of(jr["normal"], w + ".normal");
      if (glm::length(rd.normal) < 1e-9) throw Error(w + ".normal: zero vector");
      rd.normal = glm::normalize(rd.normal);
      if (jr.contains("x_axis")) rd.x_axis = vec3_of(jr["x_axis"], w + ".x_axis");
      const json& p = jr["pressure"];
      if (!p.is_array() || p.size() != static_cast<std::size_t>(elements))
        throw Error(w + ".pressure: expected " + std::to_string(elements) + " numbers (the map's sensor)");
      for (const auto& v : p) {
        if (!v.is_number() || !std::isfinite(v.get<double>())) throw Error(w + ".pressure: non-numeric or non-finite value");
        rd.pressure.push_back(v.get<float>());
      }
      if (jr.contains("status")) {
        if (!jr["status"].is_string()) throw Error(w + ".status: expected a string");
        const std::string st = jr["status"];
        bool known = false;
        for (auto c : {ControllerStatus::converged, ControllerStatus::not_converged, ControllerStatus::no_contact})
          if (st == to_string(c)) {
            rd.status = c;
            known = true;
          }
        if (!known) throw Error(w + ".status: expected converged, not_converged or no_contact");
      }
      s.readings.push_back(std::move(rd));
    }
    out.push_back(std::move(s));
  }
  if (out.empty()) throw Error(file + ": no sessions (empty file)");
  return out;
}

int write_sessions(const Args& a, const std::string& out_file) {
  const std::string data_file = a.required("--data"), map_file = a.required("--map");
  const Map map = Map::load(map_file);
  const Dataset test = load_dataset(data_file);
  eval::check_compatible(map, test, map_file, data_file);
  const auto n = static_cast<std::size_t>(a.integer("--trials", static_cast<long long>(map.objects()), 1, 10000000));
  const auto m = static_cast<std::size_t>(a.integer("--max-readings", 30, 1, 100000));
  eval::TrialGenerator gen(test, map.pose_space(), static_cast<std::uint64_t>(a.integer("--seed", 1, 0, INT64_MAX)), m, data_file);
  std::string text;
  for (std::size_t t = 0; t < n; ++t) {
    util::throw_if_interrupted();
    const eval::Trial tr = gen.make(t);
    json readings = json::array();
    for (const Reading& r : tr.readings)
      readings.push_back({{"position", vec3_json(r.position)}, {"normal", vec3_json(r.normal)},
                          {"x_axis", vec3_json(r.x_axis)}, {"pressure", r.pressure}});
    json truth = pose_json(tr.pose);
    truth["object"] = test.scene.objects[tr.object].name;
    text += json{{"id", "trial-" + std::to_string(t)}, {"truth", truth}, {"readings", readings}}.dump() + "\n";
  }
  io::write_text_file(out_file, text);
  std::printf("wrote %zu sessions of %zu readings to %s\n", n, m, out_file.c_str());
  return 0;
}

}  // namespace

int cmd_recognize(const std::vector<std::string>& argv) {
  Args a("sva recognize",
         "Recognise a batch of independent sessions of readings (JSON Lines, docs/batch-format.md) and write one\n"
         "estimate per session (JSON Lines). All sessions step together: one backend update carries the next\n"
         "reading of every session, which keeps a GPU busy. With --write-sessions it instead writes a sessions file\n"
         "of evaluation trials (random poses of a test set's objects, ground truth included).",
         argv);
  a.option("--map", "MAP", "map file (sva train)")
      .option("--batch", "SESSIONS.jsonl", "the sessions to recognise")
      .option("--out", "RESULTS.jsonl", "where the estimates go")
      .option("--backend", "auto|cpu|vulkan", "vote backend (default auto: Vulkan when a device exists, else CPU)")
      .option("--sessions-per-submission", "N", "sessions stepped together (default 64)")
      .option("--device", "NAME|INDEX", "Vulkan device (default: prefer a discrete GPU; env SVA_VK_DEVICE)")
      .option("--top", "K", "hypotheses reported per session (default 3)")
      .option("--write-sessions", "FILE.jsonl", "write trials as a sessions file instead (needs --map, --data)")
      .option("--data", "TEST", "test dataset for --write-sessions")
      .option("--trials", "N", "sessions to write (default: one per object)")
      .option("--max-readings", "M", "readings per written session (default 30)")
      .option("--seed", "S", "seed of the written trials (default 1)");
  if (!a.parse()) return 0;
  if (auto ws = a.get("--write-sessions")) return write_sessions(a, *ws);
  const std::string map_file = a.required("--map"), batch_file = a.required("--batch"), out_file = a.required("--out");
  const Map map = Map::load(map_file);
  const PairMap& pm = map.internal();
  const auto sessions = read_sessions(batch_file, pm.appearance.calibration.sensor.elements());
  const auto per = static_cast<std::size_t>(a.integer("--sessions-per-submission", 64, 1, 1 << 20));
  const auto top_k = static_cast<std::size_t>(a.integer("--top", 3, 0, 1000));
  RecognizerOptions ro;
  const std::string backend = a.get_or("--backend", "auto");
  if (backend == "cpu") ro.backend = BackendKind::cpu;
  else if (backend == "vulkan" || backend == "auto") ro.backend = BackendKind::vulkan;
  else throw Error("sva recognize: --backend expects auto, cpu or vulkan, got \"" + backend + "\"");
  ro.vulkan_device = a.get_or("--device", "");

  std::size_t total_readings = 0;
  for (const auto& s : sessions) total_readings += s.readings.size();
  util::Progress progress("recognize", total_readings);
  std::vector<std::string> lines(sessions.size());
  std::string device;
  for (std::size_t first = 0; first < sessions.size(); first += per) {
    const std::size_t n = std::min(per, sessions.size() - first);
    std::unique_ptr<BatchRecognizer> rec;
    try {
      rec = std::make_unique<BatchRecognizer>(map, map.pose_space(), n, ro);
    } catch (const Error& e) {
      if (backend != "auto") throw;
      std::fprintf(stderr, "sva recognize: no usable Vulkan device (%s); using the CPU backend\n", e.what());
      ro.backend = BackendKind::cpu;
      rec = std::make_unique<BatchRecognizer>(map, map.pose_space(), n, ro);
    }
    device = rec->backend_description();
    std::size_t longest = 0;
    for (std::size_t i = 0; i < n; ++i) longest = std::max(longest, sessions[first + i].readings.size());
    for (std::size_t step = 0; step < longest; ++step) {
      util::throw_if_interrupted();
      std::vector<std::size_t> ids;
      std::vector<Reading> rd;
      for (std::size_t i = 0; i < n; ++i) {
        const auto& s = sessions[first + i];
        if (step >= s.readings.size()) continue;
        ids.push_back(i);
        rd.push_back(s.readings[step]);
      }
      try {
        rec->add_readings(ids, rd);
      } catch (const Error& e) {
        throw Error(batch_file + ": " + e.what() + " (session numbers count from " + std::to_string(first) + ")");
      }
      progress.advance(ids.size());
    }
    for (std::size_t i = 0; i < n; ++i) {
      const auto& s = sessions[first + i];
      const Estimate e = rec->estimate(i, top_k);
      json probs = json::object();
      for (std::size_t o = 0; o < e.object_probability.size(); ++o) probs[pm.objects[o].name] = e.object_probability[o];
      json top = json::array();
      for (const auto& h : e.top) {
        json t = pose_json(h.pose);
        t["object"] = h.object_name;
        t["probability"] = h.probability;
        top.push_back(t);
      }
      json line = {{"id", s.id}, {"readings", e.readings}, {"object", e.object_name}, {"object_probability", probs},
                   {"pose_valid", e.pose_valid}};
      if (e.pose_valid) line["pose"] = pose_json(e.pose);
      line["top"] = top;
      if (!s.truth.is_null()) line["truth"] = s.truth;
      lines[first + i] = line.dump();
    }
  }
  progress.finish();
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  io::write_text_file(out_file, text);
  std::fprintf(stderr, "recognised %zu sessions (%zu readings) with %s; wrote %s\n", sessions.size(), total_readings,
               device.c_str(), out_file.c_str());
  return 0;
}

}  // namespace sva::cli
