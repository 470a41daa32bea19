#include "map/map_builder.hpp"

#include <sva/base/interrupt.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/progress.hpp>
#include <sva/base/rng.hpp>
#include <sva/error.hpp>
#include <sva/io/binary_file.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <memory>
#include <numeric>

#include "appearance/descriptor.hpp"
#include "appearance/pam.hpp"
#include "appearance/soft_classes.hpp"
#include "map/pair_keys.hpp"

namespace sva {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
double cpu_seconds_since(std::clock_t c0) { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

// Eq 13's kernel against the arm's position error (docs/recognition.md, "Real
// errors"). Each end of a pair is off by sigma_p per axis, so a pair's distance
// is off by ~sqrt(2) sigma_p, and an observed pair's distance differs from the
// same training pair's by ~2 sigma_p. The linear interpolation between the two
// nearest centres, on both sides, matches them with a kernel of standard
// deviation w / sqrt(3) in that difference (two triangles of half-width w, the
// bin width, each of variance w^2 / 6). Bins narrower than 2 sqrt(3) sigma_p
// would cut true matches, so the scene's bin count is lowered until a bin is
// that wide; an ideal or accurate arm keeps the scene's bins.
int bins_for_position_error(int bins, double min_mm, double max_mm, double position_sigma_mm) {
  if (!(position_sigma_mm > 0)) return bins;
  const double widest = (max_mm - min_mm) / (2.0 * std::sqrt(3.0) * position_sigma_mm);
  return std::clamp(static_cast<int>(std::floor(widest)), 1, bins);
}

}  // namespace

void TrainOptions::validate(const std::string& context) const {
  auto fail = [&](const std::string& what) { throw Error(context + ": " + what); };
  if (descriptor && *descriptor != "mn" && *descriptor != "mnti")
    fail("descriptor \"" + *descriptor + "\": expected \"mn\" or \"mnti\"");
  if (clusters && (*clusters < 1 || *clusters > 4096))
    fail("clusters " + std::to_string(*clusters) + ": expected 1 to 4096");
  if (dist_bins && (*dist_bins < 1 || *dist_bins > 100000))
    fail("distance bins " + std::to_string(*dist_bins) + ": expected 1 to 100000");
  if (dist_min_mm.has_value() != dist_max_mm.has_value()) fail("distance range: give both its min and its max");
  if (dist_min_mm && (!std::isfinite(*dist_min_mm) || !std::isfinite(*dist_max_mm) || *dist_min_mm < 0 ||
                      *dist_min_mm >= *dist_max_mm))
    fail("distance range " + std::to_string(*dist_min_mm) + ":" + std::to_string(*dist_max_mm) +
         " mm: expected 0 <= min < max, both finite");
  if (threads > 1024) fail("threads " + std::to_string(threads) + ": expected 0 (all cores) to 1024");
  if (!(calibration_held_out > 0.0 && calibration_held_out <= 0.5))
    fail("calibration held-out share " + std::to_string(calibration_held_out) + ": expected a share in (0, 0.5]");
  if (calibration_sessions < 10 || calibration_sessions > 100000)
    fail("calibration sessions " + std::to_string(calibration_sessions) + ": expected 10 to 100000");
  if (calibration_readings < 2 || calibration_readings > 1000)
    fail("calibration readings " + std::to_string(calibration_readings) + ": expected 2 to 1000");
  if (fine_pose_from &&
      (*fine_pose_from < Calibration::kMinFinePoseFrom || *fine_pose_from > Calibration::kMaxFinePoseFrom))
    fail("fine pose from " + std::to_string(*fine_pose_from) + " readings: expected " +
         std::to_string(Calibration::kMinFinePoseFrom) + " to " + std::to_string(Calibration::kMaxFinePoseFrom));
  if (pair_readings && (*pair_readings == 1 || *pair_readings > 100000000))
    fail("pair readings " + std::to_string(*pair_readings) +
         " per object: expected 0 (all) or 2 to 100000000 (a pair needs two readings)");
}

TrainParameters resolve_train_parameters(const Scene& scene, const TrainOptions& o) {
  o.validate();
  TrainParameters p;
  const std::string desc = o.descriptor.value_or(scene.appearance.descriptor);
  if (desc == "mn")
    p.descriptor = DescriptorKind::mn;
  else if (desc == "mnti")
    p.descriptor = DescriptorKind::mnti;
  else
    throw Error("descriptor \"" + desc + "\": expected \"mn\" or \"mnti\"");
  const int clusters = o.clusters.value_or(scene.appearance.clusters);
  if (clusters < 1 || clusters > 4096) throw Error("clusters " + std::to_string(clusters) + ": expected 1 to 4096");
  p.clusters = static_cast<std::uint32_t>(clusters);
  int bins = o.dist_bins.value_or(scene.appearance.dist_bins);
  if (bins < 1 || bins > 100000) throw Error("distance bins " + std::to_string(bins) + ": expected 1 to 100000");
  p.distance.min_mm = o.dist_min_mm.value_or(scene.appearance.dist_min_mm);
  p.distance.max_mm = o.dist_max_mm.value_or(scene.appearance.dist_max_mm);
  if (!std::isfinite(p.distance.min_mm) || !std::isfinite(p.distance.max_mm) || p.distance.min_mm < 0 ||
      p.distance.min_mm >= p.distance.max_mm)
    throw Error("distance range " + std::to_string(p.distance.min_mm) + ":" + std::to_string(p.distance.max_mm) +
                " mm: expected 0 <= min < max, both finite");
  // A count given explicitly is kept; the scene's default follows the training scene's position error.
  if (!o.dist_bins)
    bins = bins_for_position_error(bins, p.distance.min_mm, p.distance.max_mm, scene.errors.position_sigma_mm);
  p.distance.count = static_cast<std::uint32_t>(bins);
  const int pair = o.pair_readings ? static_cast<int>(*o.pair_readings) : scene.appearance.pair_readings;
  if (pair == 1 || pair < 0)
    throw Error("pair readings " + std::to_string(pair) + " per object: expected 0 (all) or at least 2");
  p.pair_readings = static_cast<std::size_t>(pair);
  const std::uint64_t space = static_cast<std::uint64_t>(p.clusters) * p.clusters * p.distance.count;
  if (space > kMaxPairKeySpace)
    throw Error("clusters x clusters x distance bins = " + std::to_string(space) + " keys: more than the supported " +
                std::to_string(kMaxPairKeySpace));
  p.seed = o.seed;
  p.threads = o.threads;
  p.progress = o.progress;
  return p;
}

namespace {

// Where each object's paired readings end (readings are grouped by object): the rest are its surface contacts only.
std::vector<std::size_t> paired_ends(const MapReadings& rd, std::size_t objects, std::size_t pair_readings) {
  std::vector<std::size_t> first(objects + 1, 0);
  for (std::size_t i = 0; i < rd.size(); ++i) first[rd.object[i] + 1] = i + 1;
  for (std::size_t o = 1; o < first.size(); ++o) first[o] = std::max(first[o], first[o - 1]);
  std::vector<std::size_t> end(first.begin() + 1, first.end());
  if (pair_readings)
    for (std::size_t o = 0; o < end.size(); ++o) end[o] = std::min(end[o], first[o] + pair_readings);
  return end;
}

// Every entry of reading a (as the first of the pair; none past its object's paired readings), in a fixed order:
// b, then class of a, class of b, distance bin. Each unordered pair is stored once, as (a, b) with a < b: the other
// order is the same pair reversed, which the recognizer looks up under the reversed keys (for_each_query_key).
struct PairEntries {
  const PairMap& map;
  const std::vector<std::vector<ClassWeight>>& classes;
  std::vector<std::size_t> pair_end;

