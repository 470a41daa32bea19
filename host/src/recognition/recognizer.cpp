// The public Recognizer: describes each raw reading with the map's appearance
// model, then hands it to the Bayes filter (Method::sva) or to the
// appearance-only baseline (Method::appearance).
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <cmath>
#include <string>

#include "appearance/appearance_baseline.hpp"
#include "map/pair_map.hpp"
#include "recognition/bayes_filter.hpp"
#include "recognition/describe_reading.hpp"
#include "recognition/pose_space.hpp"
#include "recognition/vote_backend.hpp"
#include "vulkan/vulkan_vote_backend.hpp"

namespace sva {

struct Recognizer::Impl {
  Map map;  // keeps the shared PairMap alive
  const PairMap* pair_map = nullptr;
  RecognizerOptions options;
  PoseSpace space;
  std::unique_ptr<VoteBackend> backend;
  std::unique_ptr<BayesFilter> filter;
  std::vector<double> appearance_log_posterior;
  std::size_t readings = 0;
  std::uint64_t last_votes = 0;

  Impl(const Map& m, const PoseSpaceSpec& spec, const RecognizerOptions& o)
      : map(m), pair_map(&m.internal()), options(o),
        space(spec, static_cast<std::uint32_t>(m.internal().objects.size())) {}

  ObservedReading observe(const Reading& r) const {
    return describe_reading(*pair_map, r, "reading " + std::to_string(readings + 1));
  }
};

Recognizer::Recognizer(const Map& map, const PoseSpaceSpec& pose_space, const RecognizerOptions& options) {
  if (map.empty()) throw Error("recognizer: the map is empty (not trained or not loaded)");
  if (pose_space.kind != map.pose_space().kind)
    throw Error(std::string("recognizer: the pose space is ") +
                (pose_space.kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial") + " but map '" +
                map.scene_name() + "' was trained for a " +
                (map.pose_space().kind == PoseSpaceSpec::Kind::planar ? "planar" : "spatial") + " scene");
  if (!(options.likelihood_cutoff >= 0.0f) || !std::isfinite(options.likelihood_cutoff))
    throw Error("recognizer option likelihood_cutoff = " + std::to_string(options.likelihood_cutoff) +
                " must be a finite number >= 0");
  impl_ = std::make_unique<Impl>(map, pose_space, options);
  if (options.method == Method::sva) {
    VoteSettings vs;
    vs.likelihood_cutoff = options.likelihood_cutoff;
    vs.threads = options.threads;
    if (options.backend == BackendKind::vulkan) {
      VulkanBackendOptions vo;
      vo.device = options.vulkan_device;
      impl_->backend = make_vulkan_vote_backend(*impl_->pair_map, impl_->space, vs, vo);
    } else {
      impl_->backend = make_cpu_vote_backend(*impl_->pair_map, impl_->space, vs);
    }
    FilterOptions fo;
    fo.eps = options.eps;
    fo.object_prune_probability = options.object_prune_probability;
    fo.max_pairs_per_update = options.max_pairs_per_update;
    impl_->filter = std::make_unique<BayesFilter>(*impl_->pair_map, impl_->space, fo);
  } else {
    if (impl_->pair_map->baseline.n_objects != impl_->pair_map->objects.size())
      throw Error("recognizer: map '" + map.scene_name() + "' has no appearance baseline");
    impl_->appearance_log_posterior.assign(impl_->pair_map->objects.size(), 0.0);
  }
}

Recognizer::~Recognizer() = default;
Recognizer::Recognizer(Recognizer&&) noexcept = default;
Recognizer& Recognizer::operator=(Recognizer&&) noexcept = default;

void Recognizer::add_reading(const Reading& reading) {
  const ObservedReading o = impl_->observe(reading);
  if (impl_->filter) {
    impl_->last_votes = impl_->filter->add(o, *impl_->backend).votes;
  } else {
    impl_->pair_map->baseline.update(impl_->appearance_log_posterior, o.classes);
    impl_->last_votes = 0;
  }
  ++impl_->readings;
}

Estimate Recognizer::estimate(std::size_t top_k) const {
  Estimate e;
  e.readings = impl_->readings;
  e.votes = impl_->last_votes;
  const auto& objects = impl_->pair_map->objects;
  if (!impl_->filter) {
    e.object_probability = AppearanceBaseline::posterior(impl_->appearance_log_posterior);
    for (std::uint32_t o = 1; o < e.object_probability.size(); ++o)
      if (e.object_probability[o] > e.object_probability[e.object]) e.object = o;
    e.object_name = objects[e.object].name;
    return e;
  }
  const BeliefEstimate b = impl_->filter->estimate(top_k);
  e.object = b.object;
  e.object_name = objects[b.object].name;
  e.object_probability = b.object_probability;
  e.pose_valid = b.pose_valid;
  e.pose = b.pose;
  e.bin_pose = b.bin_pose;
  for (const BinHypothesis& h : b.top) {
    Hypothesis out;
    out.object = h.object;
    out.object_name = objects[h.object].name;
    out.pose = h.pose;
    out.probability = h.probability;
    e.top.push_back(out);
  }
  const UpdateStats& st = impl_->filter->last_update();
  e.votes_outside = st.votes_outside;
  return e;
}

void Recognizer::reset() {
  impl_->readings = 0;
  impl_->last_votes = 0;
  if (impl_->filter) impl_->filter->reset();
  std::fill(impl_->appearance_log_posterior.begin(), impl_->appearance_log_posterior.end(), 0.0);
}

std::size_t Recognizer::readings() const { return impl_->readings; }

}  // namespace sva
