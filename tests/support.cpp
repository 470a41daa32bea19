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
