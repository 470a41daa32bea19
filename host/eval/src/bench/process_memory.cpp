#include <sva/eval/process_memory.hpp>

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

namespace sva::bench {

namespace {

// A "Name:   1234 kB" line of /proc/self/status, in bytes.
std::uint64_t status_kib_field(const std::string& text, const char* name) {
  const std::size_t at = text.find(std::string("\n") + name + ":");
  if (at == std::string::npos) return 0;
  return 1024u * std::strtoull(text.c_str() + at + std::char_traits<char>::length(name) + 2, nullptr, 10);
}

// Resets VmHWM to the current VmRSS (Linux >= 4.0). False where it cannot.
bool reset_peak() {
  const int fd = ::open("/proc/self/clear_refs", O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::write(fd, "5", 1) == 1;
  ::close(fd);
  return ok;
}

}  // namespace

ResidentMemory resident_memory() {
  std::ifstream in("/proc/self/status");
  if (!in) return {};
  const std::string text = "\n" + std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return {status_kib_field(text, "VmRSS"), status_kib_field(text, "VmHWM")};
}

std::uint64_t max_rss_bytes() {
  rusage u{};
  if (::getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return 1024u * static_cast<std::uint64_t>(u.ru_maxrss);  // kilobytes on Linux
}

std::uint64_t MemoryMeter::process_peak_bytes() {
  const ResidentMemory now = resident_memory();
  peak_seen_ = std::max({peak_seen_, now.hwm_bytes, now.rss_bytes, max_rss_bytes()});
  return peak_seen_;
}

void MemoryMeter::start() {
  process_peak_bytes();  // what the reset is about to wipe
  peak_reset_ = reset_peak();
  rss_before_ = resident_memory().rss_bytes;
}

RunMemory MemoryMeter::stop() {
  const ResidentMemory now = resident_memory();
  RunMemory m;
  m.rss_before_bytes = rss_before_;
  m.rss_after_bytes = now.rss_bytes;
  if (peak_reset_ && now.hwm_bytes > 0) m.peak_during_bytes = std::max(now.hwm_bytes, now.rss_bytes);
  peak_seen_ = std::max(peak_seen_, m.peak_during_bytes.value_or(0));
  m.process_peak_bytes = process_peak_bytes();
  return m;
}

}  // namespace sva::bench