  template <class Emit>
  void operator()(std::size_t a, Emit&& emit) const {
    const MapReadings& rd = map.readings;
    const std::uint32_t obj = rd.object[a];
    const double ax = rd.px[a], ay = rd.py[a], az = rd.pz[a];
    for (std::size_t b = a + 1; b < pair_end[obj]; ++b) {
      const double dx = rd.px[b] - ax, dy = rd.py[b] - ay, dz = rd.pz[b] - az;
      const auto bins = map.distance.bins(std::sqrt(dx * dx + dy * dy + dz * dz));
      for_each_pair_key(classes[a], classes[b], bins, map.key_space,
                        [&](PairKeyWeight k) { emit(k.key, static_cast<std::uint32_t>(b), k.weight); });
    }
  }
};

// The counting sort's chunks: fixed ranges of readings (not one per thread), so that the entry order within a key,
// chunk by chunk, is the same for any thread count; each chunk counts into (then writes from) a table of the whole
// key space, so the key space bounds how many there are.
struct Chunks {
  std::size_t readings = 0, size = 0, count = 0;
  Chunks(std::size_t n, std::uint64_t space) : readings(n) {
    const std::size_t max_chunks = std::max<std::size_t>(1, (std::size_t{1} << 24) / space);
    size = std::max<std::size_t>(16, (n + max_chunks - 1) / max_chunks);
    count = n ? (n + size - 1) / size : 0;
  }
  std::size_t begin(std::size_t c) const { return c * size; }
  std::size_t end(std::size_t c) const { return std::min(readings, (c + 1) * size); }
};

// Pass 1: each chunk's entries per key, into cursor[c]; the total, refused past what 32-bit offsets allow.
std::uint64_t count_entries(const PairEntries& entries, const Chunks& chunks, std::uint64_t space,
                            std::vector<std::vector<std::uint32_t>>& cursor, unsigned threads, util::Progress* bar) {
  std::vector<std::uint64_t> chunk_total(chunks.count, 0);
  util::parallel_for(
      chunks.count,
      [&](std::size_t c) {
        auto& count = cursor[c];
        count.assign(space, 0);
        std::uint64_t total = 0;
        for (std::size_t a = chunks.begin(c); a < chunks.end(c); ++a)
          entries(a, [&](std::uint32_t key, std::uint32_t, float) {
            ++count[key];
            ++total;
          });
        chunk_total[c] = total;
        if (bar) bar->advance();
      },
      threads);
  std::uint64_t total = 0;
  for (auto t : chunk_total) total += t;
  if (total >= std::numeric_limits<std::uint32_t>::max())
    throw Error("the map would hold " + std::to_string(total) +
                " entries, more than 32-bit offsets allow: use fewer readings, classes or a narrower distance range");
  return total;
}

// The keys that have entries and their offsets, from the counts; each chunk's counts become where it writes.
void key_offsets(PairMap& map, std::uint64_t space, std::vector<std::vector<std::uint32_t>>& cursor) {
  map.keys.clear();
  map.offsets.assign(1, 0);
  std::uint32_t run = 0;
  for (std::uint64_t key = 0; key < space; ++key) {
    const std::uint32_t start = run;
    for (auto& chunk : cursor) {
      const std::uint32_t k = chunk[key];
      chunk[key] = run;
      run += k;
    }
    if (run != start) {
      map.keys.push_back(static_cast<std::uint32_t>(key));
      map.offsets.push_back(run);
    }
  }
}

// Pass 2: every entry at its place.
void write_entries(PairMap& map, const PairEntries& entries, const Chunks& chunks, std::uint64_t total,
                   std::vector<std::vector<std::uint32_t>>& cursor, unsigned threads, util::Progress* bar) {
  map.entry_a.assign(total, 0);
  map.entry_b.assign(total, 0);
  map.entry_weight.assign(total, 0.0f);
  util::parallel_for(
      chunks.count,
      [&](std::size_t c) {
        auto& pos = cursor[c];
        for (std::size_t a = chunks.begin(c); a < chunks.end(c); ++a)
          entries(a, [&](std::uint32_t key, std::uint32_t b, float w) {
            const std::uint32_t at = pos[key]++;
            map.entry_a[at] = static_cast<std::uint32_t>(a);
            map.entry_b[at] = b;
            map.entry_weight[at] = w;
          });
        std::vector<std::uint32_t>().swap(pos);
        if (bar) bar->advance();
      },
      threads);
}

}  // namespace

void build_pair_index(PairMap& map, const std::vector<std::vector<ClassWeight>>& classes, unsigned threads,
                      bool progress, std::size_t pair_readings) {
  const std::uint64_t space =
      static_cast<std::uint64_t>(map.key_space.n_classes) * map.key_space.n_classes * map.key_space.n_dist_bins;
  const PairEntries entries{map, classes, paired_ends(map.readings, map.objects.size(), pair_readings)};
  const Chunks chunks(map.readings.size(), space);  // a counting sort into CSR
  std::vector<std::vector<std::uint32_t>> cursor(chunks.count);
  std::unique_ptr<util::Progress> bar;
  if (progress) bar = std::make_unique<util::Progress>("map: pairs", 2 * chunks.count);
  const std::uint64_t total = count_entries(entries, chunks, space, cursor, threads, bar.get());
  key_offsets(map, space, cursor);
  write_entries(map, entries, chunks, total, cursor, threads, bar.get());
  if (bar) bar->finish();
}

namespace {

// The appearance model's fixed part: the sensor's calibration and the descriptor's sizes (the medoids and psi come
// from clustering).
AppearanceModel appearance_model_for(const Scene& scene, DescriptorKind descriptor) {
  AppearanceModel model;
  model.descriptor = descriptor;
  model.calibration.sensor = scene.sensor;
  model.calibration.stiffness_kpa_per_mm = scene.skin.stiffness_kpa_per_mm;
  model.calibration.contact_threshold_kpa = scene.skin.contact_threshold_kpa;
  if (!(model.calibration.stiffness_kpa_per_mm > 0))
    throw Error("scene \"" + scene.name + "\": skin stiffness must be positive");
  model.mn_size = static_cast<std::uint32_t>(std::max(scene.sensor.rows, scene.sensor.cols)) + 2;
  model.mnti_pad = 2 * model.mn_size;
  model.mnti_freqs = std::min<std::uint32_t>(4, model.mnti_pad / 2);
  model.descriptor_size = descriptor == DescriptorKind::mn ? model.mn_size * model.mn_size
                                                           : appearance::fourier_magnitude_count(model.mnti_freqs);
  return model;
}

// The samples training uses (converged, describable), grouped by object and stable within one; every object
// needs at least one.
std::vector<std::size_t> usable_samples(const Dataset& data, const AppearanceModel& model, TrainReport& rep) {
  const Scene& scene = data.scene;
  std::vector<std::size_t> use;
  std::vector<std::size_t> per_object(scene.objects.size(), 0);
  for (std::uint32_t o = 0; o < scene.objects.size(); ++o)
    for (std::size_t i = 0; i < data.samples.size(); ++i) {
      const Reading& r = data.samples[i].reading;
      if (data.samples[i].object != o) continue;
      if (r.status != ControllerStatus::converged) {
        ++rep.skipped_not_converged;
        continue;
      }
      if (!model.why_not_describable(r).empty()) {
        ++rep.skipped_undescribable;
        continue;
      }
      use.push_back(i);
      ++per_object[o];
    }
  for (std::uint32_t o = 0; o < scene.objects.size(); ++o)
    if (per_object[o] == 0)
      throw Error("object \"" + scene.objects[o].name + "\" has no usable training reading (converged, with contact)");
  return use;
}

// Puts each object's paired readings first in its group of `use` (grouped by object): `pair_readings` of them drawn
// at random (seeded; every one when the object has no more), both parts kept in dataset order. A random draw, not
// the first ones, so that a dataset recorded sweep by sweep still pairs readings from all over each object.
// Returns how many readings pair.
std::size_t put_paired_first(std::vector<std::size_t>& use, const Dataset& data, std::size_t pair_readings,
                             std::uint64_t seed) {
  if (pair_readings == 0) return use.size();
  std::size_t paired = 0;
  for (std::size_t begin = 0; begin < use.size();) {
    const std::uint32_t object = data.samples[use[begin]].object;
    std::size_t end = begin;
    while (end < use.size() && data.samples[use[end]].object == object) ++end;
    const std::size_t m = end - begin, k = std::min(m, pair_readings);
    std::vector<std::size_t> order(m);
    std::iota(order.begin(), order.end(), std::size_t{0});
    util::Rng rng(seed, 0x9a17ed, object);
    for (std::size_t i = 0; i < k; ++i) std::swap(order[i], order[i + rng.below(m - i)]);
    std::vector<char> chosen(m, 0);
    for (std::size_t i = 0; i < k; ++i) chosen[order[i]] = 1;
    std::vector<std::size_t> group;
    group.reserve(m);
    for (char want : {1, 0})
      for (std::size_t i = 0; i < m; ++i)
        if (chosen[i] == want) group.push_back(use[begin + i]);
    std::copy(group.begin(), group.end(), use.begin() + static_cast<std::ptrdiff_t>(begin));
    paired += k;
    begin = end;
  }
  return paired;
}

// Fills the map's reading table (object frame positions and normals, normConf) and returns the descriptors, one
// row of model.descriptor_size per used sample.
std::vector<float> describe_training_readings(const Dataset& data, const std::vector<std::size_t>& use,
                                              const AppearanceModel& model, const TrainParameters& p, MapReadings& rd) {
  const std::size_t n = use.size();
  rd.object.resize(n);
  for (auto* v : {&rd.px, &rd.py, &rd.pz, &rd.nx, &rd.ny, &rd.nz, &rd.norm_conf}) v->resize(n);
  const std::uint32_t dim = model.descriptor_size;
  std::vector<float> descriptors(n * dim);
  std::unique_ptr<util::Progress> bar;
  if (p.progress) bar = std::make_unique<util::Progress>("describe", n);
  util::parallel_for(
      n,
      [&](std::size_t j) {
        const Sample& s = data.samples[use[j]];
        const Reading& r = s.reading;
        // Positions and normals in the object frame (the pose the object had
        // when the reading was taken; identity in simulation).
        const RigidPose inv = s.object_pose.inverse();
        const glm::dvec3 pos = inv.apply(r.position);
        glm::dvec3 nrm = inv.rotate(r.normal);
        const double len = glm::length(nrm);
        if (!(len > 0) || !std::isfinite(len))
          throw Error("training reading " + std::to_string(use[j]) + " has a zero normal");
        nrm /= len;
        rd.object[j] = s.object;
        rd.px[j] = static_cast<float>(pos.x), rd.py[j] = static_cast<float>(pos.y),
        rd.pz[j] = static_cast<float>(pos.z);
        rd.nx[j] = static_cast<float>(nrm.x), rd.ny[j] = static_cast<float>(nrm.y),
        rd.nz[j] = static_cast<float>(nrm.z);
        if (!std::isfinite(rd.px[j]) || !std::isfinite(rd.py[j]) || !std::isfinite(rd.pz[j]))
          throw Error("training reading " + std::to_string(use[j]) + " has a position out of float range");
        rd.norm_conf[j] = model.norm_conf(r);
        const auto d = model.describe(r);
        std::copy(d.begin(), d.end(), descriptors.begin() + static_cast<std::ptrdiff_t>(j * dim));
        if (bar) bar->advance();
      },
      p.threads);
  if (bar) bar->finish();
  return descriptors;
}

// The descriptor rows of the readings that pair (each object's first `pair_readings`, > 0): the appearance classes
// are the pairs' keys, so they are clustered from those (and PAM's cost stays that of the pairs).
std::vector<float> paired_rows(const std::vector<float>& descriptors, const MapReadings& rd, std::size_t pair_readings,
                               std::uint32_t dim) {
  std::vector<float> rows;
  std::size_t in_object = 0;
  for (std::size_t j = 0; j < rd.size(); ++j) {
    in_object = j > 0 && rd.object[j] == rd.object[j - 1] ? in_object + 1 : 0;
    if (in_object < pair_readings)
      rows.insert(rows.end(), descriptors.begin() + static_cast<std::ptrdiff_t>(j * dim),
                  descriptors.begin() + static_cast<std::ptrdiff_t>((j + 1) * dim));
  }
  return rows;
}

// Appearance classes (PAM, Eq 7-9): the medoids and psi go into the model; returns the number of classes.
std::uint32_t cluster_appearance(const std::vector<float>& descriptors, const TrainParameters& p,
                                 AppearanceModel& model, TrainReport& rep) {
  const std::uint32_t dim = model.descriptor_size;
  const auto t0 = std::chrono::steady_clock::now();
  const auto c0 = std::clock();
  appearance::PamOptions po;
  po.k = p.clusters;
  po.seed = p.seed;
  po.threads = p.threads;
  po.progress = p.progress;
  const auto clusters = appearance::pam(descriptors, dim, po);
  rep.clustering_seconds = seconds_since(t0);
  rep.clustering_cpu_seconds = cpu_seconds_since(c0);
  rep.clustering_loss = clusters.loss;
  const auto k = static_cast<std::uint32_t>(clusters.medoids.size());
  model.medoids.resize(static_cast<std::size_t>(k) * dim);
  for (std::uint32_t i = 0; i < k; ++i)
    std::copy_n(&descriptors[static_cast<std::size_t>(clusters.medoids[i]) * dim], dim,
                &model.medoids[static_cast<std::size_t>(i) * dim]);
  model.psi = appearance::cluster_psi(descriptors, model.medoids, clusters.membership, dim);
  return k;
}

}  // namespace

std::uint64_t location_free_scene_hash(Scene scene) {
  for (auto& o : scene.objects) o.mesh = o.mesh.filename();
  const std::string json = scene_to_json(scene);
  return io::fnv1a64(reinterpret_cast<const std::uint8_t*>(json.data()), json.size());
}

std::shared_ptr<PairMap> train_pair_map(const Dataset& data, const TrainParameters& p, TrainReport* report) {
  TrainReport rep;
  const Scene& scene = data.scene;
  if (scene.objects.empty()) throw Error("dataset has no objects");
  if (data.samples.empty()) throw Error("dataset has no readings");
  auto map = std::make_shared<PairMap>();
  map->scene_name = scene.name;
  map->pose_space = scene.pose_space;
  map->scene_hash = location_free_scene_hash(scene);
  map->train_seed = p.seed;
  for (const auto& o : scene.objects) map->objects.push_back({o.name, o.symmetry, o.inertial_radius_mm});

  AppearanceModel& model = map->appearance;
  model = appearance_model_for(scene, p.descriptor);
  std::vector<std::size_t> use = usable_samples(data, model, rep);
  const std::size_t n = use.size();
  rep.readings_used = n;
  rep.readings_paired = put_paired_first(use, data, p.pair_readings, p.seed);
  const std::vector<float> descriptors = describe_training_readings(data, use, model, p, map->readings);
  const std::vector<float> paired =
      p.pair_readings ? paired_rows(descriptors, map->readings, p.pair_readings, model.descriptor_size)
                      : std::vector<float>{};
  const std::uint32_t k = cluster_appearance(p.pair_readings ? paired : descriptors, p, model, rep);

  const auto t0 = std::chrono::steady_clock::now();
  const auto c0 = std::clock();
  const std::uint32_t dim = model.descriptor_size;
  std::vector<std::vector<ClassWeight>> classes(n);
  util::parallel_for(
      n,
      [&](std::size_t j) {
        classes[j] = appearance::soft_classes(&descriptors[j * dim], model.medoids, model.psi, dim, model.prune_ratio);
      },
      p.threads);
  std::size_t class_count = 0;
  for (const auto& c : classes) class_count += c.size();
  map->ambiguity = static_cast<double>(class_count) / static_cast<double>(n);

  map->distance = p.distance;
  map->key_space = {k, p.distance.count};
  build_pair_index(*map, classes, p.threads, p.progress, p.pair_readings);
  map->baseline =
      AppearanceBaseline::fit(static_cast<std::uint32_t>(scene.objects.size()), k, map->readings.object, classes);
  rep.map_build_seconds = seconds_since(t0);
  rep.map_build_cpu_seconds = cpu_seconds_since(c0);
  if (report) *report = rep;
  return map;
}

}  // namespace sva
