// Batch recognition of a sessions file (<sva/batch_file.hpp>), streamed a group at a time (sva recognize), against
// the whole file in memory and against shards of it (the path of sva.recognize_batch and sva.distributed): the same
// result lines, and a bad line refused up front.
#include <catch2/catch.hpp>

#include <sva/batch_file.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "recognition/batch_sessions.hpp"
#include "recognition/fixture.hpp"
#include "recognition/trained_map.hpp"
#include "test_support.hpp"

using namespace sva;
using namespace sva::test;

namespace {

std::vector<Reading> readings_of(std::uint32_t object, std::uint64_t seed, int count) {
  return readings_at(object, random_pose(seed, 100.0), util::Rng(seed, 9), count);
}

// Seven sessions of 2 to 5 readings, written by the project's writer, with blank lines between some of them, one
// session without an id (numbered by its place in the file) and one with a truth.
std::filesystem::path sessions_file(const std::filesystem::path& dir) {
  std::vector<BatchSession> sessions(7);
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    sessions[i].id = "s" + std::to_string(i);
    sessions[i].readings = readings_of(static_cast<std::uint32_t>(i % 3), 900 + i, 2 + static_cast<int>(i % 4));
  }
  sessions[2].truth = R"({"object":"b","note":[1,2.5]})";
  const auto file = dir / "sessions.jsonl";
  write_batch_sessions(file, sessions);
  std::ifstream in(file);
  std::string text, line;
  for (int n = 0; std::getline(in, line); ++n) {
    if (n == 4) line.replace(line.find("\"id\":\"s4\","), 10, "");  // no id: numbered 4
    text += line + "\n" + (n % 3 == 1 ? "\n  \n" : "");
  }
  std::ofstream(file) << text;
  return file;
}

