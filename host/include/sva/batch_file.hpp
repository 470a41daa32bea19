#pragma once
// Batch recognition of a sessions file (docs/batch-format.md), as `sva recognize`, sva.recognize_batch and
// sva.distributed run it: a sessions file (JSON Lines, one session of readings per line) is checked whole, its
// sessions are recognised on a BatchRecognizer, rec.sessions() of them stepped together, and the results file gets
// one estimate per session (JSON Lines, in input order). A bad line is refused before any recognition runs, with
// sva::Error naming FILE:LINE, the field and the fault.
//
//   sva::BatchSessionsFile file("sessions.jsonl", map.sensor().elements());  // every line checked
//   sva::BatchRecognizer rec(map, map.pose_space(), std::min<std::size_t>(64, file.sessions()));
//   file.recognize(rec, map, "results.jsonl");
#include <sva/batch_recognizer.hpp>
#include <sva/engine.hpp>
#include <sva/map.hpp>
#include <sva/pose.hpp>
#include <sva/reading.hpp>

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sva {

// One session of a sessions file.
struct BatchSession {
  std::string id;                 // the line's "id", else the session's number in the file (from 0)
  std::vector<Reading> readings;  // at least one in a file
  std::string truth;              // the line's "truth" (any JSON, copied to the session's result) as JSON text; ""
                                  // when absent
};

// The sessions of a whole sessions file whose pressure images have `elements` values (the map's sensor:
// map.sensor().elements()). sva::Error for a file without sessions.
std::vector<BatchSession> read_batch_sessions(const std::filesystem::path& file, int elements);

// Writes `sessions` as a sessions file (every reading's position, normal, x axis and pressure; the truth when
// given), atomically as every file sva writes.
void write_batch_sessions(const std::filesystem::path& file, std::span<const BatchSession> sessions);

// A pose as the results file writes it, as JSON text: {"R": [3 rows], "T": [x, y, z], "rodrigues": [x, y, z]}.
std::string pose_json(const RigidPose& pose);

// A sessions file of any length: checked whole when made (a bad line anywhere is refused before hours of
// recognition), then recognised a group at a time, so that memory holds one group's sessions.
class BatchSessionsFile {
 public:
  BatchSessionsFile(std::filesystem::path file, int elements);

  std::size_t sessions() const { return sessions_; }
  std::size_t readings() const { return readings_; }

  // Recognises every session on `rec` (made from `map`), `top_k` hypotheses each, and writes their results to
  // `results`, which appears whole or not at all. With `progress`, a progress line on stderr
  // (util::Progress). `depth`: each session's estimate at its end (light: the belief's answer, no host fits;
  // docs/recognition.md, "Light and full estimates"). sva::Error names the file and the failing update's first session.
  void recognize(BatchRecognizer& rec, const Map& map, const std::filesystem::path& results, std::size_t top_k = 3,
                 bool progress = false, EstimateDepth depth = EstimateDepth::full) const;
  // The same with groups in flight on several recognizers at once, one thread each (batch_recognizers() makes them,
  // on one Engine, as many sessions each): while one group's update runs on the device, the next group's host work
  // goes on. The results file holds the same bytes as on one.
  void recognize(std::span<BatchRecognizer> recs, const Map& map, const std::filesystem::path& results,
                 std::size_t top_k = 3, bool progress = false, EstimateDepth depth = EstimateDepth::full) const;

 private:
  std::filesystem::path file_;
  int elements_ = 0;
  std::size_t sessions_ = 0, readings_ = 0;
};

// One shard of a sessions file, for recognition sharded over machines (sva.distributed): `text` holds whole lines
// of the file `source`, the first being line `first_line` (from 1), preceded in the file by `first_session`
// sessions. Returns the result lines of its sessions, recognised on `rec` (made from `map`): the lines that
// recognising the whole file writes for them, so that the shards' lines concatenated in input order are the whole
// file's results. Errors name `source`:LINE as for the whole file.
std::string recognize_batch_shard(BatchRecognizer& rec, const Map& map, std::string_view text,
                                  const std::string& source, std::size_t first_line, std::size_t first_session,
                                  std::size_t top_k = 3, EstimateDepth depth = EstimateDepth::full);
// The same with groups in flight on several recognizers at once (as BatchSessionsFile::recognize).
std::string recognize_batch_shard(std::span<BatchRecognizer> recs, const Map& map, std::string_view text,
                                  const std::string& source, std::size_t first_line, std::size_t first_session,
                                  std::size_t top_k = 3, EstimateDepth depth = EstimateDepth::full);

// The recognizers of a batch of `sessions` sessions with `in_flight` groups of `per_group` at once (the defaults:
// engine.sessions_per_submission(options), engine.submissions_in_flight()): as many as there are groups, at most
// `in_flight`, each stepping min(per_group, sessions) sessions on `engine` with the map's pose space.
std::vector<BatchRecognizer> batch_recognizers(const Engine& engine, std::size_t sessions, std::size_t per_group,
                                               std::size_t in_flight, const RecognizerOptions& options = {});

}  // namespace sva
