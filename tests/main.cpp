// Test main: the environment every test runs in is set here, not in ctest
// properties, so a test binary run by hand behaves exactly as under ctest.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

int main(int argc, char** argv) {
  // Software Vulkan (Mesa lavapipe) unless the caller chose a driver.
  const char* lvp = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
  if (std::filesystem::exists(lvp)) setenv("VK_DRIVER_FILES", lvp, 0);
    // Validation layer on: any validation message fails the GPU tests.
#ifdef SVA_TEST_VALIDATION
  setenv("SVA_VK_VALIDATION", "1", 0);
#endif
  setenv("SVA_BIN", SVA_TEST_SVA_BIN, 0);
  setenv("SVA_ASSETS", SVA_TEST_ASSETS, 0);
  return Catch::Session().run(argc, argv);
}
