#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include <sva/io/binary_file.hpp>
#include "recognition/session_file.hpp"
#include "test_support.hpp"

using namespace sva;

namespace {
Reading reading_at(double x, double time_s) {
  Reading r;
  r.position = {x, 2.0, 3.0};
  r.normal = {0.0, 1.0, 0.0};
  r.x_axis = {1.0, 0.0, 0.0};
  r.pressure = {1.0f, 2.5f, 0.0f, 4.0f};
  r.iterations = 7;
  r.time_s = time_s;
  return r;
}
}  // namespace

TEST_CASE("Session file: readings keep their time, and a version-1 file (object ids) still loads") {
  const auto dir = test::temp_dir("session-file");
  io::SessionFile s;
  s.scene_hash = 0x1234;
  s.objects = 3;
  s.scene_name = "unit";
  s.prior.object_probability = {0.2, 0.3, 0.5};
  s.prior.object_pose.resize(3);
  PosePrior seen{{10.0, -20.0, 30.0}, 4.0};
  seen.has_rotation = true;
  seen.rotation = glm::dmat3(0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
  seen.rotation_sigma_rad = 0.25;
  s.prior.object_pose[2] = seen;
  s.readings = {reading_at(1.0, 12.5), reading_at(-4.0, 13.25)};
  io::save_session_file(s, dir / "now.svas");
  const io::SessionFile back = io::load_session_file(dir / "now.svas");
  REQUIRE(back.readings.size() == 2);
  CHECK(back.readings[0].time_s == 12.5);
  CHECK(back.readings[1].time_s == 13.25);
  CHECK(back.readings[1].position == s.readings[1].position);
  CHECK(back.readings[0].pressure == s.readings[0].pressure);
  CHECK(back.prior.object_probability == s.prior.object_probability);
  REQUIRE(back.prior.object_pose.size() == 3);
  CHECK_FALSE(back.prior.object_pose[0].has_value());
  REQUIRE(back.prior.object_pose[2].has_value());
  CHECK(back.prior.object_pose[2]->position == seen.position);
  CHECK(back.prior.object_pose[2]->position_sigma_mm == 4.0);
  CHECK(back.prior.object_pose[2]->has_rotation);
  CHECK(back.prior.object_pose[2]->rotation == seen.rotation);
  CHECK(back.prior.object_pose[2]->rotation_sigma_rad == 0.25);

  // Version 1 stored the dataset's object id where the time now is: read, the id is skipped and the time unknown.
  io::BinaryWriter w;
  w.put<std::uint64_t>(0x1234);
  w.put<std::uint32_t>(3);
  w.put_string("unit");
  w.put_vector(std::vector<double>{});
  w.put<std::uint64_t>(1);
  const Reading r = reading_at(5.0, 0.0);
  for (const glm::dvec3& v : {r.position, r.normal, r.x_axis}) w.put_array(&v.x, 3);
  w.put<std::uint8_t>(0);
  w.put<std::uint16_t>(r.iterations);
  w.put<std::uint32_t>(2);  // the object id of version 1
  w.put_vector(r.pressure);
  w.write_file(dir / "v1.svas", "SVASESS1", 1);
  const io::SessionFile v1 = io::load_session_file(dir / "v1.svas");
  REQUIRE(v1.readings.size() == 1);
  CHECK(v1.readings[0].position == r.position);
  CHECK(v1.readings[0].pressure == r.pressure);
  CHECK(v1.readings[0].time_s == 0.0);
  CHECK(v1.prior.object_pose.empty());

  // Pose priors for another object count are refused before anything is read past them.
  s.prior.object_pose.resize(2);
  io::save_session_file(s, dir / "count.svas");
  CHECK_THROWS_WITH(io::load_session_file(dir / "count.svas"),
                    Catch::Contains("count.svas") && Catch::Contains("2 pose priors for 3 objects"));
  s.prior.object_pose.resize(3);

  // A non-finite time is refused with the file's name.
  s.readings[0].time_s = std::numeric_limits<double>::quiet_NaN();
  io::save_session_file(s, dir / "nan.svas");
  CHECK_THROWS_WITH(io::load_session_file(dir / "nan.svas"), Catch::Contains("nan.svas") && Catch::Contains("time"));
  std::filesystem::remove_all(dir);
}
