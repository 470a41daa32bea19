#pragma once
// The batch-recognition files of `sva recognize` (docs/batch-format.md): the
// sessions file (JSON Lines, one session of readings per line) and the results
// file (one estimate per session, in input order). Reading checks every field
// before any recognition runs; an error names FILE:LINE, the field and the fault.
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/recognizer.hpp>

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
void write_batch_results(const std::string& file, std::span<const BatchSession> sessions,
                         std::span<const Estimate> estimates, std::span<const std::string> objects);

}  // namespace sva::io
