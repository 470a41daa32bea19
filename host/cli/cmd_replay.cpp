// sva replay: plays a sensor session recording through the live pipeline
// (parser, settle rule, pose matching) and prints each reading as it forms;
// with a map, recognises as the readings arrive and prints the estimate.
#include <sva/batch_file.hpp>
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include <sva/io/json.hpp>
#include "args.hpp"
#include "sensor_output.hpp"

namespace sva::cli {

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
      .option("--backend", "cpu|vulkan|auto", "vote backend with --map (default cpu)")
      .option("--pose-clock-offset", "S",
              "seconds added to the recorded poses' times before matching, in place of the recording's own offset")
      .option("--write-session", "FILE.jsonl",
              "also write the converged readings as a one-session sessions file (docs/batch-format.md; their times "
              "in seconds under truth.stamps_s), for sva recognize and python -m sva.ros export");
  if (!a.parse()) return 0;
  const std::string file = positional ? *positional : a.required("--session");
  const double speed = a.number("--speed", 1.0, 0.0, 1e6);
  auto session = drivers::load_session(file);
  if (a.has("--pose-clock-offset")) {
    session.settings.settle.pose_clock_offset_s = a.number("--pose-clock-offset", 0.0, -1e9, 1e9);
    session.settings.settle.validate();
  }
  if (!session.tail_problem.empty())
    std::fprintf(stderr, "sva replay: %s ends early (%s); replaying everything before it\n", file.c_str(),
                 session.tail_problem.c_str());

  ReadingPrinter printer("sva replay", a.get_or("--map", ""),
                         parse_backend_kind(a.get_or("--backend", "cpu"), "sva replay: --backend"));
  double worst_latency_ms = 0;
  // --write-session: the recognizer's readings (only converged ones are used) and their times.
  BatchSession kept{std::filesystem::path(file).stem().string(), {}, {}};
  nlohmann::json stamps = nlohmann::json::array();
  drivers::PipelineEvents events;
  events.on_reading = [&](const drivers::FormedReading& f, std::int64_t delivered_ns) {
    printer(f);
    if (f.reading.status == ControllerStatus::converged) {
      kept.readings.push_back(f.reading);
      stamps.push_back(f.time);
    }
    worst_latency_ms = std::max(worst_latency_ms, static_cast<double>(drivers::monotonic_ns() - delivered_ns) * 1e-6);
  };
  events.on_note = [](const drivers::ContactNote& n) { std::fprintf(stderr, "sva replay: %s\n", n.text.c_str()); };
  events.on_link = [](const drivers::SensorEvent& e) {
    if (e.status != drivers::LinkStatus::ended)
      std::fprintf(stderr, "sva replay: link %s: %s\n", drivers::to_string(e.status), e.message.c_str());
  };
  const auto stats = drivers::replay_session(session, speed, events);
  if (auto out = a.get("--write-session")) {
    if (kept.readings.empty())
      throw Error("sva replay: " + file + " formed no converged reading: nothing to write to " + *out);
    kept.truth = io::dump_json(nlohmann::json{{"recording", file}, {"stamps_s", std::move(stamps)}});
    write_batch_sessions(*out, std::span<const BatchSession>(&kept, 1));
    std::fprintf(stderr, "sva replay: wrote %zu converged readings to %s\n", kept.readings.size(), out->c_str());
  }
  std::fprintf(stderr,
               "sva replay: %zu readings (%zu recognised); %llu frames, %llu bytes skipped, %llu CRC errors, %llu "
               "frames missing in %llu gaps, %llu disconnects; worst latency last frame -> output %.2f ms (worst "
               "recognizer update %.2f ms)\n",
               printer.readings(), printer.recognised(), static_cast<unsigned long long>(stats.parser.frames),
               static_cast<unsigned long long>(stats.parser.bytes_skipped),
               static_cast<unsigned long long>(stats.parser.crc_errors),
               static_cast<unsigned long long>(stats.parser.frames_missing),
               static_cast<unsigned long long>(stats.parser.sequence_gaps),
               static_cast<unsigned long long>(stats.disconnects), worst_latency_ms, printer.worst_update_ms());
  return 0;
}

}  // namespace sva::cli
