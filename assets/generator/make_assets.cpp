// Generates the built-in objects (assets/objects/*.glb) and the scenes of
// objects at their real sizes (assets/scenes/household{10,25,50,100}.json and
// lookalikes.json) from code, so that every asset can be remade and reviewed:
//   usage: sva_make_assets OBJECTS_DIR [SCENES_DIR]
// Units are millimetres. The paper's objects are rescaled by their scenes; the
// household objects and the look-alikes are written at their real sizes and
// their scenes keep them (size_mm is each mesh's largest dimension).
#include <sva/error.hpp>
#include <sva/io/text_file.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>

#include "objects.hpp"

namespace {

using sva::assets::LookalikeFamily;
using sva::assets::ObjectSpec;

struct Written {
  const ObjectSpec* spec;
  double size_mm;                // largest bounding-box dimension
  const char* family = nullptr;  // its look-alike family, if it has one
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

// The scenes of objects at their real sizes (the household scenes and the
// look-alikes') share everything but their name, comment and objects. Pair
// distances reach from the smallest objects' 10 mm to the largest's 250 mm;
// see docs/evaluation.md ("Many objects") for the protocol's sizes. The scene
// of near-twins (lookalikes) touches each object four times as often as it
// pairs its readings: the twins differ where few touches land, and the extra
// contacts are the surface the fine pose and the surface check read
// (docs/recognition.md, "Surface check"). household100 keeps 300 readings, all
// paired: there the extra surface bought no accuracy and its calibration lost
// (docs/evaluation.md, "A surface denser than the pairs").
std::string household_scene(const std::string& name, const std::string& comment, const std::vector<Written>& objects,
                            bool twins) {
  std::ostringstream s;
  s << "{\n  \"name\": \"" << name << "\",\n"
    << "  \"comment\": \"" << comment << "\",\n  \"objects\": [\n";
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const Written& w = objects[i];
    char size[32], radius[32];
    std::snprintf(size, sizeof size, "%.1f", w.size_mm);
    std::snprintf(radius, sizeof radius, "%.1f", std::round(w.size_mm * 5) / 10);  // half the size
    s << "    {\"name\": \"" << w.spec->name << "\", \"mesh\": \"../objects/" << w.spec->name
      << ".glb\", \"size_mm\": " << size << ", \"symmetry\": " << w.spec->symmetry;
    if (w.family) s << ", \"family\": \"" << w.family << "\"";
    s << ", \"inertial_radius_mm\": " << radius << "}" << (i + 1 < objects.size() ? ",\n" : "\n");
  }
  s << "  ],\n"
    << R"(  "sensor": {"rows": 6, "cols": 6, "pitch_mm": 2.0},
  "skin": {"stiffness_kpa_per_mm": 100, "spread_mm": 0.6, "rays_per_axis": 3, "noise_kpa": 0.0, "contact_threshold_kpa": 2.0, "target_pressure_kpa": 20.0},
  "errors": {"comment": "A capacitive 6 x 6 array (PPS-class) on a 6-axis arm (UR5/Panda-class); where each value comes from: docs/sensor-model.md, Error model.", "position_sigma_mm": 0.5, "normal_sigma_deg": 0.3, "gain_spread": 0.05, "offset_kpa": 0.3, "noise_kpa": 0.3, "full_scale_kpa": 200, "crosstalk": 0.02, "crosstalk_diagonal": 0.0, "train_sensor": 1, "test_sensor": 2},
  "pose_space": {"kind": "spatial", "translation_bins": 50, "translation_range_mm": [-200, 200], "rotation_bins": 9},
  "appearance": {"descriptor": "mnti", "clusters": 25, "dist_bins": 40, "dist_range_mm": [10, 170])"
    << (twins ? R"(, "pair_readings": 300)" : "") << R"(},
  "protocol": {"kind": "paper3d", "train_per_object": )"
    << (twins ? 1200 : 300) << R"(, "test_per_object": 50, "approach_mm": 3.0, "tilt_deg": 10.0, "max_iterations": 100}
}
)";
  return s.str();
}

// household10, 25 and 50 (the household set and its first objects), lookalikes
// (the families' objects) and household100: the household set followed by
// whole families, in order, up to 100 objects.
void write_scenes(const std::filesystem::path& dir, const std::vector<Written>& household,
                  const std::vector<Written>& lookalikes) {
  auto write = [&](const std::string& name, const std::string& comment, const std::vector<Written>& objects,
                   bool twins = false) {
    auto file = dir / (name + ".json");
    sva::io::write_text_file(file, household_scene(name, comment, objects, twins));
    std::printf("%s\n", file.string().c_str());
  };
  const std::string real = " at their real sizes (sva_make_assets; docs/evaluation.md, Many objects).";
  for (std::size_t count : {10u, 25u, 50u}) {
    std::string first = count == household.size() ? "The" : "The first " + std::to_string(count) + " of the";
    write("household" + std::to_string(count), first + " 50 everyday objects of the household set" + real,
          {household.begin(), household.begin() + static_cast<std::ptrdiff_t>(count)});
  }
  write("lookalikes",
        "Look-alike families, near-twins that differ by a scale, a detail, a handedness or one region," + real,
        lookalikes, true);
  std::vector<Written> all = household;
  for (std::size_t i = 0, end = 0; i < lookalikes.size() && all.size() < 100; i = end) {
    for (end = i; end < lookalikes.size() && std::string_view(lookalikes[end].family) == lookalikes[i].family;) ++end;
    if (all.size() + (end - i) > 100) break;  // whole families only
    all.insert(all.end(), lookalikes.begin() + static_cast<std::ptrdiff_t>(i),
               lookalikes.begin() + static_cast<std::ptrdiff_t>(end));
  }
  if (all.size() != 100) throw sva::Error("household100: whole look-alike families do not make 100 objects");
  write("household100", "The 50 everyday objects of the household set and the look-alike families" + real, all);
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
    const std::vector<LookalikeFamily> families = sva::assets::lookalike_families();
    std::vector<Written> lookalikes;
    for (const LookalikeFamily& f : families)
      for (const ObjectSpec& o : f.members) {
        lookalikes.push_back(write_object(o, objects_dir));
        lookalikes.back().family = f.name;
      }
    if (argc == 3) write_scenes(argv[2], written, lookalikes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sva_make_assets: %s\n", e.what());
    return 1;
  }
  return 0;
}
