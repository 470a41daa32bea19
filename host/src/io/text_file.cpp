#include "io/text_file.hpp"

#include <sva/error.hpp>

#include <fstream>
#include <unistd.h>

namespace sva::io {

void write_text_file(const std::filesystem::path& file, std::string_view text) {
  auto tmp = file;
  tmp += ".tmp." + std::to_string(::getpid());
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(file.string() + ": cannot open for writing");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      throw Error(file.string() + ": write failed (disk full?)");
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(file.string() + ": cannot rename the temporary file into place");
  }
}

}  // namespace sva::io
