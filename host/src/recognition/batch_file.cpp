// Batch recognition of a sessions file (<sva/batch_file.hpp>): the lock-step loop of recognition/lockstep.hpp over
// the sessions a file, or a shard of one, supplies a group at a time; the file's format is batch_sessions.cpp's.
#include <sva/batch_file.hpp>

#include <sva/base/progress.hpp>
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <numeric>
#include <optional>

#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>
#include "recognition/batch_sessions.hpp"
#include "recognition/group_turns.hpp"
#include "recognition/lockstep.hpp"

namespace sva {

namespace batch {

namespace {

// Every recognizer of a batch steps as many sessions together.
std::size_t group_size(std::span<BatchRecognizer> recs) {
  if (recs.empty()) throw Error("batch recognition: no recognizer given");
  for (std::size_t i = 1; i < recs.size(); ++i)
    if (recs[i].sessions() != recs[0].sessions())
      throw Error("batch recognition: recognizer " + std::to_string(i) + " of " + std::to_string(recs.size()) +
                  " steps " + std::to_string(recs[i].sessions()) + " sessions, the first " +
                  std::to_string(recs[0].sessions()) + " (they must step as many)");
  return recs[0].sessions();
}

// One group, sessions [first, first + count), on `rec`: its sessions fetched in its turn, stepped in lock step, its
// estimates read, and handed to `done` in its turn. An error names `source` and the group's first session, counted
// from `first_session`.
template <class Fetch, class Done>
void recognize_group(BatchRecognizer& rec, std::size_t group, std::size_t first, std::size_t count, GroupTurns& turns,
                     const EstimateAsk& ask, const std::string& source, std::size_t first_session,
                     util::Progress* progress, Fetch& fetch, Done& done) {
  std::vector<BatchSession> storage;  // what fetch() read for this group, when it reads
  turns.wait(GroupTurns::kFetch, group);
  const std::span<const BatchSession> sessions = fetch(first, count, storage);
  turns.pass(GroupTurns::kFetch);
  LockstepHooks hooks;
  hooks.progress = progress;
  hooks.group = [&](std::size_t, std::size_t) {
    std::vector<std::span<const Reading>> readings;
    for (const BatchSession& s : sessions) readings.emplace_back(s.readings);
    return readings;
  };
  hooks.on_step = [&](const LockstepStep&) { turns.check(group); };
  hooks.on_error = [&](const Error& e, const LockstepStep&) {
    return Error(source + ": " + e.what() + " (session numbers count from " + std::to_string(first_session + first) +
                 ")");
  };
  run_lockstep(rec, count, hooks);
  std::vector<std::size_t> slots(count);
  std::iota(slots.begin(), slots.end(), std::size_t{0});
  std::vector<Estimate> estimates = rec.estimates(slots, ask.top_k, ask.depth);
  turns.wait(GroupTurns::kDone, group);
  done(first, sessions, std::move(estimates));
  turns.pass(GroupTurns::kDone);
}

// The lock-step loop over `sessions` sessions that `fetch(first, count, storage)` supplies a group at a time (a
// span into `storage` or into what the caller keeps); `done(first, group, estimates)` takes each group's estimates
// in group order. Group g runs on recs[g % recs.size()], the groups of different recognizers at once.
template <class Fetch, class Done>
void recognize_groups(std::span<BatchRecognizer> recs, std::size_t sessions, const EstimateAsk& ask,
                      const std::string& source, std::size_t first_session, util::Progress* progress, Fetch fetch,
                      Done done) {
  const std::size_t per = group_size(recs);
  GroupTurns turns;
  run_groups((sessions + per - 1) / per, recs.size(), turns, [&](std::size_t g, std::size_t w) {
    const std::size_t first = g * per;
    recognize_group(recs[w], g, first, std::min(per, sessions - first), turns, ask, source, first_session, progress,
                    fetch, done);
  });
}

}  // namespace

std::vector<Estimate> recognize_sessions(std::span<BatchRecognizer> recs, std::span<const BatchSession> sessions,
                                         const EstimateAsk& ask, const std::string& source, std::size_t first_session,
                                         util::Progress* progress) {
  std::vector<Estimate> out(sessions.size());
  recognize_groups(
      recs, sessions.size(), ask, source, first_session, progress,
      [&](std::size_t first, std::size_t count, std::vector<BatchSession>&) { return sessions.subspan(first, count); },
      [&](std::size_t first, std::span<const BatchSession>, std::vector<Estimate> estimates) {
        std::move(estimates.begin(), estimates.end(), out.begin() + static_cast<std::ptrdiff_t>(first));
      });
  return out;
}

}  // namespace batch

std::vector<BatchSession> read_batch_sessions(const std::filesystem::path& file, int elements) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(name + ": cannot read the sessions file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(name + ": cannot read the sessions file");
  std::vector<BatchSession> out = batch::parse_sessions(text, name, 1, 0, elements);
  if (out.empty()) throw Error(name + ": no sessions (empty file)");
  return out;
}

void write_batch_sessions(const std::filesystem::path& file, std::span<const BatchSession> sessions) {
  io::write_text_file(file, batch::format_sessions(sessions));
}

std::string pose_json(const RigidPose& pose) { return io::dump_json(batch::pose_value(pose)); }

BatchSessionsFile::BatchSessionsFile(std::filesystem::path file, int elements)
    : file_(std::move(file)), elements_(elements) {
  // Every line parsed and checked, only the counts kept: the whole file's check costs one group's memory.
  batch::SessionReader reader(file_.string(), elements_);
  for (std::vector<BatchSession> part; !(part = reader.next(256)).empty();)
    for (const BatchSession& s : part) ++sessions_, readings_ += s.readings.size();
  if (sessions_ == 0) throw Error(file_.string() + ": no sessions (empty file)");
}

void BatchSessionsFile::recognize(BatchRecognizer& rec, const Map& map, const std::filesystem::path& results,
                                  std::size_t top_k, bool progress, EstimateDepth depth) const {
  recognize(std::span(&rec, 1), map, results, top_k, progress, depth);
}

void BatchSessionsFile::recognize(std::span<BatchRecognizer> recs, const Map& map, const std::filesystem::path& results,
                                  std::size_t top_k, bool progress, EstimateDepth depth) const {
  const std::string source = file_.string();
  const std::vector<std::string> objects = map.object_names();
  std::optional<util::Progress> shown;
  if (progress) shown.emplace("recognize", readings_);
  // Each group's result lines go to the results file's temporary as the group ends; the rename comes last.
  io::write_file_atomically(results, [&](std::ostream& out) {
    batch::SessionReader reader(source, elements_);  // read in group order (the fetch turn)
    batch::recognize_groups(
        recs, sessions_, {top_k, depth}, source, 0, shown ? &*shown : nullptr,
        [&](std::size_t first, std::size_t count, std::vector<BatchSession>& held) {
          held = reader.next(count);  // the groups in flight: all the memory the file's sessions take
          if (held.size() != count)
            throw Error(source + ": the file changed while it was read (session " +
                        std::to_string(first + held.size()) + " is missing)");
          return std::span<const BatchSession>(held);
        },
        [&](std::size_t, std::span<const BatchSession> group, const std::vector<Estimate>& estimates) {
          out << batch::format_results(group, estimates, objects);
        });
  });
  if (shown) shown->finish();
}

std::string recognize_batch_shard(BatchRecognizer& rec, const Map& map, std::string_view text,
                                  const std::string& source, std::size_t first_line, std::size_t first_session,
                                  std::size_t top_k, EstimateDepth depth) {
  return recognize_batch_shard(std::span(&rec, 1), map, text, source, first_line, first_session, top_k, depth);
}

std::string recognize_batch_shard(std::span<BatchRecognizer> recs, const Map& map, std::string_view text,
                                  const std::string& source, std::size_t first_line, std::size_t first_session,
                                  std::size_t top_k, EstimateDepth depth) {
  const auto sessions = batch::parse_sessions(text, source, first_line, first_session, map.sensor().elements());
  const auto estimates = batch::recognize_sessions(recs, sessions, {top_k, depth}, source, first_session);
  return batch::format_results(sessions, estimates, map.object_names());
}

std::vector<BatchRecognizer> batch_recognizers(const Engine& engine, std::size_t sessions, std::size_t per_group,
                                               std::size_t in_flight, const RecognizerOptions& options) {
  if (sessions == 0 || per_group == 0 || in_flight == 0)
    throw Error("batch recognition: sessions, sessions per group and groups in flight must be >= 1 (have " +
                std::to_string(sessions) + ", " + std::to_string(per_group) + ", " + std::to_string(in_flight) + ")");
  const std::size_t group = std::min(per_group, sessions);
  std::vector<BatchRecognizer> recs;
  for (std::size_t i = 0; i < std::min(in_flight, (sessions + group - 1) / group); ++i)
    recs.emplace_back(engine, engine.map().pose_space(), group, options);
  return recs;
}

}  // namespace sva
