#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <cstdlib>

#include "test_support.hpp"

namespace sva::test {

int run_sva(const std::string& arguments, std::string* output) {
  const char* bin = std::getenv("SVA_BIN");
  std::string cmd = std::string(bin ? bin : "sva") + " --quiet " + arguments + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return -1;
  std::string out;
  std::array<char, 4096> buf;
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  int status = ::pclose(p);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void skip(const std::string& reason) {
  std::fprintf(stderr, "SKIPPED: %s\n", reason.c_str());
  std::fflush(stderr);
  temp_dirs().remove();  // _Exit runs no destructors
  std::_Exit(77);
}

}  // namespace sva::test

namespace sva::test {

std::uint64_t scenario_seed(std::uint64_t base) {
  const char* s = std::getenv("SVA_TEST_SEED");
  if (!s || !*s) return base;
  char* end = nullptr;
  const unsigned long long k = std::strtoull(s, &end, 10);
  if (*end) {
    std::fprintf(stderr, "SVA_TEST_SEED=%s: not a non-negative integer\n", s);
    std::exit(2);
  }
  return base + 7919 * k;  // k = 0 is the checked-in seed
}

void margin(const std::string& statistic, double value, const char* relation, double threshold) {
  std::printf("margin: %s = %.6g (asserted %s %.6g)\n", statistic.c_str(), value, relation, threshold);
  std::fflush(stdout);
}

}  // namespace sva::test
