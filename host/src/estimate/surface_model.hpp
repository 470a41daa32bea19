#pragma once
// The measurement model of the verify stage (DESIGN 2): p(reading | object, pose) from the object's own surface,
// the mesh the map carries (map version 9, PairMap::surfaces), rather than from the training contacts sampled on it.
// A reading says where the sensor met the surface and which way the surface faced; under a hypothesis (object,
// pose) the model finds the point of the object's surface nearest to that contact and compares position and normal,
// with the noise the fine pose assumes (estimate/fine_pose.hpp: the final scale and the normal's weight). Everything
// it reads is the mesh, so two copies of one mesh predict every reading identically and give exactly zero evidence
// between them: where twins agree, no touch moves the balance.
//
// With the map's pad (PadGeometry), the image joins the comparison: the penetration each element felt against the
// hypothesis's surface under it, so a slot, a ridge or a rim under the pad tells twins apart even where the contact
// point and normal agree. Not modelled: the skin's elastic spread (the simulator's sim/ alone, docs/architecture.md).
#include <sva/base/triangle_tree.hpp>
#include <sva/map.hpp>
#include <sva/pose.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "reading/observed_reading.hpp"

namespace sva {

// How a reading is weighed against a predicted contact: the joint residual s^2 = d^2 + (normal_weight_mm * angle)^2
// with d the distance to the surface and `angle` the normals' misfit; a reading scores log2(exp(-s^2 / (2 sigma^2))
// + floor), and one the surface does not reach within `reach_mm` scores log2(floor).
struct ContactNoise {
  double sigma_mm = 1.0;
  double normal_weight_mm = 4.0;
  double floor = 0.01;
  double reach_mm = 3.0;  // past it the Gaussian term is below the floor's hundredth: not searched
  // The pad's image against the surface under it (SurfaceModel::pad_misfit): its misfit in mm joins the residual
  // as (sigma / pad_sigma)^2 * misfit^2. 0: the image is not compared (the contact alone, as before).
  double pad_sigma_mm = 0.0;
};

// The pad a map's readings were pressed with (its appearance calibration): the array's shape and pitch, and the
// penetration an element must feel to count as touching (the contact threshold over the stiffness).
struct PadGeometry {
  int rows = 0, cols = 0;
  double pitch_mm = 0.0;
  double contact_depth_mm = 0.02;
  double reach_mm = 1.5;  // how far from an element's centre the surface is looked for (no surface: no contact)
};

class SurfaceModel {
 public:
  // One tree of triangles per object (sva/base/triangle_tree.hpp); no query looks farther than `reach_mm`. Throws
  // sva::Error on a reach that is not positive or a corner that is not finite.
  SurfaceModel(const std::vector<ObjectSurface>& surfaces, double reach_mm);
  // With the pad the readings were taken with, the model also compares each reading's image (pad_misfit).
  SurfaceModel(const std::vector<ObjectSurface>& surfaces, double reach_mm, const PadGeometry& pad);

  std::size_t objects() const { return meshes_.size(); }
  double reach_mm() const { return reach_; }  // the farthest a query looks

  struct Nearest {
    bool found = false;
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0.0};  // the triangle's unit normal, outward by its winding
    double distance = 0.0;
    double d2 = 0.0;  // the squared distance the search weighed (distance is its square root)
    std::uint32_t triangle = 0;
  };
  // The point of `object`'s surface nearest to `p` (object frame) within `radius` (at most the reach); ties go to
  // the smaller triangle index, so the answer is one and the same on every machine.
  Nearest nearest(std::uint32_t object, const glm::dvec3& p, double radius) const;
  // Whether a nearest point found at squared distance d2 lies within `radius` as nearest() tests it. So the answer
  // of nearest() at a smaller radius follows from one at a larger: the same point where this holds, none where not
  // (every other point within the larger radius lay no nearer).
  bool within(double d2, double radius) const {
    const double r = std::min(radius, reach_);
    return r > 0.0 && d2 < r * r;
  }

  // log2 p(readings | object, pose), each reading once (grid frame: the readings and the pose alike).
  double log2_likelihood(std::uint32_t object, std::span<const ObservedReading> readings, const RigidPose& pose,
                         const ContactNoise& noise) const;
  // One reading's term of it.
  double log2_likelihood(std::uint32_t object, const ObservedReading& reading, const RigidPose& pose,
                         const ContactNoise& noise) const;

  // How far the pad's image departs from what `object`'s surface at `pose` predicts, in mm (root mean square over
  // the elements either side sees in contact): each element's centre on the reading's pad plane, the surface's height
  // under it (the nearest point within the pad's reach, along the reading's normal), the predicted penetration that
  // height below a plane fitted to the image (the press depth and the arm's small tilt, which the image cannot tell
  // from the surface's own). Negative when there is nothing to compare: no pad, no image, an image of another size.
  double pad_misfit(std::uint32_t object, const ObservedReading& reading, const RigidPose& pose) const;
  bool has_pad() const { return pad_.rows > 0; }

 private:
  struct Mesh {
    TriangleTree tree;                 // the kept triangles (degenerate ones dropped), searched by their kept number
    std::vector<glm::dvec3> normal;    // each kept triangle's unit normal
    std::vector<std::uint32_t> index;  // each kept triangle's index in the object's surface
  };
  std::vector<Mesh> meshes_;
  double reach_ = 1.0;
  PadGeometry pad_;
};

}  // namespace sva
