// The sessions file and the results file (docs/batch-format.md): each line parsed and checked field by field, the
// result lines formatted. recognition/batch_file.cpp runs them; this file knows nothing of recognition.
#include "recognition/batch_sessions.hpp"

#include <sva/error.hpp>
#include <sva/io/json.hpp>

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <sva/base/so3.hpp>

namespace sva::batch {

namespace {

using nlohmann::json;

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

ControllerStatus status_of(const json& j, const std::string& where) {
  if (!j.is_string()) throw Error(where + ": expected a string");
  const std::string st = j;
  for (auto c : {ControllerStatus::converged, ControllerStatus::not_converged, ControllerStatus::no_contact})
    if (st == to_string(c)) return c;
  throw Error(where + ": expected converged, not_converged or no_contact");
}

// One element of "readings"; `w` names the file, line and element.
Reading reading_of(const json& jr, const std::string& w, int elements) {
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
    const auto f = io::json_float(v);
    if (!f) throw Error(w + ".pressure: non-numeric, non-finite or out-of-range value");
    rd.pressure.push_back(*f);
  }
  if (jr.contains("status")) rd.status = status_of(jr["status"], w + ".status");
  return rd;
}

// One line of the sessions file; `number` is the session's place in the file.
BatchSession session_of(const std::string& line, const std::string& where, std::size_t number, int elements) {
  if (io::json_depth(line) > io::kMaxJsonDepth) throw Error(where + ": " + io::json_too_deep_message());
  json j;
  try {
    j = io::parse_json(line);
  } catch (const json::exception& e) {
    throw Error(where + ": invalid JSON: " + e.what());
  }
  if (!j.is_object()) throw Error(where + ": expected one JSON object per line");
  BatchSession s;
  s.id = std::to_string(number);
  if (j.contains("id")) s.id = j["id"].is_string() ? j["id"].get<std::string>() : io::dump_json(j["id"]);
  // Kept as text: the public type carries no JSON library. An explicit null is no truth, as an absent one.
  if (j.contains("truth") && !j["truth"].is_null()) s.truth = io::dump_json(j["truth"]);
  if (!j.contains("readings") || !j["readings"].is_array() || j["readings"].empty())
    throw Error(where + ": \"readings\" must be a non-empty array");
  for (std::size_t r = 0; r < j["readings"].size(); ++r)
    s.readings.push_back(reading_of(j["readings"][r], where + ": readings[" + std::to_string(r) + "]", elements));
  return s;
}

// A session's truth as JSON; a caller's session (not one read from a file) may hold text that is not JSON.
json truth_value(const BatchSession& s) {
  try {
    return io::parse_json(s.truth);
  } catch (const json::exception&) {
    throw Error("session \"" + s.id + "\": its truth is not JSON text: " + s.truth.substr(0, 40));
  }
}

json result_json(const BatchSession& s, const Estimate& e, std::span<const std::string> objects) {
  json probs = json::object();
  for (std::size_t o = 0; o < e.object_probability.size(); ++o) probs[objects[o]] = e.object_probability[o];
  json top = json::array();
  for (const auto& h : e.top) {
    json t = pose_value(h.pose);
    t["object"] = h.object_name;
    t["probability"] = h.probability;
    top.push_back(t);
  }
  json line = {{"id", s.id},
               {"readings", e.readings},
               {"object", e.object_name},
               {"object_probability", probs},
               {"p_unknown", e.p_unknown},
               {"pose_valid", e.pose_valid}};
  if (e.pose_valid) line["pose"] = pose_value(e.pose);
  line["top"] = top;
  if (!s.truth.empty()) line["truth"] = truth_value(s);
  return line;
}

}  // namespace

json pose_value(const RigidPose& p) {
  json R = json::array();
  for (int r = 0; r < 3; ++r) R.push_back(json::array({p.R[0][r], p.R[1][r], p.R[2][r]}));  // row-major rows
  return {{"R", R}, {"T", vec3_json(p.T)}, {"rodrigues", vec3_json(so3::log(p.R))}};
}

std::vector<BatchSession> parse_sessions(std::string_view text, const std::string& file, std::size_t first_line,
                                         std::size_t first_session, int elements) {
  std::vector<BatchSession> out;
  std::size_t line_no = first_line;
  for (std::size_t begin = 0; begin < text.size(); ++line_no) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    const std::string line(text.substr(begin, end - begin));
    begin = end + 1;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    out.push_back(session_of(line, file + ":" + std::to_string(line_no), first_session + out.size(), elements));
  }
  return out;
}

SessionReader::SessionReader(const std::string& file, int elements)
    : in_(file, std::ios::binary), file_(file), elements_(elements) {
  if (!in_) throw Error(file + ": cannot read the sessions file");
}

std::vector<BatchSession> SessionReader::next(std::size_t count) {
  std::vector<BatchSession> out;
  std::string line;
  while (out.size() < count && std::getline(in_, line)) {
    ++line_;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    out.push_back(session_of(line, file_ + ":" + std::to_string(line_), sessions_ + out.size(), elements_));
  }
  if (in_.bad()) throw Error(file_ + ": cannot read the sessions file (line " + std::to_string(line_ + 1) + ")");
  sessions_ += out.size();
  return out;
}

std::string format_sessions(std::span<const BatchSession> sessions) {
  std::string text;
  for (const BatchSession& s : sessions) {
    json readings = json::array();
    for (const Reading& r : s.readings)
      readings.push_back({{"position", vec3_json(r.position)},
                          {"normal", vec3_json(r.normal)},
                          {"x_axis", vec3_json(r.x_axis)},
                          {"pressure", r.pressure}});
    json line = {{"id", s.id}, {"readings", readings}};
    if (!s.truth.empty()) line["truth"] = truth_value(s);
    text += io::dump_json(line) + "\n";
  }
  return text;
}

std::string format_results(std::span<const BatchSession> sessions, std::span<const Estimate> estimates,
                           std::span<const std::string> objects) {
  if (sessions.size() != estimates.size()) throw std::logic_error("format_results: one estimate per session is needed");
  std::string text;
  for (std::size_t i = 0; i < sessions.size(); ++i)
    text += io::dump_json(result_json(sessions[i], estimates[i], objects)) + "\n";
  return text;
}

}  // namespace sva::batch
