// The alignment a fine pose solves (estimate/fit_problem.hpp): a fit at a smaller scale taken from the last one
// without a search, and a fit that stops once it cannot beat a cost, each deciding as the whole search would, on the
// object's mesh and on the map's training contacts.
#include <catch2/catch.hpp>

#include <sva/base/rng.hpp>
#include <sva/base/so3.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "estimate/blob.hpp"
#include "estimate/fit_problem.hpp"
#include "recognition/fixture.hpp"

using namespace sva;
using namespace sva::pose_fit;

namespace {

using test::blob_normal;
using test::blob_point;

// The blob cut into about 3,000 triangles of 2-3 mm, and its vertices with their normals as training contacts.
struct Blob {
  ObjectSurface mesh;
  MapReadings contacts;
};

Blob blob() {
  Blob b;
  const int rings = 30, segments = 50;
  const double pi = std::acos(-1.0);
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = pi * i / rings, ph = 2.0 * pi * j / segments;
      const glm::dvec3 p = blob_point(th, ph);
      b.mesh.positions.emplace_back(p);
      if (i == 0 || i == rings) continue;  // the poles' normals are not defined by the grid
      b.contacts.push_back(0, p, blob_normal(th, ph), 1.0f);
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const auto at = [&](int r, int k) { return static_cast<unsigned>(r * segments + (k % segments)); };
      b.mesh.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));  // outward, as the normals
      b.mesh.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return b;
}

// Readings on the blob under `truth`, a few with 2-5 mm off the surface (what a smaller scale leaves out).
std::vector<ObservedReading> readings_on(const RigidPose& truth, util::Rng& rng, int count) {
  std::vector<ObservedReading> out;
  for (int k = 0; k < count; ++k) {
    const double th = std::acos(rng.uniform(-0.95, 0.95)), ph = rng.uniform(0.0, 2.0 * std::acos(-1.0));
    const double lift = k % 4 == 0 ? rng.uniform(2.0, 5.0) : rng.uniform(-0.2, 0.2);
    const glm::dvec3 p = blob_point(th, ph), n = glm::normalize(p);
    ObservedReading r;
    r.position = truth.apply(p + lift * n);
    r.normal = truth.rotate(n);
    r.norm_conf = 1.0f;
    r.classes = {{0, 1.0f}};
    out.push_back(r);
  }
  return out;
}

// `truth` moved by up to `mm` and `rad` in random directions.
RigidPose near(const RigidPose& truth, util::Rng& rng, double mm, double rad) {
  const double ax = rng.normal(), ay = rng.normal(), az = rng.normal(), angle = rng.uniform(0.0, rad);
  const double tx = rng.uniform(-mm, mm), ty = rng.uniform(-mm, mm), tz = rng.uniform(-mm, mm);
  RigidPose p = truth;
  p.R = so3::exp(angle * glm::normalize(glm::dvec3(ax, ay, az))) * truth.R;
  p.T = truth.T + glm::dvec3(tx, ty, tz);
  return p;
}

bool same_fit(const Fit& a, const Fit& b) {
  if (a.cost != b.cost || a.inliers != b.inliers || a.matches.size() != b.matches.size()) return false;
  for (std::size_t i = 0; i < a.matches.size(); ++i) {
    const Match &x = a.matches[i], &y = b.matches[i];
    if (x.found != y.found || x.point != y.point || x.normal != y.normal || x.s2 != y.s2) return false;
  }
  return true;
}

RefineSettings settings() {
  RefineSettings s;
  s.normal_weight_mm = 1.0;
  return s;
}

}  // namespace

TEST_CASE("pose fit: a fit narrowed to a smaller scale is the search's own, on the mesh and on the contacts") {
  // A run weighs the same pose again at its next scale from the last fit (Problem::narrowed): the same matches, less
  // those the mesh's smaller radius leaves out. Against a fresh search at that scale, bit for bit.
  const Blob b = blob();
  const SurfaceModel model({b.mesh}, 3.0);
  const SurfaceIndex index(b.contacts, 1);
  const RefineSettings s = settings();
  const MeshCorrespondences mesh(model, 0, s);
  const ContactCorrespondences contacts(index, 0, s);
  util::Rng rng(7, 1);
  const RigidPose truth = test::random_pose(3, 80.0);
  const std::vector<ObservedReading> readings = readings_on(truth, rng, 40);
  std::size_t kept = 0, dropped = 0;
  const std::vector<const Correspondences*> sources{&mesh, &contacts};
  for (const Correspondences* source : sources) {
    const Problem problem(*source, readings, s);
    for (int trial = 0; trial < 40; ++trial) {
      const RigidPose pose = near(truth, rng, 2.0, 0.05);
      for (const double wide : {4.0, 2.0, 1.0}) {
        const Fit first = problem.fit(pose, wide);
        for (const double narrow : {wide, 0.75 * wide, 0.5 * wide, 0.25 * wide}) {
          INFO((source == &mesh ? "mesh" : "contacts")
               << ", trial " << trial << ", scale " << wide << " then " << narrow);
          const Fit searched = problem.fit(pose, narrow), narrowed = problem.narrowed(first, narrow);
          REQUIRE(same_fit(narrowed, searched));
          for (std::size_t i = 0; i < first.matches.size(); ++i)
            (first.matches[i].found && !searched.matches[i].found ? dropped : kept) += first.matches[i].found;
        }
      }
    }
  }
  CHECK(kept > 1000);  // not vacuous: the smaller radius both keeps and leaves out matches
  CHECK(dropped > 100);
}

