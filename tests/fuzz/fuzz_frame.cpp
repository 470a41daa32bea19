// One tactile frame, as the sensor sends it (drivers/src/frame.cpp, docs/usb-sensor.md). A frame that parses must
// encode back to the same bytes.
#include <sva/drivers/frame.hpp>
#include <sva/error.hpp>

#include <cstdlib>
#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto f = sva::drivers::parse_frame({data, size});
    const auto again = sva::drivers::encode_frame(f);
    if (again.size() != size || std::memcmp(again.data(), data, size) != 0) std::abort();
  } catch (const sva::Error&) {
  }
  return 0;
}
