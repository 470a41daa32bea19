#pragma once
// Helpers shared by the test areas.
#include <cstdlib>
#include <filesystem>
#include <string>

namespace sva::test {

// A fresh, empty temporary directory for one test.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("sva-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Runs the sva CLI (path from SVA_BIN) with arguments; returns the exit code
// and captures stdout+stderr in `output`.
int run_sva(const std::string& arguments, std::string* output = nullptr);

// Ends the current test as skipped (ctest SKIP_RETURN_CODE 77) with a reason.
[[noreturn]] void skip(const std::string& reason);

}  // namespace sva::test