TEST_CASE("pose fit: a fit asked to beat a cost stops once it cannot, and decides as the whole fit") {
  // A step's candidate is only compared with the pose it would replace: its fit stops at the first reading whose
  // running cost reaches that (Problem::fit's `beat`). Whatever the bar, it must fall below it exactly when the whole
  // fit does, and be the whole fit then.
  const Blob b = blob();
  const SurfaceModel model({b.mesh}, 3.0);
  const RefineSettings s = settings();
  const MeshCorrespondences mesh(model, 0, s);
  util::Rng rng(8, 1);
  const RigidPose truth = test::random_pose(4, 80.0);
  const std::vector<ObservedReading> readings = readings_on(truth, rng, 30);
  const Problem problem(mesh, readings, s);
  std::size_t stopped = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const RigidPose pose = near(truth, rng, 1.5, 0.04);
    const double scale = trial % 2 ? 1.0 : 3.0;
    const Fit whole = problem.fit(pose, scale);
    const double inf = std::numeric_limits<double>::infinity();
    for (const double bar : {whole.cost, std::nextafter(whole.cost, inf), std::nextafter(whole.cost, 0.0),
                             0.5 * whole.cost, 0.9 * whole.cost, 1.1 * whole.cost, inf}) {
      INFO("trial " << trial << ", cost " << whole.cost << ", bar " << bar);
      const Fit part = problem.fit(pose, scale, nullptr, bar);
      REQUIRE((part.cost < bar) == (whole.cost < bar));
      if (whole.cost < bar) REQUIRE(same_fit(part, whole));
      stopped += part.matches.size() < readings.size();
    }
  }
  CHECK(stopped > 200);  // not vacuous: most bars below the cost stop the fit early
}

TEST_CASE("pose fit: a run gives its start's own fit at the final scale, from the first fit narrowed") {
  const Blob b = blob();
  const SurfaceModel model({b.mesh}, 3.0);
  RefineSettings s = settings();
  s.scale_start_mm = 3.0;
  s.scale_final_mm = 0.75;
  const MeshCorrespondences mesh(model, 0, s);
  util::Rng rng(9, 1);
  const RigidPose truth = test::random_pose(5, 80.0);
  const std::vector<ObservedReading> readings = readings_on(truth, rng, 30);
  const Problem problem(mesh, readings, s);
  for (int trial = 0; trial < 10; ++trial) {
    const RigidPose start = near(truth, rng, 1.5, 0.04);
    Fit start_fit;
    int observable = 0;
    const auto [pose, f] = problem.run(start, &observable, &start_fit);
    CHECK(same_fit(start_fit, problem.fit(start, s.scale_final_mm)));
    CHECK(f.cost <= start_fit.cost);  // the run never ends worse than where it began
  }
}

TEST_CASE("pose fit: a fit split over its readings is the fit in turn, stop and runs included, on both sources") {
  // One robot's session on many cores: a run's fits match their readings side by side in chunks
  // (RefineSettings::reading_threads), then add them in order. Bit for bit the fit in turn, for any chunking, with a
  // bar that stops it, and whole runs from the same start with their memos.
  const Blob b = blob();
  const SurfaceModel model({b.mesh}, 3.0);
  const SurfaceIndex index(b.contacts, 1);
  RefineSettings in_turn = settings();
  in_turn.scale_start_mm = 3.0;
  in_turn.scale_final_mm = 0.75;
  util::Rng rng(10, 1);
  const RigidPose truth = test::random_pose(6, 80.0);
  const std::vector<ObservedReading> readings = readings_on(truth, rng, 31);  // chunks of unequal size
  std::size_t stopped = 0;
  for (const unsigned split : {2u, 3u, 7u, 16u}) {
    RefineSettings side = in_turn;
    side.reading_threads = split;
    const MeshCorrespondences mesh(model, 0, in_turn), mesh_split(model, 0, side);
    const ContactCorrespondences contacts(index, 0, in_turn), contacts_split(index, 0, side);
    const std::vector<std::pair<const Correspondences*, const Correspondences*>> sources{{&mesh, &mesh_split},
                                                                                         {&contacts, &contacts_split}};
    for (const auto& [one, other] : sources) {
      const Problem a(*one, readings, in_turn), c(*other, readings, side);
      for (int trial = 0; trial < 8; ++trial) {
        const RigidPose pose = near(truth, rng, 1.5, 0.04);
        const Fit whole = a.fit(pose, 1.0);
        INFO("split " << split << ", trial " << trial);
        REQUIRE(same_fit(c.fit(pose, 1.0), whole));
        const Fit part = c.fit(pose, 1.0, nullptr, 0.5 * whole.cost);
        REQUIRE(same_fit(part, a.fit(pose, 1.0, nullptr, 0.5 * whole.cost)));
        stopped += part.matches.size() < readings.size();
        int oa = 0, oc = 0;
        Fit sa, sc;
        const auto [pa, fa] = a.run(pose, &oa, &sa);
        const auto [pc, fc] = c.run(pose, &oc, &sc);
        REQUIRE(pa.R == pc.R);
        REQUIRE(pa.T == pc.T);
        REQUIRE(same_fit(fa, fc));
        REQUIRE(same_fit(sa, sc));
        REQUIRE(oa == oc);
      }
    }
  }
  CHECK(stopped > 16);  // not vacuous: the bar stopped split fits too
  RefineSettings many = in_turn;
  many.threads = 16;
  CHECK(with_runs_side_by_side(many, 12).reading_threads == 16);  // 4 idle workers: each run may split
  CHECK(with_runs_side_by_side(many, 16).reading_threads == 1);   // the runs fill the workers
  many.threads = 2;
  CHECK(with_runs_side_by_side(many, 12).reading_threads == 1);
}
