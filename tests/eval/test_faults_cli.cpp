// Interrupts and disk faults through the CLI, on the tiny scene simulated once per process: Ctrl-C (SIGINT) and
// SIGTERM during `sva train`, `sva recognize --batch` and `sva bench` exit with 130 and leave no output, partial or
// temporary; an output on a full disk (a file-size limit) or through a regular file fails with the file named and
// leaves the previous file as it was. (`sva eval` and `sva simulate` have their own interrupt tests.)
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using Catch::Contains;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The tiny scene simulated and trained once: a map, a test set, and a sessions file of many long sessions.
struct Tiny {
  fs::path dir = sva::test::temp_dir("faults-cli");
  fs::path map = dir / "map.svam", train = dir / "train.svad", test = dir / "test.svad",
           sessions = dir / "sessions.jsonl";
  Tiny() {
    std::string out;
    const std::string d = dir.string();
    if (sva::test::run_sva("simulate --scene tiny --train 1500 --test 40 --seed 3 --out " + d, &out) != 0) FAIL(out);
    if (sva::test::run_sva("train --data " + train.string() + " --out " + map.string(), &out) != 0) FAIL(out);
    if (sva::test::run_sva("recognize --write-sessions " + sessions.string() + " --map " + map.string() + " --data " +
                               test.string() + " --trials 400 --max-readings 60",
                           &out) != 0)
      FAIL(out);
  }
};

const Tiny& tiny() {
  static const Tiny t;
  return t;
}

// Runs sva with `args`, sends `signal` after `after`, and returns its exit status (or 128 + a killing signal).
int interrupted_run(const std::vector<std::string>& args, int signal, std::chrono::milliseconds after,
                    const fs::path& log) {
  const char* bin = std::getenv("SVA_BIN");
  REQUIRE(bin);
  std::vector<std::string> all{bin, "--quiet"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
    }
    ::execv(bin, argv.data());
    std::_Exit(127);
  }
  std::this_thread::sleep_for(after);
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Nothing named after the output (the output itself or its temporary file) is in `dir`.
void check_no_output(const fs::path& dir, const std::string& stem) {
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename().string().find(stem) == std::string::npos);
}

void check_stopped_cleanly(int status, const fs::path& log) {
  INFO(slurp(log));
  CHECK(status == 130);
  // Stopped by the CLI's handler (a kill by the signal would read 130 too, without the message).
  CHECK_THAT(slurp(log), Contains("interrupted; no partial output was kept"));
}

}  // namespace

TEST_CASE("interrupts: sva train stops on Ctrl-C with no map written") {
  const Tiny& t = tiny();
  // 3,000 readings and many clusters: the clustering runs for seconds (about 3 s alone on one core).
  const int status = interrupted_run({"train", "--data", t.train.string(), "--out", (t.dir / "never.svam").string(),
                                      "--clusters", "400", "--threads", "1"},
                                     SIGINT, std::chrono::milliseconds(1000), t.dir / "train.log");
  check_stopped_cleanly(status, t.dir / "train.log");
  check_no_output(t.dir, "never");
}

TEST_CASE("interrupts: sva recognize --batch stops on SIGTERM with no results written") {
  const Tiny& t = tiny();
  const int status = interrupted_run({"recognize", "--map", t.map.string(), "--batch", t.sessions.string(), "--out",
                                      (t.dir / "never.jsonl").string(), "--backend", "cpu"},
                                     SIGTERM, std::chrono::milliseconds(1500), t.dir / "recognize.log");
  check_stopped_cleanly(status, t.dir / "recognize.log");
  check_no_output(t.dir, "never");
}

TEST_CASE("interrupts: sva bench stops on Ctrl-C and on SIGTERM with no figures written") {
  const Tiny& t = tiny();
  for (int signal : {SIGINT, SIGTERM}) {
    INFO("signal " << signal);
    const int status =
        interrupted_run({"bench", "--map", t.map.string(), "--data", t.test.string(), "--backend", "cpu", "--readings",
                         "10,30,1000", "--trials", "50", "--json", (t.dir / "never.json").string()},
                        signal, std::chrono::milliseconds(1500), t.dir / "bench.log");
    check_stopped_cleanly(status, t.dir / "bench.log");
    check_no_output(t.dir, "never");
  }
}

TEST_CASE("disk faults: sva train onto a full disk keeps the previous map and names the file") {
  const Tiny& t = tiny();
  const fs::path target = t.dir / "full.svam";
  { std::ofstream(target) << "previous"; }
  // bash's ulimit -f (1024-byte blocks) stands in for a full disk: writes past it fail with EFBIG, for root too.
  const char* bin = std::getenv("SVA_BIN");
  REQUIRE(bin);
  const std::string cmd = "bash -c \"trap '' XFSZ; ulimit -f 64; exec '" + std::string(bin) +
                          "' --quiet train --data '" + t.train.string() + "' --out '" + target.string() + "'\" > '" +
                          (t.dir / "full.log").string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  INFO(slurp(t.dir / "full.log"));
  CHECK(WEXITSTATUS(status) != 0);
  CHECK(WEXITSTATUS(status) < 128);
  CHECK_THAT(slurp(t.dir / "full.log"), Contains(target.string()) && Contains("File too large"));
  CHECK(slurp(target) == "previous");
  check_no_output(t.dir, "full.svam.tmp");
}

TEST_CASE("disk faults: outputs through a regular file fail with the file named") {
  const Tiny& t = tiny();
  { std::ofstream(t.dir / "plain") << "previous"; }
  const fs::path under = t.dir / "plain";
  std::string out;
  CHECK(sva::test::run_sva("train --data " + t.train.string() + " --out " + (under / "m.svam").string(), &out) != 0);
  CHECK_THAT(out, Contains((under / "m.svam").string()) && Contains("Not a directory"));
  CHECK(sva::test::run_sva("eval --map " + t.map.string() + " --data " + t.test.string() +
                               " --trials 2 --max-readings 3 --backend cpu --plot " + (under / "e.png").string(),
                           &out) != 0);
  CHECK_THAT(out, Contains((under / "e.png").string()));  // refused before the trials run
  CHECK(slurp(under) == "previous");
}
