#pragma once
// Every output file is written atomically: to a temporary name first, renamed
// into place only when complete, so an error or Ctrl-C never leaves a partial
// file that looks complete, and a full disk or a read-only directory leaves
// the previous file intact with an sva::Error naming the file and the system's
// reason. The one helper for every writer (maps, datasets, sessions, batch
// results, figures, eval and bench outputs, calibrations, meshes); recordings
// alone append in place (a crash keeps every whole record; docs/recording-format.md).
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>

namespace sva::io {

// Runs `body` on a stream to a temporary file beside `file`, then renames it
// into place; on any exception the temporary file is removed and the
// exception propagates.
void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& body);
void write_text_file(const std::filesystem::path& file, std::string_view text);
// A whole file's bytes; sva::Error "<file>: <failure>" when it cannot be opened (e.g. "cannot read scene file").
std::string read_text_file(const std::filesystem::path& file, std::string_view failure);

}  // namespace sva::io
