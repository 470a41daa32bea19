// glTF 2.0 meshes, .gltf and .glb (sim/src/mesh.cpp: tinygltf's parse, then the loader's validation).
#include <sva/error.hpp>
#include <sva/sim/mesh.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)sva::sim::load_mesh(sva::fuzz::write_input({data, size}, "input.glb"));
  } catch (const sva::Error&) {
  }
  return 0;
}
