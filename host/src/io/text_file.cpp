#include "io/text_file.hpp"

#include <sva/error.hpp>

#include <unistd.h>
#include <fstream>

namespace sva::io {

void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& body) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  auto tmp = file;
  tmp += ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(file.string() + ": cannot open for writing");
    try {
      body(out);
      out.flush();
      if (!out) throw Error(file.string() + ": write failed (disk full?)");
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp, ec);
      throw;
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(file.string() + ": cannot rename the temporary file into place (" + ec.message() + ")");
  }
}

void write_text_file(const std::filesystem::path& file, std::string_view text) {
  write_file_atomically(file,
                        [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

}  // namespace sva::io
