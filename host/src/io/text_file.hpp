#pragma once
// Text outputs (JSON, JSON Lines, CSV) written atomically: to a temporary name
// first, renamed into place only when complete, so an error or Ctrl-C never
// leaves a partial file that looks complete.
#include <filesystem>
#include <string_view>

namespace sva::io {

void write_text_file(const std::filesystem::path& file, std::string_view text);

}  // namespace sva::io
