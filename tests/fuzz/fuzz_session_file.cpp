// Saved recognizer sessions (host/src/recognition/session_file.cpp); the container's checksum is repaired.
#include <sva/error.hpp>

#include "fuzz_support.hpp"
#include "recognition/session_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = sva::fuzz::repair_container({data, size}, "SVASESS1");
  try {
    (void)sva::io::load_session_file(sva::fuzz::write_input(bytes, "input.svas"));
  } catch (const sva::Error&) {
  }
  return 0;
}
