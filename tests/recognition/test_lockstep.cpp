// The lock-step loop (recognition/lockstep.hpp): groups of sessions step together, and each hook runs where its
// comment says: a group's readings are asked for, the batch reset, the group started (a session's prior goes there,
// after the reset that would forget it), its updates made, the group ended.
#include <catch2/catch.hpp>

#include <sva/reading.hpp>

#include <string>
#include <vector>

#include "recognition/lockstep.hpp"

using namespace sva;

namespace {

// Sessions that record what happens to them, in order.
class RecordedSessions final : public LockstepSessions {
 public:
  RecordedSessions(std::size_t size, std::vector<std::string>* log) : size_(size), log_(log) {}
  std::size_t size() const override { return size_; }
  void add_readings(std::span<const std::size_t> sessions, std::span<const Reading> readings) override {
    REQUIRE(sessions.size() == readings.size());
    log_->push_back("update " + std::to_string(sessions.size()));
  }
  void reset() override { log_->push_back("reset"); }

 private:
  std::size_t size_;
  std::vector<std::string>* log_;
};

}  // namespace

TEST_CASE("lockstep: a group is started after its reset and before its first update") {
  std::vector<std::string> log;
  RecordedSessions batch(2, &log);
  // Five sessions in groups of two: the last group has one. Session s has s % 3 + 1 readings.
  std::vector<std::vector<Reading>> readings(5);
  for (std::size_t s = 0; s < readings.size(); ++s) readings[s].resize(s % 3 + 1);
  LockstepHooks hooks;
  hooks.group = [&](std::size_t first, std::size_t count) {
    log.push_back("group " + std::to_string(first) + "+" + std::to_string(count));
    std::vector<std::span<const Reading>> out;
    for (std::size_t i = 0; i < count; ++i) out.emplace_back(readings[first + i]);
    return out;
  };
  hooks.on_group_start = [&](std::size_t first, std::size_t count) {
    log.push_back("start " + std::to_string(first) + "+" + std::to_string(count));
  };
  hooks.on_step = [&](const LockstepStep& s) { log.push_back("step " + std::to_string(s.step)); };
  hooks.on_group_end = [&](std::size_t first, std::size_t) { log.push_back("end " + std::to_string(first)); };
  run_lockstep(batch, readings.size(), hooks);
  const std::vector<std::string> want{
      "group 0+2", "reset",     "start 0+2", "update 2", "step 0",   "update 1", "step 1",   "end 0",  "group 2+2",
      "reset",     "start 2+2", "update 2",  "step 0",   "update 1", "step 1",   "update 1", "step 2", "end 2",
      "group 4+1", "reset",     "start 4+1", "update 1", "step 0",   "update 1", "step 1",   "end 4"};
  CHECK(log == want);
}

TEST_CASE("lockstep: without a start hook, the loop runs as before") {
  std::vector<std::string> log;
  RecordedSessions batch(3, &log);
  std::vector<std::vector<Reading>> readings(2, std::vector<Reading>(2));
  LockstepHooks hooks;
  hooks.group = [&](std::size_t first, std::size_t count) {
    std::vector<std::span<const Reading>> out;
    for (std::size_t i = 0; i < count; ++i) out.emplace_back(readings[first + i]);
    return out;
  };
  run_lockstep(batch, readings.size(), hooks);
  CHECK(log == std::vector<std::string>{"reset", "update 2", "update 2"});
}
