// tinygltf's implementation, compiled with the harnesses' sanitizers and coverage so that the fuzzer sees into
// the glTF container parser too (the normal build links Debian's libtinygltf instead).
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
