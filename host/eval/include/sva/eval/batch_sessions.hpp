#pragma once
// The batch-recognition files of `sva recognize` (docs/batch-format.md): the
// sessions file (JSON Lines, one session of readings per line) and the results
// file (one estimate per session, in input order). Reading checks every field
// before any recognition runs; an error names FILE:LINE, the field and the fault.
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/recognizer.hpp>

#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sva::io {

struct BatchSession {
  std::string id;                 // from the file, else the session's number
  std::vector<Reading> readings;  // at least one
  nlohmann::json truth;           // copied to the result when present (null otherwise)
};

// Reads a sessions file whose pressure images have `elements` values (the map's sensor).
std::vector<BatchSession> read_batch_sessions(const std::string& file, int elements);

// The sessions of `text`, a run of whole lines of the sessions file `file` (all of it, or one shard of it when
// batch recognition is sharded over machines): errors name `file`:LINE with lines counted from `first_line`, and
// sessions without an id are numbered from `first_session`, as in the whole file. Blank lines are skipped; no
// session at all is not an error here.
std::vector<BatchSession> parse_batch_sessions(std::string_view text, const std::string& file, std::size_t first_line,
                                               std::size_t first_session, int elements);

// Writes sessions in the same format (position, normal, x axis and pressure of every reading).
void write_batch_sessions(const std::string& file, std::span<const BatchSession> sessions);

// A pose as the results file writes it: R row by row, T and the Rodrigues vector.
nlohmann::json pose_json(const RigidPose& pose);

// One result line per session (sessions[i] with estimates[i]), each ending in a newline; `objects` names the
// map's objects in order. The results file is the concatenation of these lines, shard after shard.
std::string format_batch_results(std::span<const BatchSession> sessions, std::span<const Estimate> estimates,
                                 std::span<const std::string> objects);

// Writes format_batch_results to `file`.
// A sessions file read a few sessions at a time, so that batch recognition of a file of any length holds one
// group's sessions at once. Lines and session numbers count as in read_batch_sessions.
class BatchSessionReader {
 public:
  BatchSessionReader(const std::string& file, int elements);
  // The next `count` sessions (fewer at the end of the file; none after it).
  std::vector<BatchSession> next(std::size_t count);

 private:
  std::ifstream in_;
  std::string file_;
  int elements_ = 0;
  std::size_t line_ = 0;      // lines read so far
  std::size_t sessions_ = 0;  // sessions returned so far
};

struct BatchSessionsSummary {
  std::size_t sessions = 0, readings = 0;
};
// Reads the whole file once, checking every line as read_batch_sessions does, and keeps only the counts: a bad
// line anywhere is refused before hours of recognition. sva::Error for a file without sessions.
BatchSessionsSummary scan_batch_sessions(const std::string& file, int elements);

void write_batch_results(const std::string& file, std::span<const BatchSession> sessions,
                         std::span<const Estimate> estimates, std::span<const std::string> objects);

}  // namespace sva::io
