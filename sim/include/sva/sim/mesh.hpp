#pragma once
// Triangle meshes for the simulator: loaded from glTF 2.0 (.gltf, .glb),
// validated, flattened (every mesh, primitive and node transform) and fitted
// to a scene object's size and centre. Units: millimetres after fitting.
#include <sva/map.hpp>
#include <sva/scene.hpp>

#include <glm/glm.hpp>

#include <filesystem>
#include <vector>

namespace sva::sim {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;     // per vertex; computed (area-weighted) where the file has none
  std::vector<glm::uvec3> triangles;  // counter-clockwise seen from outside
  glm::dvec3 bounds_min{0.0}, bounds_max{0.0};

  double area() const;
  glm::dvec3 extent() const { return bounds_max - bounds_min; }
  void update_bounds();
};

// Loads every triangle of the file's default scene (or of all root nodes when it
// names none), with node transforms applied. Strips and fans are triangulated;
// points and lines are ignored. Throws sva::Error naming the file and the fault:
// unreadable or not glTF, missing buffers, indices out of range, accessors that
// overrun their buffers, non-finite positions, no triangles, zero area.
Mesh load_mesh(const std::filesystem::path& file);

// Scales (largest bounding-box dimension -> size_mm, when > 0) and centres (the
// bounding-box centre -> origin, when `center`) as the scene object asks.
void fit_mesh(Mesh& mesh, const SceneObject& object);

// load_mesh + fit_mesh.
Mesh load_object_mesh(const SceneObject& object);

// The objects' surfaces of `scene` for a map (TrainOptions::surfaces): each object's mesh fitted as the simulator
// fits it (load_object_mesh), in the scene's order: the frame its simulated readings were taken in. Throws
// sva::Error naming the object and the file when a mesh is missing or broken.
std::vector<ObjectSurface> object_surfaces(const Scene& scene);

// Writes the mesh as a binary glTF (.glb) atomically: positions and indices
// (and normals when `with_normals`), one node, one primitive.
void save_glb(const Mesh& mesh, const std::filesystem::path& file, bool with_normals = false);

}  // namespace sva::sim
