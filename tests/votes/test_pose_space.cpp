// Pose-space validation and bin-key packing.
#include <catch2/catch.hpp>

#include <sva/error.hpp>

#include "recognition/fixture.hpp"

using namespace sva;
using namespace sva::test;

TEST_CASE("pose space refuses specs that do not fit the bin key") {
  PoseSpaceSpec s = paper_space();
  CHECK_NOTHROW(PoseSpace(s, 255));
  CHECK_THROWS_AS(PoseSpace(s, 256), Error);
  CHECK_THROWS_AS(PoseSpace(s, 0), Error);
  s.translation_bins = 1025;
  CHECK_THROWS_WITH(PoseSpace(s, 3), Catch::Contains("translation_bins"));
  s = paper_space();
  s.rotation_bins = 257;
  CHECK_THROWS_WITH(PoseSpace(s, 3), Catch::Contains("rotation_bins"));
  s = paper_space();
  s.rotation_bins = 0;
  CHECK_THROWS_AS(PoseSpace(s, 3), Error);
  s = paper_space();
  s.translation_min_mm = 10.0;
  s.translation_max_mm = 10.0;  // empty pose space
  CHECK_THROWS_WITH(PoseSpace(s, 3), Catch::Contains("empty"));
  s.translation_max_mm = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(PoseSpace(s, 3), Error);
}

TEST_CASE("pose space refuses a workspace frame that is not rigid, or that tilts a planar space") {
  PoseSpaceSpec s = placed_pose_space(paper_space(), {500.0, 0.0, 0.0}, 100.0, so3::exp({0.0, 0.4, 0.0}));
  CHECK_NOTHROW(PoseSpace(s, 3));
  CHECK(PoseSpace(s, 3).to_robot(RigidPose{}).T.x == 500.0);
  s.workspace.R = 2.0 * s.workspace.R;  // a scale
  CHECK_THROWS_WITH(PoseSpace(s, 3), Catch::Contains("workspace rotation"));
  s.workspace.R = glm::dmat3(1.0);
  s.workspace.R[0][0] = -1.0;  // a mirror
  CHECK_THROWS_WITH(PoseSpace(s, 3), Catch::Contains("workspace rotation"));
  s.workspace.R = glm::dmat3(1.0);
  s.workspace.T.y = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(PoseSpace(s, 3), Catch::Contains("workspace centre"));
  PoseSpaceSpec planar = placed_pose_space(letters_space(), {30.0, 40.0, 5.0}, 10.0, so3::about_z(0.7));
  CHECK_NOTHROW(PoseSpace(planar, 3));
  planar.workspace.R = so3::exp({0.2, 0.0, 0.0});
  CHECK_THROWS_WITH(PoseSpace(planar, 3), Catch::Contains("planar"));
}

TEST_CASE("bin keys pack and unpack, and bin centres fall in their own bins") {
  for (const PoseSpaceSpec& spec : {paper_space(), letters_space()}) {
    PoseSpace space(spec, 7);
    util::Rng rng(4);
    for (int i = 0; i < 500; ++i) {
      const auto object = static_cast<std::uint32_t>(rng.below(7));
      const RigidPose p = random_pose(5000 + i, 0.9 * spec.translation_max_mm, space.planar());
      std::uint64_t key = 0;
      REQUIRE(space.bin_of(object, p, &key));
      CHECK(PoseSpace::object_of(key) == object);
      const BinIndex b = space.unpack(key);
      CHECK(space.pack(b) == key);
      // A centre maps back to its bin, unless it lies outside the Rodrigues
      // ball |r| <= pi (corner bins of the cube, which no vote can reach).
      if (glm::length(space.rotation_centre(b)) < std::numbers::pi) {
        std::uint64_t again = 0;
        REQUIRE(space.bin_of(object, space.centre(key), &again));
        CHECK(again == key);
      }
      // The centre is within half a bin of the pose.
      const double w = bin_width(spec);
      for (int k = 0; k < (space.planar() ? 2 : 3); ++k)
        CHECK(std::fabs(space.centre(key).T[k] - p.T[k]) <= 0.5 * w + 1e-9);
    }
    RigidPose outside;
    outside.T = glm::dvec3(spec.translation_max_mm + 1.0);
    std::uint64_t key = 0;
    CHECK_FALSE(space.bin_of(0, outside, &key));
  }
  // The neighbourhood has 3^6 keys in the interior (3^3 planar) and fewer at the border.
  PoseSpace space(paper_space(), 1);
  std::uint64_t key = 0;
  RigidPose p;
  p.R = so3::exp(glm::dvec3(0.3, -0.2, 0.1));
  REQUIRE(space.bin_of(0, p, &key));
  int n = 0;
  space.for_each_neighbour(key, [&](std::uint64_t) { ++n; });
  CHECK(n == 729);
  PoseSpace planar(letters_space(), 1);
  REQUIRE(planar.bin_of(0, RigidPose{so3::about_z(0.2), glm::dvec3(-9.9, 0.0, 0.0)}, &key));
  n = 0;
  planar.for_each_neighbour(key, [&](std::uint64_t) { ++n; });
  CHECK(n == 18);
}
