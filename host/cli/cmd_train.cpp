// sva train: build the SVA pair map from a training dataset.
#include <sva/dataset.hpp>
#include <sva/eval/mesh_symmetry.hpp>
#include <sva/eval/report.hpp>
#include <sva/map.hpp>
#include <sva/sim/mesh.hpp>

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "args.hpp"

namespace sva::cli {

namespace {
// "MIN:MAX" in mm.
std::pair<double, double> parse_range(const std::string& text) {
  const auto colon = text.find(':');
  auto bad = [&] { return Error("sva train: --dist-range expects MIN:MAX in mm (e.g. 30:160), got \"" + text + "\""); };
  if (colon == std::string::npos) throw bad();
  const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
  char* end = nullptr;
  const double lo = std::strtod(a.c_str(), &end);
  if (a.empty() || *end != '\0') throw bad();
  const double hi = std::strtod(b.c_str(), &end);
  if (b.empty() || *end != '\0') throw bad();
  return {lo, hi};  // the range itself is TrainOptions::validate's to check
}

// The command's options as the library's TrainOptions (TrainOptions::validate checks them).
TrainOptions train_options(const Args& a) {
  TrainOptions o;
  constexpr long long kInt = std::numeric_limits<int>::max();
  o.descriptor = a.get("--descriptor");
  if (a.has("--clusters")) o.clusters = static_cast<int>(a.integer("--clusters", 25, -kInt, kInt));
  if (a.has("--dist-bins")) o.dist_bins = static_cast<int>(a.integer("--dist-bins", 40, -kInt, kInt));
  if (auto r = a.get("--dist-range")) {
    auto [lo, hi] = parse_range(*r);
    o.dist_min_mm = lo;
    o.dist_max_mm = hi;
  }
  if (a.has("--pair-readings"))
    o.pair_readings = static_cast<std::size_t>(a.integer("--pair-readings", 0, 0, 100000000));
  o.seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, std::numeric_limits<long long>::max()));
  o.threads = static_cast<unsigned>(a.integer("--threads", 0, 0, kInt));
  o.progress = true;
  o.calibrate = !a.has("--no-calibration");
  o.calibration_sessions = static_cast<std::size_t>(a.integer("--calibration-sessions", 60, -kInt, kInt));
  o.calibration_readings = static_cast<std::size_t>(a.integer("--calibration-readings", 12, -kInt, kInt));
  o.calibration_held_out = a.number("--calibration-held-out", 0.1, -1e9, 1e9);
  if (a.has("--fine-pose-from"))
    o.fine_pose_from = static_cast<std::uint32_t>(a.integer("--fine-pose-from", 6, 3, 1000));
  o.validate("sva train");  // before the dataset loads
  return o;
}

// --exclude-objects' names.
std::vector<std::string> comma_list(const std::string& names) {
  std::vector<std::string> list;
  std::size_t start = 0;
  for (std::size_t comma; (comma = names.find(',', start)) != std::string::npos; start = comma + 1)
    list.push_back(names.substr(start, comma - start));
  list.push_back(names.substr(start));
  return list;
}

// What was built, from what, and what it cost.
void print_report(const MapSummary& m, const TrainReport& rep, const std::string& out_file,
                  const std::string& data_file) {
  std::printf("%s: SVA map of scene \"%s\" from %s\n", out_file.c_str(), m.scene_name.c_str(), data_file.c_str());
  std::printf("  descriptor     %s (%u values)\n", m.descriptor == "mn" ? "MN" : "MNTI", m.descriptor_size);
  std::printf("  readings       %zu used, %zu skipped (not converged), %zu skipped (no contact to describe)\n",
              rep.readings_used, rep.skipped_not_converged, rep.skipped_undescribable);
  if (rep.readings_paired != rep.readings_used)
    std::printf("                 %zu of them paired, %zu surface contacts only\n", rep.readings_paired,
                rep.readings_used - rep.readings_paired);
  std::printf("  classes        %u (PAM loss %.4f, %.2f s, %.2f s CPU)\n", m.classes, rep.clustering_loss,
              rep.clustering_seconds, rep.clustering_cpu_seconds);
  std::printf("  ambiguity A    %.3f classes per reading\n", m.ambiguity);
  std::printf("  distance bins  %u over %g-%g mm\n", m.distance_bins, m.distance_min_mm, m.distance_max_mm);
  std::printf("  map            %zu entries under %zu keys, %.1f MB (%.2f bytes/entry), built in %.2f s (%.2f s CPU)\n",
              m.entries, m.keys, static_cast<double>(m.bytes) / 1e6,
              m.entries ? static_cast<double>(m.bytes) / static_cast<double>(m.entries) : 0.0, rep.map_build_seconds,
              rep.map_build_cpu_seconds);
  std::printf("  surfaces       %s\n", eval::describe_surfaces(m).c_str());
  std::printf("  calibration    %s (%.1f s)\n", eval::describe_calibration(m).c_str(), rep.calibration_seconds);
  if (!rep.calibration_note.empty()) std::printf("                 %s\n", rep.calibration_note.c_str());
}

}  // namespace

