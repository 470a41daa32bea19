#pragma once
// MSSD and ADD-S for every posed step of an evaluation (docs/pose-errors.md), from each object's mesh and the
// symmetries found on it; computed after the trials, so the trial runners stay as they are.
#include <sva/eval/mesh_symmetry.hpp>
#include <sva/eval/results.hpp>
#include <sva/scene.hpp>

#include <memory>

#include "eval/surface_distance.hpp"

namespace sva::eval {

// What the surface errors need of one object, built once per mesh in a process.
struct SurfaceModel {
  MeshSymmetry symmetry;
  std::unique_ptr<SurfaceDistance> surface;
  std::vector<glm::dvec3> points;       // 500 on the surface (object frame): MSSD's
  std::vector<glm::dvec3> adds_points;  // the first 200 of them: ADD-S's (a closest point costs ~100 MSSD terms)
  std::vector<glm::dmat3> symmetries;   // symmetry_rotations(symmetry)
};

// The object's model (cached), or nullptr when it has no readable mesh (see object_symmetry).
std::shared_ptr<const SurfaceModel> surface_model(const SceneObject& object);

// Sets StepResult::mssd_mm and adds_mm of every step with a pose error, for the objects of `scene` (the test
// set's, indexed by TrialResult::object) that have a mesh; the others' stay unset.
void add_surface_errors(EvalResult& result, const Scene& scene, unsigned threads);

}  // namespace sva::eval
