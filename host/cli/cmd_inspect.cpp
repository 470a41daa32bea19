#include <sva/dataset.hpp>
#include <sva/eval/report.hpp>
#include <sva/io/binary_file.hpp>
#include <sva/map.hpp>

#include <cstdio>
#include <map>
#include <vector>

#include "args.hpp"

namespace sva::cli {

namespace {
void inspect_dataset(const std::string& file) {
  Dataset d = load_dataset(file);
  std::printf("%s: sva dataset (format 1)\n", file.c_str());
  std::printf("  scene      %s (%s pose space, protocol %s)\n", d.scene.name.c_str(),
              d.scene.pose_space.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial",
              d.scene.protocol.kind.c_str());
  std::printf("  split      %s, seed %llu\n", d.split.c_str(), static_cast<unsigned long long>(d.seed));
  std::printf("  sensor     %d x %d elements, %.2f mm pitch\n", d.scene.sensor.rows, d.scene.sensor.cols,
              d.scene.sensor.pitch_mm);
  std::printf("  readings   %zu (%zu converged)\n", d.samples.size(), d.count_converged());
  std::map<std::uint32_t, std::map<ControllerStatus, std::size_t>> per;
  std::map<std::uint32_t, double> mean_p, iters;
  for (const auto& s : d.samples) {
    per[s.object][s.reading.status]++;
    double sum = 0;
    for (float p : s.reading.pressure) sum += p;
    mean_p[s.object] += sum / static_cast<double>(s.reading.pressure.size());
    iters[s.object] += s.reading.iterations;
  }
  std::printf("  %-16s %8s %10s %8s %14s %12s\n", "object", "readings", "converged", "failed", "mean kPa/elem",
              "mean iters");
  for (std::uint32_t o = 0; o < d.scene.objects.size(); ++o) {
    std::size_t total = 0;
    for (auto& [st, n] : per[o]) total += n;
    std::size_t conv = per[o][ControllerStatus::converged];
    std::printf("  %-16s %8zu %10zu %8zu %14.2f %12.1f\n", d.scene.objects[o].name.c_str(), total, conv, total - conv,
                total ? mean_p[o] / static_cast<double>(total) : 0.0,
                total ? iters[o] / static_cast<double>(total) : 0.0);
  }
}
void inspect_map(const std::string& file) {
  const MapSummary m = Map::load(file).summary();
  std::printf("%s: sva map (format %u)\n", file.c_str(), m.format_version);
  std::printf("  scene          %s (%s pose space), scene hash %016llx, seed %llu\n", m.scene_name.c_str(),
              m.planar ? "planar" : "spatial", static_cast<unsigned long long>(m.scene_hash),
              static_cast<unsigned long long>(m.train_seed));
  std::printf("  descriptor     %s (%u values), T_a %.2f\n", m.descriptor == "mn" ? "MN" : "MNTI", m.descriptor_size,
              m.prune_ratio);
  std::printf("  objects        %zu\n", m.objects.size());
  std::printf("  classes        %u\n", m.classes);
  std::printf("  ambiguity A    %.3f classes per reading\n", m.ambiguity);
  std::printf("  calibration    %s\n", eval::describe_calibration(m).c_str());
  std::printf("  distance bins  %u over %g-%g mm\n", m.distance_bins, m.distance_min_mm, m.distance_max_mm);
  if (m.readings_paired == m.readings)
    std::printf("  readings       %zu\n", m.readings);
  else
    std::printf("  readings       %zu (%zu paired, %zu surface contacts only)\n", m.readings, m.readings_paired,
                m.readings - m.readings_paired);
  std::printf("  entries        %zu under %zu keys (of %llu possible)\n", m.entries, m.keys,
              static_cast<unsigned long long>(m.possible_keys));
  std::printf("  bytes          %zu (%.2f per entry)\n", m.bytes,
              m.entries ? static_cast<double>(m.bytes) / static_cast<double>(m.entries) : 0.0);
  std::printf("  surfaces       %s\n", eval::describe_surfaces(m).c_str());
  if (m.keys > 0)
    std::printf("  entries/key    min %u, median %u, max %u\n", m.entries_per_key_min, m.entries_per_key_median,
                m.entries_per_key_max);
  std::printf("  %-16s %8s %12s\n", "object", "readings", "entries");
  for (const MapSummary::Object& o : m.objects)
    std::printf("  %-16s %8zu %12zu\n", o.name.c_str(), o.readings, o.entries);
}
}  // namespace

int cmd_inspect(const std::vector<std::string>& argv) {
  Args a("sva inspect", "Summarise an sva file: a dataset (from sva simulate) or a map (from sva train).", argv);
  a.option("--file", "FILE", "the file to inspect (or give it as the only argument)");
  std::vector<std::string> rest = argv;
  std::string file;
  if (argv.size() == 1 && argv[0].rfind("-", 0) != 0) {
    file = argv[0];
  } else {
    if (!a.parse()) return 0;
    file = a.required("--file");
  }
  std::string magic = io::peek_magic(file);
  if (magic == "SVADATA1") {
    inspect_dataset(file);
    return 0;
  }
  if (magic == "SVAMAP01") {  // docs/map-format.md
    inspect_map(file);
    return 0;
  }
  // Not a known magic: let the dataset loader produce the precise message.
  load_dataset(file);
  return 1;
}

}  // namespace sva::cli