std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST_CASE("Batch recognition: light estimates at the sessions' ends are each session's light estimate") {
  const Trained& t = trained();
  const auto dir = temp_dir("batch-light");
  std::vector<BatchSession> sessions(3);  // 7 readings: past the fine pose's first, where the depths differ
  for (std::size_t i = 0; i < sessions.size(); ++i) {
    sessions[i].id = "s" + std::to_string(i);
    sessions[i].readings = readings_of(static_cast<std::uint32_t>(i), 700 + i, 7);
  }
  write_batch_sessions(dir / "sessions.jsonl", sessions);
  const BatchSessionsFile file(dir / "sessions.jsonl", t.data.scene.sensor.elements());
  BatchRecognizer rec(t.map, paper_space(), 2);
  file.recognize(rec, t.map, dir / "light.jsonl", 3, false, EstimateDepth::light);
  file.recognize(rec, t.map, dir / "full.jsonl", 3);
  // Each session's light estimate, alone on a recognizer of its own.
  std::vector<Estimate> alone;
  for (const BatchSession& s : sessions) {
    BatchRecognizer one(t.map, paper_space(), 1);
    const std::size_t id = 0;
    for (const Reading& r : s.readings) one.add_readings(std::span(&id, 1), std::span(&r, 1));
    alone.push_back(one.estimate(0, 3, EstimateDepth::light));
    CHECK_FALSE(alone.back().pose_refined);
  }
  CHECK(read_all(dir / "light.jsonl") == batch::format_results(sessions, alone, t.map.object_names()));
  CHECK(read_all(dir / "light.jsonl") != read_all(dir / "full.jsonl"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("Batch recognition: a streamed file gives the whole file's result lines, for any group size and shards") {
  const Trained& t = trained();
  const auto dir = temp_dir("batch-stream");
  const auto file = sessions_file(dir);
  const int elements = t.data.scene.sensor.elements();
  const auto all = read_batch_sessions(file, elements);
  REQUIRE(all.size() == 7);
  CHECK(all[4].id == "4");
  CHECK(all[2].truth == R"({"note":[1,2.5],"object":"b"})");  // any JSON, kept as text
  BatchRecognizer whole(t.map, paper_space(), 7);
  const std::string expected = batch::format_results(
      all, batch::recognize_sessions(std::span(&whole, 1), all, {.top_k = 3}, file.string()), t.map.object_names());
  CHECK(expected.find(R"("truth":{"note":[1,2.5],"object":"b"})") != std::string::npos);

  const BatchSessionsFile checked(file, elements);
  CHECK(checked.sessions() == 7);
  std::size_t readings = 0;
  for (const auto& s : all) readings += s.readings.size();
  CHECK(checked.readings() == readings);
  for (std::size_t group : {1, 3, 7}) {
    INFO("group of " << group);
    BatchRecognizer rec(t.map, paper_space(), group);
    checked.recognize(rec, t.map, dir / "results.jsonl", 3);
    CHECK(read_all(dir / "results.jsonl") == expected);
  }
  // Groups in flight on two and three recognizers of one engine at once (a GPU's double buffering): the file is
  // read and its results written in group order, the same bytes.
  const Engine engine(t.map);
  for (std::size_t in_flight : {2, 3}) {
    INFO(in_flight << " recognizers, groups of 2");
    std::vector<BatchRecognizer> recs = batch_recognizers(engine, all.size(), 2, in_flight);
    REQUIRE(recs.size() == in_flight);
    checked.recognize(recs, t.map, dir / "results.jsonl", 3);
    CHECK(read_all(dir / "results.jsonl") == expected);
    CHECK(batch::format_results(all, batch::recognize_sessions(recs, all, {.top_k = 3}, file.string()),
                                t.map.object_names()) == expected);
  }
  // Recognizers that cannot share a batch are refused by name, before any recognition.
  std::vector<BatchRecognizer> uneven;
  uneven.emplace_back(engine, paper_space(), 7);
  uneven.emplace_back(engine, paper_space(), 3);
  CHECK_THROWS_WITH(checked.recognize(uneven, t.map, dir / "results.jsonl", 3),
                    Catch::Contains("recognizer 1 of 2 steps 3 sessions, the first 7"));
  CHECK(read_all(dir / "results.jsonl") == expected);  // the earlier results file is untouched
  // Two shards cut at a line boundary (lines 1-5 hold sessions 0-2): their lines concatenated are the whole file's.
  const std::string text = read_all(file);
  std::size_t cut = 0;
  for (int n = 0; n < 5; ++n) cut = text.find('\n', cut) + 1;
  BatchRecognizer shard_rec(t.map, paper_space(), 2);
  const std::string first = recognize_batch_shard(shard_rec, t.map, text.substr(0, cut), file.string(), 1, 0, 3);
  const std::string second = recognize_batch_shard(shard_rec, t.map, text.substr(cut), file.string(), 6, 3, 3);
  CHECK(first + second == expected);
  CHECK_THROWS_WITH(recognize_batch_shard(shard_rec, t.map, "{\"readings\": 1}\n", "part.jsonl", 40, 9, 3),
                    Catch::Contains("part.jsonl:40") && Catch::Contains("\"readings\""));
  std::filesystem::remove_all(dir);
}

TEST_CASE("Batch recognition: a batch's recognizers, one per group in flight, no more than its groups") {
  const Engine engine(trained().map);
  const auto sizes = [](const std::vector<BatchRecognizer>& recs) {
    std::vector<std::size_t> out;
    for (const BatchRecognizer& r : recs) out.push_back(r.sessions());
    return out;
  };
  CHECK(sizes(batch_recognizers(engine, 30, 8, 3)) == std::vector<std::size_t>{8, 8, 8});
  CHECK(sizes(batch_recognizers(engine, 12, 8, 3)) == std::vector<std::size_t>{8, 8});  // two groups
  CHECK(sizes(batch_recognizers(engine, 5, 8, 2)) == std::vector<std::size_t>{5});      // one group, smaller
  CHECK_THROWS_WITH(batch_recognizers(engine, 5, 8, 0), Catch::Contains("groups in flight must be >= 1"));
  CHECK_THROWS_WITH(batch_recognizers(engine, 0, 8, 1), Catch::Contains("have 0, 8, 1"));
}

TEST_CASE("Batch recognition: the check refuses a bad line anywhere, naming it, and a file without sessions") {
  const Trained& t = trained();
  const auto dir = temp_dir("batch-scan");
  const auto file = sessions_file(dir);
  std::ofstream(file, std::ios::app) << "{\"id\": \"last\", \"readings\": []}\n";
  const int elements = t.data.scene.sensor.elements();
  CHECK_THROWS_WITH(BatchSessionsFile(file, elements),
                    Catch::Contains("sessions.jsonl:12") && Catch::Contains("non-empty"));
  // The reader gives what is good up to the bad line, then the same error.
  batch::SessionReader reader(file.string(), elements);
  CHECK(reader.next(5).size() == 5);
  CHECK(reader.next(2).size() == 2);
  CHECK_THROWS_WITH(reader.next(1), Catch::Contains("sessions.jsonl:12"));
  std::ofstream(dir / "blank.jsonl") << "\n  \n";
  CHECK_THROWS_WITH(BatchSessionsFile(dir / "blank.jsonl", elements),
                    Catch::Contains("blank.jsonl") && Catch::Contains("no sessions"));
  CHECK_THROWS_WITH(read_batch_sessions(dir / "blank.jsonl", elements),
                    Catch::Contains("blank.jsonl") && Catch::Contains("no sessions"));
  CHECK_THROWS_WITH(BatchSessionsFile(dir / "none.jsonl", elements), Catch::Contains("none.jsonl"));
  // A caller's session whose truth is not JSON is refused by the writer, naming the session.
  BatchSession odd{"odd", readings_of(0, 5, 1), "{not json"};
  CHECK_THROWS_WITH(write_batch_sessions(dir / "odd.jsonl", std::span<const BatchSession>(&odd, 1)),
                    Catch::Contains("\"odd\"") && Catch::Contains("not JSON"));
  CHECK_FALSE(std::filesystem::exists(dir / "odd.jsonl"));
  std::filesystem::remove_all(dir);
}
