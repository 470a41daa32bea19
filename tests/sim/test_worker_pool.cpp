// The simulator's Embree device must leave the process its threads. Embree built with TBB tasking turns a device's
// "threads=N" into a process-wide TBB limit, which once capped every parallel loop after the first mesh was loaded
// (`sva simulate --threads 2` ran on one core, and so did recognition in the same process). After a mesh is loaded,
// a parallel loop of slow items must still run more than one item at a time.
#include <catch2/catch.hpp>

#include <sva/base/parallel.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "gltf_writer.hpp"
#include "test_support.hpp"

using namespace sva;

TEST_CASE("loading a mesh (the Embree device) leaves the worker pool all of its threads") {
  if (std::thread::hardware_concurrency() < 2) test::skip("needs 2 cores");
  const test::TestMesh sphere = test::sphere_mesh(30.0f, 2);
  sim::Mesh mesh;
  mesh.positions = sphere.positions;
  for (std::size_t i = 0; i < sphere.indices.size(); i += 3)
    mesh.triangles.emplace_back(sphere.indices[i], sphere.indices[i + 1], sphere.indices[i + 2]);
  mesh.update_bounds();
  const sim::ObjectGeometry geometry(mesh);
  REQUIRE(geometry.intersect({0.0, 0.0, 100.0}, {0.0, 0.0, -1.0}, 0.0, 1e3).hit);

  std::atomic<int> active{0}, most{0};
  util::parallel_for(
      16,
      [&](std::size_t) {
        const int now = ++active;
        int seen = most.load();
        while (now > seen && !most.compare_exchange_weak(seen, now)) {
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        --active;
      },
      2);
  CHECK(most.load() >= 2);
}
