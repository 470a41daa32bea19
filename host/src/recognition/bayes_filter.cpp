#include "recognition/bayes_filter.hpp"

#include "belief/belief_math.hpp"
#include "belief/object_mass.hpp"
#include "map/pair_keys.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace sva {

BayesFilter::BayesFilter(const PairMap& map, const PoseSpace& space, const FilterOptions& options, VoteBackend& backend)
    : map_(&map), space_(&space), options_(options), backend_(&backend) {
  check_options(map, space, options);
  belief_ = backend.make_belief(space, options.eps);
  max_pairs_ = belief_math::max_pairs(belief_math::eps_units(options.eps));
}

BayesFilter::BayesFilter(const PairMap& map, const PoseSpace& space, const FilterOptions& options, VoteBackend& backend,
                         std::unique_ptr<BeliefState> belief)
    : map_(&map),
      space_(&space),
      options_(options),
      backend_(&backend),
      belief_(std::move(belief)),
      max_pairs_(belief_math::max_pairs(belief_math::eps_units(options.eps))) {}

std::vector<std::unique_ptr<BayesFilter>> BayesFilter::make_sessions(const PairMap& map, const PoseSpace& space,
                                                                     const FilterOptions& options, VoteBackend& backend,
                                                                     std::size_t n) {
  check_options(map, space, options);
  std::vector<std::unique_ptr<BeliefState>> beliefs = backend.make_beliefs(space, options.eps, n);
  std::vector<std::unique_ptr<BayesFilter>> made;
  for (auto& b : beliefs)
    made.push_back(std::unique_ptr<BayesFilter>(new BayesFilter(map, space, options, backend, std::move(b))));
  return made;
}

void BayesFilter::check_options(const PairMap& map, const PoseSpace& space, const FilterOptions& options) {
  if (space.objects() != map.objects.size())
    throw Error("pose space has " + std::to_string(space.objects()) + " objects but the map has " +
                std::to_string(map.objects.size()));
  if (!(options.object_prune_probability >= 0.0 && options.object_prune_probability < 1.0))
    throw Error("recognizer option object_prune_probability = " + std::to_string(options.object_prune_probability) +
                " must be in [0, 1)");
  if (options.max_pairs_per_update < 0)
    throw Error("recognizer option max_pairs_per_update = " + std::to_string(options.max_pairs_per_update) +
                " must be >= 0");
  // Below the band width a forgotten bin could still weigh in the estimate; far above it the shift overflows.
  const unsigned band_bits = belief_math::mass_bits(space.bins_per_object()) + 1;
  if (options.forget_margin_bits < band_bits || options.forget_margin_bits > (1u << 20))
    throw Error("recognizer option forget_margin_bits = " + std::to_string(options.forget_margin_bits) +
                " must be in [" + std::to_string(band_bits) + ", 1048576] for this pose space (bits of evidence)");
}

void BayesFilter::reset() {
  BayesFilter* self = this;
  reset_all(std::span(&self, 1));
}

void BayesFilter::reset_all(std::span<BayesFilter* const> sessions) {
  if (sessions.empty()) return;
  std::vector<BeliefState*> beliefs;
  for (BayesFilter* f : sessions) {
    if (f->backend_ != sessions.front()->backend_)
      throw std::logic_error("BayesFilter::reset_all: sessions of two backends");
    beliefs.push_back(f->belief_.get());
  }
  try {
    sessions.front()->backend_->reset_beliefs(beliefs);
  } catch (...) {
    // Some beliefs may be emptied and others not, beside readings kept: each session refuses use until a reset works.
    for (BayesFilter* f : sessions) f->incomplete_ = true;
    throw;
  }
  for (BayesFilter* f : sessions) {
    f->kept_after_forget_ = 0;
    f->readings_.clear();
    f->last_ = {};
    f->incomplete_ = false;
  }
}

void BayesFilter::require_complete() const {
  if (incomplete_)
    throw Error(
        "recognition session was interrupted during an update (its belief holds part of that update's pairs): "
        "reset the session");
}

namespace {
ObservedPatch observed_patch(const ObservedReading& r) {
  ObservedPatch p;
  for (int k = 0; k < 3; ++k) {
    p.position[k] = static_cast<float>(r.position[k]);
    p.normal[k] = static_cast<float>(r.normal[k]);
  }
  p.norm_conf = r.norm_conf;
  return p;
}
}  // namespace

