// Disk faults at the one output helper every writer uses (host/io/include/sva/io/text_file.hpp): a full disk, a
// file-size limit, a read-only file system and a path under a regular file leave the previous file intact, no temporary
// file behind, and give an sva::Error naming the file and the system's reason. Tests run as root, where chmod stops no
// write: the faults that stop root are a file-size limit (RLIMIT_FSIZE, EFBIG; always available), a full or read-only
// file system (a small tmpfs, where the container may mount one) and a path through a regular file (ENOTDIR).
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <sys/resource.h>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <sva/io/binary_file.hpp>
#include <sva/io/text_file.hpp>
#include "test_support.hpp"

namespace {

std::string contents(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Only the target itself: no temporary file of a failed write is left beside it.
std::size_t entries(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

// Writes `bytes` bytes over `file`, which holds "previous", and checks that it fails cleanly with `reason`.
void check_failed_write_keeps_previous(const std::filesystem::path& file, std::size_t bytes,
                                       const std::string& reason) {
  REQUIRE(contents(file) == "previous");
  const std::size_t before = entries(file.parent_path());
  try {
    sva::io::write_text_file(file, std::string(bytes, 'x'));
    FAIL("a write of " << bytes << " bytes succeeded");
  } catch (const sva::Error& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find(file.string()) != std::string::npos);
    CHECK(what.find(reason) != std::string::npos);
    CHECK(what.find("left as it was") != std::string::npos);
  }
  CHECK(contents(file) == "previous");
  CHECK(entries(file.parent_path()) == before);
}

// Runs a shell command; true when it succeeded (mount and umount, where the container allows them).
bool shell(const std::string& command) { return std::system((command + " >/dev/null 2>&1").c_str()) == 0; }

}  // namespace

TEST_CASE("disk faults: a file-size limit (as a full disk) leaves the previous file intact and names the file") {
  const auto dir = sva::test::temp_dir("disk-fsize");
  const auto file = dir / "out.json";
  sva::io::write_text_file(file, "previous");
  std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead of killing the process
  rlimit old{};
  REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
  rlimit small = old;
  small.rlim_cur = 64 << 10;
  REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
  check_failed_write_keeps_previous(file, 1 << 20, "File too large");
  // A binary container (maps, datasets, sessions) goes through the same helper.
  sva::io::BinaryWriter w;
  w.put_vector(std::vector<double>(1 << 17, 1.0));
  CHECK_THROWS_WITH(w.write_file(file, "SVATEST1", 1), Catch::Contains(file.string()));
  CHECK(contents(file) == "previous");
  REQUIRE(setrlimit(RLIMIT_FSIZE, &old) == 0);
  std::signal(SIGXFSZ, SIG_DFL);
  std::filesystem::remove_all(dir);
}

TEST_CASE("disk faults: a path through a regular file is refused with the file named") {
  const auto dir = sva::test::temp_dir("disk-notdir");
  sva::io::write_text_file(dir / "plain", "previous");
  const auto file = dir / "plain" / "out.svam";
  CHECK_THROWS_WITH(sva::io::write_text_file(file, "data"),
                    Catch::Contains(file.string()) && Catch::Contains("Not a directory"));
  CHECK(contents(dir / "plain") == "previous");
  CHECK(entries(dir) == 1);
  std::filesystem::remove_all(dir);
}

TEST_CASE("disk faults: a full and a read-only file system leave the previous file intact (tmpfs)") {
  const auto dir = sva::test::temp_dir("disk-tmpfs");
  if (!shell("mount -t tmpfs -o size=256k sva-test " + dir.string()))
    sva::test::skip(
        "cannot mount a tmpfs here (needs root with CAP_SYS_ADMIN); the file-size limit test covers a "
        "full disk");
  struct Unmount {
    std::filesystem::path dir;
    ~Unmount() {
      shell("umount " + dir.string());
      std::filesystem::remove_all(dir);
    }
  } unmount{dir};
  const auto file = dir / "out.json";
  sva::io::write_text_file(file, "previous");
  check_failed_write_keeps_previous(file, 1 << 20, "No space left on device");
  REQUIRE(shell("mount -o remount,ro " + dir.string()));
  check_failed_write_keeps_previous(file, 16, "Read-only file system");
}
