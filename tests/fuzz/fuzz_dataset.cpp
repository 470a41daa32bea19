// Dataset files (host/src/dataset/dataset.cpp, docs/file-formats.md); the container's checksum is repaired.
#include <sva/dataset.hpp>
#include <sva/error.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = sva::fuzz::repair_container({data, size}, "SVADATA1");
  try {
    (void)sva::load_dataset(sva::fuzz::write_input(bytes, "input.svad"));
  } catch (const sva::Error&) {
  }
  return 0;
}
