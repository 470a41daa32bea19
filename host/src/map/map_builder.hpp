#pragma once
// Training: descriptors of every usable training reading, PAM appearance
// classes, soft classes, then every ordered same-object pair in the distance
// range under each of its (class a, class b, distance bin) keys.
#include <sva/dataset.hpp>
#include <sva/map.hpp>

#include "map/pair_map.hpp"

namespace sva {

// The resolved training parameters (options over scene defaults), validated.
struct TrainParameters {
  DescriptorKind descriptor = DescriptorKind::mnti;
  std::uint32_t clusters = 25;
  DistanceBins distance;
  std::size_t pair_readings = 0;  // per object; 0: all (TrainOptions::pair_readings)
  std::uint64_t seed = 1;
  unsigned threads = 0;
  bool progress = false;
};
TrainParameters resolve_train_parameters(const Scene& scene, const TrainOptions& options);

// The scene's identity for matching maps, datasets and saved sessions: FNV-1a of its JSON with each mesh named by its
// file name, not by the folder it lay in, so that the same scene trained in two checkouts (or on two machines) gives
// the same map bytes (docs/reliability.md, "Same answers on every machine").
std::uint64_t location_free_scene_hash(Scene scene);

// The pair entries and CSR index for readings whose appearance classes are
// known (`classes[i]` for reading i of map.readings); fills map.keys, offsets
// and entries. Each object's readings pair among its first `pair_readings`
// (0: all of them); the rest take part in no pair. Deterministic for any
// thread count.
void build_pair_index(PairMap& map, const std::vector<std::vector<ClassWeight>>& classes, unsigned threads,
                      bool progress, std::size_t pair_readings = 0);

std::shared_ptr<PairMap> train_pair_map(const Dataset& data, const TrainParameters& params, TrainReport* report);

}  // namespace sva
