// JSON lines printed by the sensor commands (sva replay, sva record --map).
#include "sensor_output.hpp"

#include <sva/batch_file.hpp>
#include <sva/drivers/transport.hpp>

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>

namespace sva::cli {

nlohmann::json reading_json(const drivers::FormedReading& f) {
  const Reading& r = f.reading;
  return {{"type", "reading"},
          {"time", f.time},
          {"sequence", f.sequence},
          {"status", to_string(r.status)},
          {"position", {r.position.x, r.position.y, r.position.z}},
          {"normal", {r.normal.x, r.normal.y, r.normal.z}},
          {"x_axis", {r.x_axis.x, r.x_axis.y, r.x_axis.z}},
          {"pressure", r.pressure}};
}

nlohmann::json estimate_json(const Estimate& e, double time) {
  nlohmann::json top = nlohmann::json::array();
  for (const auto& h : e.top)
    top.push_back(
        {{"object", h.object_name}, {"probability", h.probability}, {"pose", io::parse_json(pose_json(h.pose))}});
  nlohmann::json j{{"type", "estimate"},
                   {"time", time},
                   {"readings", e.readings},
                   {"object", e.object_name},
                   {"object_probability", e.object_probability},
                   {"top", top}};
  if (e.pose_valid) j["pose"] = io::parse_json(pose_json(e.pose));
  return j;
}

ReadingPrinter::ReadingPrinter(const std::string& command, const std::string& map_file, BackendKind backend)
    : command_(command) {
  if (map_file.empty()) return;
  map_.emplace(Map::load(map_file));
  RecognizerOptions o;
  o.backend = backend;
  recognizer_.emplace(*map_, map_->pose_space(), o);
}

void ReadingPrinter::operator()(const drivers::FormedReading& f) {
  ++readings_;
  std::printf("%s\n", io::dump_json(reading_json(f)).c_str());
  if (recognizer_ && f.reading.status == ControllerStatus::converged) {
    const auto start = drivers::monotonic_ns();
    recognizer_->add_reading(f.reading);
    const auto e = recognizer_->estimate();
    worst_update_ms_ = std::max(worst_update_ms_, static_cast<double>(drivers::monotonic_ns() - start) * 1e-6);
    std::printf("%s\n", io::dump_json(estimate_json(e, f.time)).c_str());
    ++recognised_;
    const double p = e.object < e.object_probability.size() ? e.object_probability[e.object] : 0.0;
    std::fprintf(stderr, "%s: reading %zu: %s (p = %.3f)\n", command_.c_str(), readings_, e.object_name.c_str(), p);
  }
  std::fflush(stdout);
}

}  // namespace sva::cli
