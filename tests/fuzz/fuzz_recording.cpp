// Session recordings, .svar (host/io/src/recording_file.cpp read by drivers/src/session.cpp: the records and
// their payloads: settings JSON, raw chunks, pose lines, readings, notes). Every record's checksum is repaired
// unless bit 0 of the header's reserved field is set.
#include <sva/drivers/session.hpp>
#include <sva/error.hpp>

#include "fuzz_support.hpp"

namespace {
std::vector<std::uint8_t> repair_records(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kHeader = 16, kRecordHeader = 8, kTrailer = 8;
  std::vector<std::uint8_t> b(data, data + size);
  if (b.size() < kHeader || (b[12] & 1)) return b;
  std::memcpy(b.data(), "SVAREC\r\n", 8);
  std::size_t at = kHeader;
  while (b.size() - at >= kRecordHeader + kTrailer) {
    std::uint32_t n;
    std::memcpy(&n, b.data() + at + 4, 4);
    if (n > b.size() - at - kRecordHeader - kTrailer) break;
    const std::uint64_t sum = sva::io::fnv1a64(b.data() + at, kRecordHeader + n);
    std::memcpy(b.data() + at + kRecordHeader + n, &sum, 8);
    at += kRecordHeader + n + kTrailer;
  }
  return b;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = repair_records(data, size);
  try {
    (void)sva::drivers::load_session(sva::fuzz::write_input(bytes, "input.svar"));
  } catch (const sva::Error&) {
  }
  return 0;
}
