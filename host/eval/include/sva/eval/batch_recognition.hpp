#pragma once
// Batch recognition of a sessions file's sessions (docs/batch-format.md): the work behind `sva recognize` and
// behind the Python package's batch recognition, on one machine or sharded over a cluster (docs/python.md). A
// shard is a run of consecutive sessions; recognised on one BatchRecognizer (one engine and its map, kept for
// every shard a worker gets) its results are the lines the whole file's run writes for those sessions, so the
// shards' results concatenated in input order are the single-machine results file.
#include <sva/base/progress.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/map.hpp>

#include <cstddef>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <sva/eval/batch_sessions.hpp>

namespace sva::batch {

// The estimates of `sessions`, in order, `top_k` hypotheses each. `rec` steps rec.sessions() of them together
// (its sessions are reset first). An error names `source` and the failing update's first session, counted from
// `first_session` (the shard's place in the whole file).
std::vector<Estimate> recognize_sessions(BatchRecognizer& rec, std::span<const io::BatchSession> sessions,
                                         std::size_t top_k, const std::string& source, std::size_t first_session = 0,
                                         util::Progress* progress = nullptr);

// The whole sessions file `source` (checked first: io::scan_batch_sessions), streamed: sessions are read one group
// of rec.sessions() at a time and each group's result lines go to `out` as it ends, so that memory holds one
// group whatever the file's length. The lines are those of format_batch_results over the whole file. Returns the
// sessions recognised.
std::size_t recognize_file(BatchRecognizer& rec, const Map& map, const std::string& source, std::size_t sessions,
                           std::ostream& out, std::size_t top_k, util::Progress* progress = nullptr);

// One shard: the lines of `text` (whole lines of the sessions file `source`, the first being line `first_line`,
// preceded in the file by `first_session` sessions) parsed, recognised on `rec` and formatted as result lines.
std::string recognize_shard(BatchRecognizer& rec, const Map& map, std::string_view text, const std::string& source,
                            std::size_t first_line, std::size_t first_session, std::size_t top_k);

}  // namespace sva::batch
