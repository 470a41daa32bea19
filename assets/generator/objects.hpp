#pragma once
// The generated objects: what each is called, how it is made, and (for the
// household set and the look-alikes) the symmetry its scene declares.
#include <string>
#include <vector>

#include "mesh_builder.hpp"

namespace sva::assets {

struct ObjectSpec {
  const char* name;
  Mesh (*make)();
  // The scene's "symmetry" value (JSON) in the mesh's frame: "none", an axis
  // of revolution or an n-fold rotation group about an axis.
  std::string symmetry = "\"none\"";
};

std::string axis_symmetry(const char* axis = "[0, 0, 1]");
std::string cyclic_symmetry(int order, const char* axis = "[0, 0, 1]");

// The ten objects of paper3d and the five raised letters of letters2d.
std::vector<ObjectSpec> paper_objects();

// The 50 everyday objects at their real sizes, in the order of
// household50.json; household10 and household25 are its first 10 and 25.
std::vector<ObjectSpec> household_objects();

// A family of look-alikes: near-twins that differ by one thing a touch could
// feel (a scale, a local detail, a handedness, one region), nothing else.
struct LookalikeFamily {
  const char* name;
  std::vector<ObjectSpec> members;
};

// The look-alike families at their real sizes, 50 objects in all, in the
// order of lookalikes.json (household100 is household50 followed by them).
std::vector<LookalikeFamily> lookalike_families();

}  // namespace sva::assets
