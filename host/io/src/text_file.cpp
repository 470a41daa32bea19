#include <sva/io/text_file.hpp>

#include <sva/error.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace sva::io {

namespace {

// The system's reason for the last failure ("No space left on device", "Read-only file system").
std::string reason(int error) { return error ? std::string(" (") + std::strerror(error) + ")" : std::string(); }

}  // namespace

void write_file_atomically(const std::filesystem::path& file, const std::function<void(std::ostream&)>& body) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  auto tmp = file;
  tmp += ".tmp." + std::to_string(::getpid());
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw Error(file.string() + ": cannot write: cannot create a temporary file beside it" + reason(errno) +
                  "; any earlier file is left as it was");
    // The first failure's errno: a full disk shows in body(), when the stream's buffer reaches the file, or at
    // the final flush.
    const auto check = [&] {
      if (!out) throw Error(file.string() + ": write failed" + reason(errno) + "; any earlier file is left as it was");
    };
    try {
      errno = 0;
      body(out);
      check();
      out.flush();
      check();
      out.close();
      check();
    } catch (...) {
      out.close();
      std::filesystem::remove(tmp, ec);
      throw;
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignored;  // the rename's error is the one to report, not the clean-up's
    std::filesystem::remove(tmp, ignored);
    throw Error(file.string() + ": cannot rename the temporary file into place (" + ec.message() +
                "); any earlier file is left as it was");
  }
}

void write_text_file(const std::filesystem::path& file, std::string_view text) {
  write_file_atomically(file,
                        [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

std::string read_text_file(const std::filesystem::path& file, std::string_view failure) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": " + std::string(failure));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace sva::io
