// sva replay: plays a sensor session recording through the live pipeline
// (parser, settle rule, pose matching) and prints each reading as it forms;
// with a map, recognises as the readings arrive and prints the estimate.
#include <sva/drivers/session.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "args.hpp"
#include "io/batch_sessions.hpp"
#include "recognition/vote_backend_factory.hpp"

namespace sva::cli {

namespace {

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
    top.push_back({{"object", h.object_name}, {"probability", h.probability}, {"pose", io::pose_json(h.pose)}});
  nlohmann::json j{{"type", "estimate"},
                   {"time", time},
                   {"readings", e.readings},
                   {"object", e.object_name},
                   {"object_probability", e.object_probability},
                   {"top", top}};
  if (e.pose_valid) j["pose"] = io::pose_json(e.pose);
  return j;
}

}  // namespace

int cmd_replay(const std::vector<std::string>& argv_in) {
  std::vector<std::string> argv = argv_in;
  std::optional<std::string> positional;
  if (!argv.empty() && argv[0].rfind("-", 0) != 0) {
    positional = argv[0];
    argv.erase(argv.begin());
  }
  Args a("sva replay",
         "Play a session recording (sva record, sva export --recording) through the sensor pipeline: usage\n"
         "`sva replay SESSION [--map MAP] [--speed X]`. Prints one JSON line per reading formed (and, with a map,\n"
         "the estimate after each converged reading); link events, notes and statistics go to stderr.",
         argv);
  a.option("--session", "SESSION", "the recording (or give it first, without the option)")
      .option("--map", "MAP", "recognise the readings with this map (sva train)")
      .option("--speed", "X", "1: the recorded pace (default), 2: twice as fast, 0: as fast as possible")
      .option("--backend", "cpu|vulkan|auto", "vote backend with --map (default cpu)");
  if (!a.parse()) return 0;
  const std::string file = positional ? *positional : a.required("--session");
  const double speed = a.number("--speed", 1.0, 0.0, 1e6);
  const auto session = drivers::load_session(file);
  if (!session.tail_problem.empty())
    std::fprintf(stderr, "sva replay: %s ends early (%s); replaying everything before it\n", file.c_str(),
                 session.tail_problem.c_str());

  std::optional<Map> map;
  std::optional<Recognizer> recognizer;
  if (auto m = a.get("--map")) {
    map.emplace(Map::load(*m));
    RecognizerOptions o;
    o.backend = parse_backend_kind(a.get_or("--backend", "cpu"), "sva replay: --backend");
    recognizer.emplace(*map, map->pose_space(), o);
  }
  std::size_t readings = 0, recognised = 0;
  double worst_latency_ms = 0, worst_update_ms = 0;
  drivers::PipelineEvents events;
  events.on_reading = [&](const drivers::FormedReading& f, std::int64_t delivered_ns) {
    ++readings;
    std::printf("%s\n", reading_json(f).dump().c_str());
    if (recognizer && f.reading.status == ControllerStatus::converged) {
      const auto update_start = drivers::monotonic_ns();
      recognizer->add_reading(f.reading);
      const auto estimate = recognizer->estimate();
      worst_update_ms = std::max(worst_update_ms, static_cast<double>(drivers::monotonic_ns() - update_start) * 1e-6);
      std::printf("%s\n", estimate_json(estimate, f.time).dump().c_str());
      ++recognised;
    }
    std::fflush(stdout);
    worst_latency_ms = std::max(worst_latency_ms, static_cast<double>(drivers::monotonic_ns() - delivered_ns) * 1e-6);
  };
  events.on_note = [](const drivers::ContactNote& n) { std::fprintf(stderr, "sva replay: %s\n", n.text.c_str()); };
  events.on_link = [](const drivers::SensorEvent& e) {
    if (e.status != drivers::LinkStatus::ended)
      std::fprintf(stderr, "sva replay: link %s: %s\n", drivers::to_string(e.status), e.message.c_str());
  };
  const auto stats = drivers::replay_session(session, speed, events);
  std::fprintf(stderr,
               "sva replay: %zu readings (%zu recognised); %llu frames, %llu bytes skipped, %llu CRC errors, %llu "
               "frames missing in %llu gaps, %llu disconnects; worst latency last frame -> output %.2f ms (worst "
               "recognizer update %.2f ms)\n",
               readings, recognised, static_cast<unsigned long long>(stats.parser.frames),
               static_cast<unsigned long long>(stats.parser.bytes_skipped),
               static_cast<unsigned long long>(stats.parser.crc_errors),
               static_cast<unsigned long long>(stats.parser.frames_missing),
               static_cast<unsigned long long>(stats.parser.sequence_gaps),
               static_cast<unsigned long long>(stats.disconnects), worst_latency_ms, worst_update_ms);
  return 0;
}

}  // namespace sva::cli
