#include "batch/batch_recognition.hpp"

#include <sva/error.hpp>

#include "map/pair_map.hpp"
#include "recognition/lockstep.hpp"

namespace sva::batch {

std::vector<Estimate> recognize_sessions(BatchRecognizer& rec, std::span<const io::BatchSession> sessions,
                                         std::size_t top_k, const std::string& source, std::size_t first_session,
                                         util::Progress* progress) {
  std::vector<Estimate> estimates(sessions.size());
  LockstepHooks hooks;
  hooks.progress = progress;
  hooks.group = [&](std::size_t first, std::size_t count) {
    std::vector<std::span<const Reading>> readings;
    for (std::size_t i = 0; i < count; ++i) readings.emplace_back(sessions[first + i].readings);
    return readings;
  };
  hooks.on_group_end = [&](std::size_t first, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) estimates[first + i] = rec.estimate(i, top_k);
  };
  hooks.on_error = [&](const Error& e, const LockstepStep& s) {
    return Error(source + ": " + e.what() + " (session numbers count from " + std::to_string(first_session + s.first) +
                 ")");
  };
  run_lockstep(rec, sessions.size(), hooks);
  return estimates;
}

std::size_t recognize_file(BatchRecognizer& rec, const Map& map, const std::string& source, std::size_t sessions,
                           std::ostream& out, std::size_t top_k, util::Progress* progress) {
  io::BatchSessionReader reader(source, map.internal().appearance.calibration.sensor.elements());
  const std::vector<std::string> objects = map.object_names();
  std::vector<io::BatchSession> group;
  LockstepHooks hooks;
  hooks.progress = progress;
  hooks.group = [&](std::size_t first, std::size_t count) {
    group = reader.next(count);
    if (group.size() != count)
      throw Error(source + ": the file changed while it was read (session " + std::to_string(first + group.size()) +
                  " is missing)");
    std::vector<std::span<const Reading>> readings;
    for (const io::BatchSession& s : group) readings.emplace_back(s.readings);
    return readings;
  };
  hooks.on_group_end = [&](std::size_t, std::size_t count) {
    std::vector<Estimate> estimates;
    for (std::size_t i = 0; i < count; ++i) estimates.push_back(rec.estimate(i, top_k));
    out << io::format_batch_results(group, estimates, objects);
  };
  hooks.on_error = [&](const Error& e, const LockstepStep& s) {
    return Error(source + ": " + e.what() + " (session numbers count from " + std::to_string(s.first) + ")");
  };
  run_lockstep(rec, sessions, hooks);
  return sessions;
}

std::string recognize_shard(BatchRecognizer& rec, const Map& map, std::string_view text, const std::string& source,
                            std::size_t first_line, std::size_t first_session, std::size_t top_k) {
  const int elements = map.internal().appearance.calibration.sensor.elements();
  const auto sessions = io::parse_batch_sessions(text, source, first_line, first_session, elements);
  const auto estimates = recognize_sessions(rec, sessions, top_k, source, first_session);
  return io::format_batch_results(sessions, estimates, map.object_names());
}

}  // namespace sva::batch