int cmd_train(const std::vector<std::string>& argv) {
  Args a(
      "sva train",
      "Build the SVA pair map: appearance classes (PAM on MN/MNTI descriptors) and every same-object pair of training "
      "readings under its (class, class, distance bin) keys. Defaults come from the dataset's scene.",
      argv);
  a.option("--data", "TRAIN", "training dataset (from sva simulate)");
  a.option("--out", "MAP", "map file to write");
  a.option("--descriptor", "mn|mnti", "appearance descriptor (default: the scene's)");
  a.option("--clusters", "N", "appearance classes n_C (default: the scene's, 25 for paper3d)");
  a.option("--dist-bins", "N", "distance bins (default: the scene's)");
  a.option("--dist-range", "MIN:MAX", "distance range in mm (default: the scene's)");
  a.option("--pair-readings", "N",
           "training readings per object that enter the pairs, drawn at random; the rest serve only as the object's "
           "surface (fine pose, surface check, planner). Default: the scene's, 0 = all");
  a.option("--seed", "S", "seed of the clustering's candidate order and of the paired readings' draw (default 1)");
  a.option("--threads", "N", "worker threads (default: SVA_THREADS or all cores); results do not depend on it");
  a.option("--exclude-objects", "NAME,...",
           "leave these objects out of the map (to evaluate \"none of these\" with sva eval --unknown-objects)");
  a.flag("--no-surfaces",
         "leave the objects' meshes out of the map (a dataset of a real sensor's recordings): the verify stage then "
         "reads the training contacts instead of the measurement model (docs/recognition.md)");
  a.flag("--no-calibration",
         "skip the calibration (the default temperature, no \"none of these\"; docs/recognition.md)");
  a.option("--calibration-sessions", "N", "held-out sessions on known objects that learn the calibration (default 60)");
  a.option("--calibration-readings", "N", "readings per calibration session (default 12)");
  a.option("--calibration-held-out", "F", "share of each object's readings held out for the calibration (default 0.1)");
  a.option("--fine-pose-from", "N",
           "readings from which the fine pose and the surface check run, kept in the map (default 6, planar 3; 4 names "
           "distinct objects right sooner and trusts twins less: docs/evaluation.md)");
  if (!a.parse()) return 0;
  const std::string data_file = a.required("--data");
  const std::string out_file = a.required("--out");
  TrainOptions o = train_options(a);

  Dataset data = load_dataset(data_file);
  if (auto names = a.get("--exclude-objects")) data = without_objects(data, comma_list(*names));
  if (!a.has("--no-surfaces")) {
    try {
      o.surfaces = sim::object_surfaces(data.scene);
    } catch (const Error& e) {
      throw Error(std::string("sva train: ") + e.what() +
                  " (--no-surfaces trains without the objects' meshes: the verify stage then reads the training "
                  "contacts)");
    }
  }
  // The scene's declared symmetries against its meshes' (docs/pose-errors.md): the evaluation's angle error reads
  // the declared ones.
  for (const std::string& w : eval::symmetry_warnings(data.scene))
    std::fprintf(stderr, "sva train: warning: %s\n", w.c_str());
  TrainReport rep;
  const Map map = Map::train(data, o, &rep);
  map.save(out_file);
  print_report(map.summary(), rep, out_file, data_file);
  return 0;
}

}  // namespace sva::cli
