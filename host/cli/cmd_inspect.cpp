#include <sva/dataset.hpp>
#include <sva/io/binary_file.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

#include "args.hpp"
#include "map/map_file.hpp"
#include "map/pair_map.hpp"

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
  const Map map = Map::load(file);
  const PairMap& m = map.internal();
  std::printf("%s: sva map (format %u)\n", file.c_str(), kMapVersion);
  std::printf("  scene          %s (%s pose space), scene hash %016llx, seed %llu\n", m.scene_name.c_str(),
              m.pose_space.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial",
              static_cast<unsigned long long>(m.scene_hash), static_cast<unsigned long long>(m.train_seed));
  std::printf("  descriptor     %s (%u values), T_a %.2f\n",
              m.appearance.descriptor == DescriptorKind::mn ? "MN" : "MNTI", m.appearance.descriptor_size,
              m.appearance.prune_ratio);
  std::printf("  objects        %zu\n", map.objects());
  std::printf("  classes        %u\n", map.classes());
  std::printf("  ambiguity A    %.3f classes per reading\n", m.ambiguity);
  std::printf("  distance bins  %u over %g-%g mm\n", m.distance.count, m.distance.min_mm, m.distance.max_mm);
  std::printf("  readings       %zu\n", map.readings());
  std::printf("  entries        %zu under %zu keys (of %llu possible)\n", map.entries(), map.keys(),
              static_cast<unsigned long long>(m.key_space.n_classes) * m.key_space.n_classes * m.key_space.n_dist_bins);
  std::printf("  bytes          %zu (%.2f per entry)\n", map.bytes(),
              map.entries() ? static_cast<double>(map.bytes()) / static_cast<double>(map.entries()) : 0.0);
  if (!m.keys.empty()) {
    std::vector<std::uint32_t> per(m.keys.size());
    for (std::size_t i = 0; i < per.size(); ++i) per[i] = m.offsets[i + 1] - m.offsets[i];
    std::sort(per.begin(), per.end());
    std::printf("  entries/key    min %u, median %u, max %u\n", per.front(), per[per.size() / 2], per.back());
  }
  std::vector<std::size_t> readings(m.objects.size(), 0), entries(m.objects.size(), 0);
  for (auto o : m.readings.object) ++readings[o];
  for (auto a : m.entry_a) ++entries[m.readings.object[a]];
  std::printf("  %-16s %8s %12s\n", "object", "readings", "entries");
  for (std::size_t o = 0; o < m.objects.size(); ++o)
    std::printf("  %-16s %8zu %12zu\n", m.objects[o].name.c_str(), readings[o], entries[o]);
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
  if (magic == std::string(kMapMagic, 8)) {
    inspect_map(file);
    return 0;
  }
  // Not a known magic: let the dataset loader produce the precise message.
  load_dataset(file);
  return 1;
}

}  // namespace sva::cli
