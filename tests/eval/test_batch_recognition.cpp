// Batch recognition of a sessions file, streamed a group at a time (sva recognize), against the whole file in
// memory (the path of the Python package's shards): the same result lines, and a bad line refused up front.
#include <catch2/catch.hpp>

#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <sva/eval/batch_recognition.hpp>
#include <sva/eval/batch_sessions.hpp>
#include "recognition/fixture.hpp"
#include "recognition/trained_map.hpp"
#include "test_support.hpp"

using namespace sva;
using namespace sva::test;

namespace {

std::vector<Reading> readings_of(std::uint32_t object, std::uint64_t seed, int count) {
  return readings_at(object, random_pose(seed, 100.0), util::Rng(seed, 9), count);
}

// Seven sessions of 2 to 5 readings, written by the project's writer, with blank lines between some of them and
// one session without an id (numbered by its place in the file).
std::filesystem::path sessions_file(const std::filesystem::path& dir) {
  std::vector<io::BatchSession> sessions(7);
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    sessions[i].id = "s" + std::to_string(i);
    sessions[i].readings = readings_of(static_cast<std::uint32_t>(i % 3), 900 + i, 2 + static_cast<int>(i % 4));
  }
  const auto file = dir / "sessions.jsonl";
  io::write_batch_sessions(file.string(), sessions);
  std::ifstream in(file);
  std::string text, line;
  for (int n = 0; std::getline(in, line); ++n) {
    if (n == 4) line.replace(line.find("\"id\":\"s4\","), 10, "");  // no id: numbered 4
    text += line + "\n" + (n % 3 == 1 ? "\n  \n" : "");
  }
  std::ofstream(file) << text;
  return file;
}

}  // namespace

TEST_CASE("Batch recognition: a streamed file gives the whole file's result lines, for any group size") {
  const Trained& t = trained();
  const auto dir = temp_dir("batch-stream");
  const auto file = sessions_file(dir);
  const int elements = t.data.scene.sensor.elements();
  const auto all = io::read_batch_sessions(file.string(), elements);
  REQUIRE(all.size() == 7);
  CHECK(all[4].id == "4");
  BatchRecognizer whole(t.map, paper_space(), 7);
  const std::string expected =
      io::format_batch_results(all, batch::recognize_sessions(whole, all, 3, file.string()), t.map.object_names());

  const io::BatchSessionsSummary sum = io::scan_batch_sessions(file.string(), elements);
  CHECK(sum.sessions == 7);
  std::size_t readings = 0;
  for (const auto& s : all) readings += s.readings.size();
  CHECK(sum.readings == readings);
  for (std::size_t group : {1, 3, 7}) {
    INFO("group of " << group);
    BatchRecognizer rec(t.map, paper_space(), group);
    std::ostringstream out;
    CHECK(batch::recognize_file(rec, t.map, file.string(), sum.sessions, out, 3) == 7);
    CHECK(out.str() == expected);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("Batch recognition: the scan refuses a bad line anywhere, naming it, and a file without sessions") {
  const Trained& t = trained();
  const auto dir = temp_dir("batch-scan");
  const auto file = sessions_file(dir);
  std::ofstream(file, std::ios::app) << "{\"id\": \"last\", \"readings\": []}\n";
  const int elements = t.data.scene.sensor.elements();
  CHECK_THROWS_WITH(io::scan_batch_sessions(file.string(), elements),
                    Catch::Contains("sessions.jsonl:12") && Catch::Contains("non-empty"));
  // The reader gives what is good up to the bad line, then the same error.
  io::BatchSessionReader reader(file.string(), elements);
  CHECK(reader.next(5).size() == 5);
  CHECK(reader.next(2).size() == 2);
  CHECK_THROWS_WITH(reader.next(1), Catch::Contains("sessions.jsonl:12"));
  std::ofstream(dir / "blank.jsonl") << "\n  \n";
  CHECK_THROWS_WITH(io::scan_batch_sessions((dir / "blank.jsonl").string(), elements),
                    Catch::Contains("blank.jsonl") && Catch::Contains("no sessions"));
  CHECK_THROWS_WITH(io::BatchSessionReader((dir / "none.jsonl").string(), elements), Catch::Contains("none.jsonl"));
  std::filesystem::remove_all(dir);
}
