// Scene JSON (host/src/scene/scene.cpp, docs/scene-format.md).
#include <sva/error.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const sva::Scene s = sva::parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz/scene.json");
    (void)sva::scene_to_json(s);  // a scene that parses also writes
  } catch (const sva::Error&) {
  }
  return 0;
}
