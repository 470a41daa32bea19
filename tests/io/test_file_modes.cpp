// The mode of the files sva writes (host/io/include/sva/io/text_file.hpp, the one helper every writer uses): a map,
// a results file or a figure is meant to be shared, so it gets what any new file of the user's gets, 0666 less the
// umask, not a temporary file's 0600. The Python package's writers are held to the same (python/tests).
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <filesystem>
#include <vector>

#include <sva/io/binary_file.hpp>
#include <sva/io/text_file.hpp>
#include "test_support.hpp"

namespace {

// The umask for one scope (it is the process's: the tests of an area run one at a time).
class Umask {
 public:
  explicit Umask(mode_t mask) : previous_(::umask(mask)) {}
  ~Umask() { ::umask(previous_); }
  Umask(const Umask&) = delete;
  Umask& operator=(const Umask&) = delete;

 private:
  mode_t previous_;
};

unsigned mode_of(const std::filesystem::path& file) {
  struct stat st {};
  REQUIRE(::stat(file.c_str(), &st) == 0);
  return st.st_mode & 07777u;
}

}  // namespace

TEST_CASE("files written take the user's umask: 0644 under 022, 0600 under 077, also when replacing one") {
  const auto dir = sva::test::temp_dir("file-modes");
  struct Case {
    mode_t mask;
    unsigned mode;
    const char* name;
  };
  for (const Case& c : {Case{022, 0644u, "022"}, Case{077, 0600u, "077"}, Case{002, 0664u, "002"}}) {
    INFO("umask " << c.name);
    const Umask scope(c.mask);
    const auto text = dir / c.name / "results.jsonl";
    sva::io::write_text_file(text, "{}\n");  // the folder made on the way
    CHECK(mode_of(text) == c.mode);
    sva::io::BinaryWriter w;
    w.put_vector(std::vector<double>(4, 1.0));
    w.write_file(dir / c.name / "map.svam", "SVATEST1", 1);
    CHECK(mode_of(dir / c.name / "map.svam") == c.mode);
  }
  // A file replaced by a later write gets the umask of that write (the temporary file's mode, renamed into place).
  {
    const Umask scope(077);
    sva::io::write_text_file(dir / "shared.txt", "a");
  }
  const Umask scope(022);
  sva::io::write_text_file(dir / "shared.txt", "b");
  CHECK(mode_of(dir / "shared.txt") == 0644u);
  std::filesystem::remove_all(dir);
}
