#pragma once
// An object's symmetries found from its mesh, as the BOP benchmark defines them
// (docs/pose-errors.md): a rotation S about the surface's centroid is a
// symmetry when no point of the turned surface lies farther than a tolerance
// from the surface. The pose errors MSSD and ADD-S are measured with them, and
// the scene's declared symmetry (SceneObject::symmetry) is checked against them.
#include <sva/map.hpp>
#include <sva/pose.hpp>
#include <sva/scene.hpp>

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace sva::eval {

struct MeshSymmetry {
  glm::dvec3 centre{0.0};  // every symmetry turns about this point: x -> S (x - centre) + centre
  double diameter_mm = 0.0;
  double tolerance_mm = 0.0;
  // A continuous symmetry: every rotation about this unit axis (through `centre`).
  std::optional<glm::dvec3> axis;
  // The discrete symmetries, identity first. With a continuous axis, only those that are not rotations about it
  // (e.g. the half turn that turns a tyre over), each standing for its whole family R_axis(g) * S.
  std::vector<glm::dmat3> rotations{glm::dmat3(1.0)};
  // The largest distance measured for an accepted symmetry (0 for the identity alone).
  double worst_accepted_mm = 0.0;

  bool only_identity() const { return !axis && rotations.size() == 1; }
  // In words: "none", "continuous about (0, 0, 1) and 2 discrete", "24 rotations".
  std::string describe() const;
};

struct SymmetrySearch {
  // BOP's step for continuous symmetries (bop_toolkit misc.get_symmetry_transformations): the point farthest from
  // the axis moves at most this fraction of the diameter between two rotations of the discretised axis.
  double tolerance_fraction = 0.01;  // of the diameter: the largest surface distance of a symmetry
  int max_order = 64;                // discrete orders tried about each candidate axis: 2..max_order
  std::size_t samples = 2000;        // surface points checked per candidate
  std::uint64_t seed = 1;
};

// The symmetries of one object's surface (object frame, mm). Throws sva::Error naming `what` for a mesh without
// area or with non-finite positions.
MeshSymmetry find_symmetries(const ObjectSurface& surface, const std::string& what, const SymmetrySearch& search = {});

// Where the scene's declared symmetry and the mesh's disagree: "" when they agree; otherwise one sentence naming
// the object, what the scene declares and what the mesh has (either way: a declared symmetry the mesh lacks, or a
// symmetry of the mesh the scene leaves out, which counts its symmetric copies as pose errors).
std::string symmetry_disagreement(const SceneObject& object, const MeshSymmetry& found);

// The rotations MSSD takes the minimum over (object frame, about `centre`): the discrete ones, and with a
// continuous axis each composed with ceil(pi / step_fraction) rotations about it (BOP's discretisation).
std::vector<glm::dmat3> symmetry_rotations(const MeshSymmetry& found, double step_fraction = 0.01);

}  // namespace sva::eval

namespace sva::eval {

// The symmetries of a scene object's mesh, fitted as the simulator fits it (sim::load_object_mesh), found once per
// mesh, size and centring in a process (later calls return the same answer). nullopt when this build has no
// simulator (no mesh loader) or the object has no mesh file; throws sva::Error naming the file when it is broken.
std::optional<MeshSymmetry> object_symmetry(const SceneObject& object);

// symmetry_disagreement for every object of the scene whose mesh can be read: what `sva train`, `sva eval` and
// `sva demo` print as warnings.
std::vector<std::string> symmetry_warnings(const Scene& scene);

}  // namespace sva::eval