void BayesFilter::queue_pairs(const ObservedReading& reading, std::uint32_t session, VoteBatch* batch) const {
  // Earlier readings, most recent first, so that a cap keeps the newest pairs.
  const std::size_t t = readings_.size();
  const std::size_t budget =
      options_.max_pairs_per_update > 0 ? static_cast<std::size_t>(options_.max_pairs_per_update) : 2 * t;
  // Session row of the object mask.
  if (options_.object_prune_probability > 0.0 && belief_->pairs_folded() > 0) {
    const std::vector<double> p = object_probability(belief_->summarise(), *space_);
    if (batch->object_active.size() < std::size_t{session + 1} * space_->objects())
      batch->object_active.resize(std::size_t{session + 1} * space_->objects(), 1);
    for (std::uint32_t o = 0; o < space_->objects(); ++o)
      batch->object_active[std::size_t{session} * space_->objects() + o] = p[o] >= options_.object_prune_probability;
  }
  batch->sessions = std::max(batch->sessions, session + 1);
  if (belief_->pairs_folded() + budget > max_pairs_)
    throw Error("recognition session has folded " + std::to_string(belief_->pairs_folded()) +
                " pairs; more could overflow its fixed-point belief (reset the session or cap max_pairs_per_update)");
  // Eq 5 multiplies the factors of pair(z_i, z_t) and pair(z_t, z_i). The map
  // holds both orders of every training pair, and the vote math is symmetric by
  // construction (sva_align, sva_beta_offset, sva_sincos): the reversed pair
  // casts bit for bit the same votes. So one order is voted and folded twice
  // (fold_count 2); an odd budget folds its last pair once, as before.
  std::size_t queued = 0;  // ordered pairs
  for (std::size_t j = 0; j < t && queued < budget; ++j) {
    const ObservedReading& a = readings_[t - 1 - j];
    PairQuery q;
    q.a = observed_patch(a);
    q.b = observed_patch(reading);
    q.session = session;
    q.fold_count = static_cast<std::uint32_t>(std::min<std::size_t>(2, budget - queued));
    q.key_begin = static_cast<std::uint32_t>(batch->keys.size());
    const double d = glm::length(reading.position - a.position);
    if (d >= SVA_MIN_PAIR_SEPARATION_MM)  // coincident points define no axis: no keys, no vote
      for_each_query_key(a.classes, reading.classes, map_->distance.bins(d), map_->key_space,
                         [&](PairKeyWeight k) { batch->keys.push_back(k); });
    q.key_end = static_cast<std::uint32_t>(batch->keys.size());
    batch->pairs.push_back(q);
    queued += q.fold_count;
  }
}

UpdateStats BayesFilter::record(const ObservedReading& reading, const PairQuery* queries, const PairStats* pairs,
                                std::size_t count) {
  UpdateStats st;
  st.pairs_voted = count;
  for (std::size_t i = 0; i < count; ++i) {
    st.pairs += queries[i].fold_count;
    st.matches += pairs[i].matches;
    st.votes += pairs[i].votes;
    st.votes_outside += pairs[i].votes_outside;
    st.votes_zero += pairs[i].votes_zero;
    if (pairs[i].folded) st.pairs_folded += queries[i].fold_count;
  }
  readings_.push_back(reading);
  last_ = st;
  return st;
}

UpdateStats BayesFilter::add(const ObservedReading& reading) { return update_sessions({this}, {reading})[0]; }

std::vector<UpdateStats> update_sessions(const std::vector<BayesFilter*>& sessions,
                                         const std::vector<ObservedReading>& readings) {
  if (sessions.size() != readings.size()) throw Error("update_sessions: one reading per session is required");
  if (sessions.empty()) return {};
  VoteBackend& backend = sessions.front()->backend();
  for (const BayesFilter* f : sessions)
    if (&f->map() != &sessions.front()->map() || &f->space() != &sessions.front()->space() || &f->backend() != &backend)
      throw Error("update_sessions: all sessions of a batch must share one map, pose space and backend");
  for (const BayesFilter* f : sessions) f->require_complete();
  const std::vector<ObservedReading>& valid = readings;
  VoteBatch batch;
  std::vector<std::size_t> first(sessions.size() + 1, 0);
  for (std::size_t s = 0; s < sessions.size(); ++s) {
    first[s] = batch.pairs.size();
    sessions[s]->queue_pairs(valid[s], static_cast<std::uint32_t>(s), &batch);
  }
  first[sessions.size()] = batch.pairs.size();
  if (!batch.object_active.empty())
    batch.object_active.resize(std::size_t{batch.sessions} * sessions.front()->space().objects(), 1);
  std::vector<BeliefState*> beliefs;
  for (BayesFilter* f : sessions) beliefs.push_back(&f->mutable_belief());
  std::vector<PairStats> stats;
  try {
    if (!batch.pairs.empty()) stats = backend.vote_and_fold(batch, beliefs);
  } catch (...) {
    for (BayesFilter* f : sessions) f->mark_incomplete();
    throw;
  }
  std::vector<UpdateStats> out;
  for (std::size_t s = 0; s < sessions.size(); ++s) {
    out.push_back(
        sessions[s]->record(valid[s], batch.pairs.data() + first[s], stats.data() + first[s], first[s + 1] - first[s]));
    out.back().bins_forgotten = sessions[s]->keep_within_budget();
  }
  return out;
}

std::size_t BayesFilter::keep_within_budget() {
  // Past the budget, and past a quarter more than the last forgetting left (bins within the margin are kept, so a
  // belief may stay above its budget: this bounds the passes over the table to one per quarter of growth).
  const std::size_t threshold = std::max(options_.belief_budget_bins, kept_after_forget_ + kept_after_forget_ / 4);
  if (options_.belief_budget_bins == 0 || belief_->touched() <= threshold) return 0;
  const std::uint64_t margin = std::uint64_t{options_.forget_margin_bits} << SVA_BELIEF_FRAC_BITS;
  const BeliefSummary summary = belief_->summarise();
  const std::uint64_t max = summary.max_offset;
  if (max <= margin) return 0;  // every bin is within the margin: nothing is hopeless yet
  // The estimate reads each object's best bin and its neighbours (the sub-bin pose, the modes): keep them.
  std::vector<std::uint64_t> keep;
  for (std::size_t o = 0; o < summary.touched.size(); ++o)
    if (summary.touched[o] > 0)
      space_->for_each_neighbour(summary.best_key[o], [&](std::uint64_t k) { keep.push_back(k); });
  std::sort(keep.begin(), keep.end());
  keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
  const std::size_t forgotten = belief_->forget_below(max - margin, keep);
  kept_after_forget_ = belief_->touched();
  last_.bins_forgotten = forgotten;
  return forgotten;
}

}  // namespace sva
