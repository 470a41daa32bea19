#include <sva/eval/batch_recognition.hpp>

#include <sva/error.hpp>

#include <algorithm>
#include <numeric>

#include "map/pair_map.hpp"
#include "recognition/lockstep.hpp"

namespace sva::batch {

namespace {

// The lock-step loop over `sessions` sessions that `fetch(first, count)` supplies a group at a time (a span that
// stays valid until the next call); `done(first, group, estimates)` takes each group's estimates as it ends. An
// error names `source` and the failing update's first session, counted from `first_session`.
template <class Fetch, class Done>
void recognize_groups(BatchRecognizer& rec, std::size_t sessions, std::size_t top_k, const std::string& source,
                      std::size_t first_session, util::Progress* progress, Fetch fetch, Done done) {
  std::span<const io::BatchSession> group;
  LockstepHooks hooks;
  hooks.progress = progress;
  hooks.group = [&](std::size_t first, std::size_t count) {
    group = fetch(first, count);
    std::vector<std::span<const Reading>> readings;
    for (const io::BatchSession& s : group) readings.emplace_back(s.readings);
    return readings;
  };
  hooks.on_group_end = [&](std::size_t first, std::size_t count) {
    std::vector<std::size_t> slots(count);
    std::iota(slots.begin(), slots.end(), std::size_t{0});
    done(first, group, rec.estimates(slots, top_k));
  };
  hooks.on_error = [&](const Error& e, const LockstepStep& s) {
    return Error(source + ": " + e.what() + " (session numbers count from " + std::to_string(first_session + s.first) +
                 ")");
  };
  run_lockstep(rec, sessions, hooks);
}

}  // namespace

std::vector<Estimate> recognize_sessions(BatchRecognizer& rec, std::span<const io::BatchSession> sessions,
                                         std::size_t top_k, const std::string& source, std::size_t first_session,
                                         util::Progress* progress) {
  std::vector<Estimate> out(sessions.size());
  recognize_groups(
      rec, sessions.size(), top_k, source, first_session, progress,
      [&](std::size_t first, std::size_t count) { return sessions.subspan(first, count); },
      [&](std::size_t first, std::span<const io::BatchSession>, std::vector<Estimate> estimates) {
        std::move(estimates.begin(), estimates.end(), out.begin() + static_cast<std::ptrdiff_t>(first));
      });
  return out;
}

std::size_t recognize_file(BatchRecognizer& rec, const Map& map, const std::string& source, std::size_t sessions,
                           std::ostream& out, std::size_t top_k, util::Progress* progress) {
  io::BatchSessionReader reader(source, map.sensor().elements());
  const std::vector<std::string> objects = map.object_names();
  std::vector<io::BatchSession> held;  // the group being recognised: all the memory the file's sessions take
  recognize_groups(
      rec, sessions, top_k, source, 0, progress,
      [&](std::size_t first, std::size_t count) {
        held = reader.next(count);
        if (held.size() != count)
          throw Error(source + ": the file changed while it was read (session " + std::to_string(first + held.size()) +
                      " is missing)");
        return std::span<const io::BatchSession>(held);
      },
      [&](std::size_t, std::span<const io::BatchSession> group, const std::vector<Estimate>& estimates) {
        out << io::format_batch_results(group, estimates, objects);
      });
  return sessions;
}

std::string recognize_shard(BatchRecognizer& rec, const Map& map, std::string_view text, const std::string& source,
                            std::size_t first_line, std::size_t first_session, std::size_t top_k) {
  const int elements = map.sensor().elements();
  const auto sessions = io::parse_batch_sessions(text, source, first_line, first_session, elements);
  const auto estimates = recognize_sessions(rec, sessions, top_k, source, first_session);
  return io::format_batch_results(sessions, estimates, map.object_names());
}

}  // namespace sva::batch
