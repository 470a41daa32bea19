#pragma once
// Helpers shared by the test areas.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace sva::test {

// The temporary directories this test process made, removed when it exits (ctest runs one test case per process)
// unless SVA_KEEP_TEST_DIRS is set, to look at what a failing test wrote: a suite run leaves /tmp as it found it.
class TempDirs {
 public:
  ~TempDirs() { remove(); }
  void remove() {
    if (std::getenv("SVA_KEEP_TEST_DIRS")) return;
    std::error_code ec;
    for (const auto& d : dirs_) std::filesystem::remove_all(d, ec);
    dirs_.clear();
  }
  void add(const std::filesystem::path& d) { dirs_.push_back(d); }

 private:
  std::vector<std::filesystem::path> dirs_;
};

inline TempDirs& temp_dirs() {
  static TempDirs dirs;
  return dirs;
}

// A fresh, empty temporary directory for one test (removed when the test process exits).
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("sva-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  temp_dirs().add(dir);
  return dir;
}

// An environment variable set for one scope (SVA_THREADS for a test that runs a path on one thread and on two), put
// back as it was when the scope ends.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* v = std::getenv(name)) had_ = true, before_ = v;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() { had_ ? ::setenv(name_.c_str(), before_.c_str(), 1) : ::unsetenv(name_.c_str()); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_, before_;
  bool had_ = false;
};

// Runs the sva CLI (path from SVA_BIN) with arguments; returns the exit code
// and captures stdout+stderr in `output`.
int run_sva(const std::string& arguments, std::string* output = nullptr);

// Statistical tests (docs/reliability.md, "Margins"). A scenario draws its seeds through scenario_seed, which
// SVA_TEST_SEED=k moves to another stream (0 or unset: the checked-in seed), so that bench/reliability/test_margins.py
// can run the same scenario at several seeds. margin() prints the statistic beside its threshold as one "margin:" line,
// which that bench collects; the test still asserts the threshold itself.
std::uint64_t scenario_seed(std::uint64_t base);
void margin(const std::string& statistic, double value, const char* relation, double threshold);

// Ends the current test as skipped (ctest SKIP_RETURN_CODE 77) with a reason.
[[noreturn]] void skip(const std::string& reason);

}  // namespace sva::test
