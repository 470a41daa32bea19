// Map files (host/src/map/map_file.cpp, docs/map-format.md); the container's checksum is repaired.
#include <sva/error.hpp>

#include "fuzz_support.hpp"
#include "map/map_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = sva::fuzz::repair_container({data, size}, sva::kMapMagic);
  try {
    (void)sva::load_pair_map(sva::fuzz::write_input(bytes, "input.svam"));
  } catch (const sva::Error&) {
  }
  return 0;
}
