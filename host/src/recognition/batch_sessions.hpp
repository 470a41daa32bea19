#pragma once
// The sessions file and the results file of batch recognition (docs/batch-format.md), behind the public
// <sva/batch_file.hpp>: parsing whole lines (a file or a shard of one), streaming a file a group at a time, and the
// result lines. Reading checks every field before any recognition runs; an error names FILE:LINE, the field and
// the fault. Private: the tests, the fuzz harness and the tools' library reach the pieces here.
#include <sva/base/progress.hpp>
#include <sva/batch_file.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/pose.hpp>
#include <sva/recognizer.hpp>

#include <cstddef>
#include <fstream>
#include <nlohmann/json_fwd.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sva::batch {

// The sessions of `text`, a run of whole lines of the sessions file `file` (all of it, or one shard of it when
// batch recognition is sharded over machines): errors name `file`:LINE with lines counted from `first_line`, and
// sessions without an id are numbered from `first_session`, as in the whole file. Blank lines are skipped; no
// session at all is not an error here.
std::vector<BatchSession> parse_sessions(std::string_view text, const std::string& file, std::size_t first_line,
                                         std::size_t first_session, int elements);

// The lines of a sessions file holding `sessions` (every reading's position, normal, x axis and pressure).
std::string format_sessions(std::span<const BatchSession> sessions);

// A pose as the results file writes it: R row by row, T and the Rodrigues vector.
nlohmann::json pose_value(const RigidPose& pose);

// One result line per session (sessions[i] with estimates[i]), each ending in a newline; `objects` names the
// map's objects in order. The results file is the concatenation of these lines, shard after shard.
std::string format_results(std::span<const BatchSession> sessions, std::span<const Estimate> estimates,
                           std::span<const std::string> objects);

// A sessions file read a few sessions at a time, so that batch recognition of a file of any length holds one
// group's sessions at once. Lines and session numbers count as in read_batch_sessions.
class SessionReader {
 public:
  SessionReader(const std::string& file, int elements);
  // The next `count` sessions (fewer at the end of the file; none after it).
  std::vector<BatchSession> next(std::size_t count);

 private:
  std::ifstream in_;
  std::string file_;
  int elements_ = 0;
  std::size_t line_ = 0;      // lines read so far
  std::size_t sessions_ = 0;  // sessions returned so far
};

// What a batch asks of each session's estimate at its end.
struct EstimateAsk {
  std::size_t top_k = 3;
  EstimateDepth depth = EstimateDepth::full;
};

// The estimates of `sessions`, in order, as `ask` says. Each recognizer of `recs` steps rec.sessions() of
// them together (its sessions are reset first), the recognizers' groups in flight at once (group_turns.hpp). An
// error names `source` and the failing update's first session, counted from `first_session` (the shard's place in
// the whole file).
std::vector<Estimate> recognize_sessions(std::span<BatchRecognizer> recs, std::span<const BatchSession> sessions,
                                         const EstimateAsk& ask, const std::string& source,
                                         std::size_t first_session = 0, util::Progress* progress = nullptr);

}  // namespace sva::batch
