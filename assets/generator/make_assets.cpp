// Generates the built-in objects (assets/objects/*.glb) and the household
// scenes (assets/scenes/household{10,25,50}.json) from code, so that every
// asset can be remade and reviewed:
//   usage: sva_make_assets OBJECTS_DIR [SCENES_DIR]
// Units are millimetres. The paper's objects are rescaled by their scenes; the
// household objects are written at their real sizes and their scenes keep them
// (size_mm is each mesh's largest dimension).
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "objects.hpp"

namespace {

using sva::assets::ObjectSpec;

struct Written {
  const ObjectSpec* spec;
  double size_mm;  // largest bounding-box dimension
};

Written write_object(const ObjectSpec& o, const std::filesystem::path& dir) {
  sva::sim::Mesh m = o.make();
  m.update_bounds();
  auto file = dir / (std::string(o.name) + ".glb");
  sva::sim::save_glb(m, file);
  glm::dvec3 e = m.extent();
  std::printf("%-20s %7zu vertices %7zu triangles  %6.1f x %6.1f x %6.1f mm  %8ju bytes\n", o.name, m.positions.size(),
              m.triangles.size(), e.x, e.y, e.z, static_cast<std::uintmax_t>(std::filesystem::file_size(file)));
  return {&o, std::max({e.x, e.y, e.z})};
}

// The household scenes share everything but their objects. Pair distances
// reach from the smallest objects' 10 mm to the largest's 250 mm; see
// docs/evaluation.md ("Many objects") for the protocol's sizes.
std::string household_scene(const std::vector<Written>& objects, std::size_t count) {
  std::ostringstream s;
  s << "{\n  \"name\": \"household" << count << "\",\n"
    << "  \"comment\": \"" << (count == objects.size() ? "The" : "The first " + std::to_string(count) + " of the")
    << " 50 everyday objects of the household set at their real sizes (sva_make_assets; docs/evaluation.md, Many "
       "objects).\",\n  \"objects\": [\n";
  for (std::size_t i = 0; i < count; ++i) {
    const Written& w = objects[i];
    char size[32], radius[32];
    std::snprintf(size, sizeof size, "%.1f", w.size_mm);
    std::snprintf(radius, sizeof radius, "%.1f", std::round(w.size_mm * 5) / 10);  // half the size
    s << "    {\"name\": \"" << w.spec->name << "\", \"mesh\": \"../objects/" << w.spec->name
      << ".glb\", \"size_mm\": " << size << ", \"symmetry\": " << w.spec->symmetry
      << ", \"inertial_radius_mm\": " << radius << "}" << (i + 1 < count ? ",\n" : "\n");
  }
  s << "  ],\n"
    << R"(  "sensor": {"rows": 6, "cols": 6, "pitch_mm": 2.0},
  "skin": {"stiffness_kpa_per_mm": 100, "spread_mm": 0.6, "rays_per_axis": 3, "noise_kpa": 0.0, "contact_threshold_kpa": 2.0, "target_pressure_kpa": 20.0},
  "errors": {"comment": "A capacitive 6 x 6 array (PPS-class) on a 6-axis arm (UR5/Panda-class); where each value comes from: docs/sensor-model.md, Error model.", "position_sigma_mm": 0.5, "normal_sigma_deg": 0.3, "gain_spread": 0.05, "offset_kpa": 0.3, "noise_kpa": 0.3, "full_scale_kpa": 200, "crosstalk": 0.02, "crosstalk_diagonal": 0.0, "train_sensor": 1, "test_sensor": 2},
  "pose_space": {"kind": "spatial", "translation_bins": 50, "translation_range_mm": [-200, 200], "rotation_bins": 9},
  "appearance": {"descriptor": "mnti", "clusters": 25, "dist_bins": 40, "dist_range_mm": [10, 170]},
  "protocol": {"kind": "paper3d", "train_per_object": 300, "test_per_object": 50, "approach_mm": 3.0, "tilt_deg": 10.0, "max_iterations": 100}
}
)";
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: %s OBJECTS_DIR [SCENES_DIR]\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path objects_dir = argv[1];
    std::filesystem::create_directories(objects_dir);
    for (const ObjectSpec& o : sva::assets::paper_objects()) write_object(o, objects_dir);
    const std::vector<ObjectSpec> household = sva::assets::household_objects();
    std::vector<Written> written;
    for (const ObjectSpec& o : household) written.push_back(write_object(o, objects_dir));
    if (argc == 3) {
      const std::filesystem::path scenes_dir = argv[2];
      for (std::size_t count : {10u, 25u, 50u}) {
        auto file = scenes_dir / ("household" + std::to_string(count) + ".json");
        sva::io::write_text_file(file, household_scene(written, count));
        std::printf("%s\n", file.string().c_str());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sva_make_assets: %s\n", e.what());
    return 1;
  }
  return 0;
}
