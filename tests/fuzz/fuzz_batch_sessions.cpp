// Batch sessions files (host/src/recognition/batch_sessions.cpp, docs/batch-format.md): JSON Lines of readings.
#include <sva/error.hpp>

#include <cstdint>
#include <string_view>

#include "recognition/batch_sessions.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    // The corpus is written for a 6 x 6 sensor (the built-in scenes'); a few other sizes are reachable too.
    const int elements = size > 0 && data[0] == '#' ? 4 : 36;
    (void)sva::batch::parse_sessions(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz/sessions.jsonl",
                                     1, 0, elements);
  } catch (const sva::Error&) {
  }
  return 0;
}
