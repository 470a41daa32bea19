#pragma once
// The robust alignment a fine pose solves (estimate/fine_pose.hpp): each reading matched to where it meets the object
// (the map's training contacts, or the object's mesh), Tukey's cost of the matches on a scale, and Gauss-Newton steps
// on SE(3) (SE(2) in a planar pose space) through a shrinking scale. Apart from the fine pose's entry points, so
// that the tests can weigh one fit against another.
#include <sva/pose.hpp>

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "estimate/fine_pose.hpp"
#include "estimate/surface_model.hpp"
#include "map/surface_index.hpp"
#include "reading/observed_reading.hpp"

namespace sva::pose_fit {

// The pose is moved by a small motion about the readings' centroid c, in the
// robot frame: x -> exp(w) (x - c) + c + v. Its parameters are (L w, v): the
// rotation scaled by the readings' spread L, so that both halves are in mm and
// the normal equations' eigenvalues compare (a planar space uses w_z, v_x, v_y).
constexpr int kMaxDim = 6;
using Vec = std::array<double, kMaxDim>;
using Mat = std::array<Vec, kMaxDim>;

// One reading matched to a training contact (both in the robot frame under the current pose).
struct Match {
  bool found = false;
  glm::dvec3 point{0.0};   // the training contact
  glm::dvec3 normal{0.0};  // its normal
  double plane = 0.0;      // point-to-plane residual (mm)
  glm::dvec3 tilt{0.0};    // observed normal minus the contact's
  double s2 = 0.0;         // squared joint residual: plane^2 + (normal weight * |tilt|)^2
  double d2 = 0.0;         // the squared distance its search weighed (Correspondences::within)
};

struct Fit {
  double cost = 0.0;
  std::size_t inliers = 0;
  std::vector<Match> matches;
};

// The weighted normal equations of one Gauss-Newton step: h (point-to-plane plus normal tilt) and g, and hs, the
// point-to-plane rows with the observed normals, which judge what the surface constrains.
struct Equations {
  Mat h{}, hs{};
  Vec g{};
};

struct Step {
  Vec delta{};         // in the parameters above
  int observable = 0;  // directions the point-to-plane equations constrain
};

// Where a reading meets the object (object frame): the surface point and normal matched to a contact `y` whose
// normal is `u`, within `radius` of it. Two sources: the map's training contacts, and the object's mesh.
// `memo`: what the last query for the same reading kept (a fit's next step asks again nearby), or null. *d2: the
// squared distance the search weighed.
class Correspondences {
 public:
  virtual ~Correspondences() = default;
  virtual bool match(const glm::dvec3& y, const glm::dvec3& u, double radius, glm::dvec3* point, glm::dvec3* normal,
                     double* d2, NeighbourMemo* memo) const = 0;
  // Whether a match found at a larger radius, at squared distance d2, is the match at `radius` (else there is none):
  // a fit's next scale at the same pose follows from its last one without a search.
  virtual bool within(double d2, double radius) const = 0;
};

// The training contacts: the first of the nearest few whose normal is compatible (the radius is not used: the
// robust loss decides what a far match is worth).
class ContactCorrespondences final : public Correspondences {
 public:
  ContactCorrespondences(const SurfaceIndex& surface, std::uint32_t object, const RefineSettings& s)
      : surface_(surface), object_(object), s_(s) {}
  bool match(const glm::dvec3& y, const glm::dvec3& u, double, glm::dvec3* point, glm::dvec3* normal, double* d2,
             NeighbourMemo* memo) const override;
  bool within(double, double) const override { return true; }  // the radius is not used

 private:
  const SurfaceIndex& surface_;
  std::uint32_t object_;
  RefineSettings s_;
};

// The mesh: the nearest point within the radius (at most the model's reach), facing the contact's way.
class MeshCorrespondences final : public Correspondences {
 public:
  MeshCorrespondences(const SurfaceModel& model, std::uint32_t object, const RefineSettings& s)
      : model_(model), object_(object), s_(s) {}
  bool match(const glm::dvec3& y, const glm::dvec3& u, double radius, glm::dvec3* point, glm::dvec3* normal, double* d2,
             NeighbourMemo*) const override;
  // The nearest facet within a smaller radius is the same one, or none; one whose normal did not face the contact
  // still does not.
  bool within(double d2, double radius) const override { return model_.within(d2, radius); }

 private:
  const SurfaceModel& model_;
  std::uint32_t object_;
  RefineSettings s_;
};

// The alignment of a session's readings to one source of correspondences: a fit of the matches at a pose and scale,
// the Gauss-Newton step it implies, and a run from a start through every scale.
class Problem {
 public:
  Problem(const Correspondences& surface, std::span<const ObservedReading> readings, const RefineSettings& s);

  // `memos`: one per reading, kept across one run's fits (run), or null. `beat`: a cost the caller only asks this fit
  // to fall below (a step's candidate against the pose it would replace). The fit stops at the first reading whose
  // running sum reaches it: a sum of non-negative terms, rounded, never falls as it grows, so the whole cost could not
  // have fallen below either, and the caller decides alike. Such a fit's cost and matches are partial: only compared.
  Fit fit(const RigidPose& pose, double scale, std::vector<NeighbourMemo>* memos = nullptr,
          double beat = std::numeric_limits<double>::infinity()) const;
  // The fit at the same pose at a scale no larger than `f`'s (a whole fit): the same matches, less those the smaller
  // radius leaves out, each weighed at the new scale. The same bits as fit(), without a search.
  Fit narrowed(const Fit& f, double scale) const;
  Equations normal_equations(const Fit& fit, double scale) const;
  Step step(const Fit& fit, double scale) const;
  RigidPose apply(const RigidPose& pose, const Vec& delta, double t) const;
  // One start through every scale; the fit at the final scale. *start_fit, unless null: the start's own fit at the
  // final scale.
  std::pair<RigidPose, Fit> run(const RigidPose& start, int* observable, Fit* start_fit = nullptr) const;

 private:
  Match match(const RigidPose& pose, const ObservedReading& r, double scale, NeighbourMemo* memo) const;
  static void add(Fit* f, const Match& m, double scale);  // a reading's term of the cost
  // A parameter's place in the full (w_x, w_y, w_z, v_x, v_y, v_z).
  int full_index(int i) const { return dim_ == 6 ? i : i + 2; }

  const Correspondences& surface_;
  std::span<const ObservedReading> readings_;
  RefineSettings s_;
  int dim_;
  glm::dvec3 centre_{0.0};
  double spread_ = 1.0;
};

}  // namespace sva::pose_fit
