#include "backends/vulkan/gpu_belief.hpp"

#include <sva/error.hpp>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "backends/vulkan/gpu_layout.hpp"
#include "belief/belief_math.hpp"
#include "votes/neighbourhood_steps.hpp"

static_assert(sva::kPriorDeviceFloats == SVA_PRIOR_FLOATS && sva::kPriorMostCandidates == SVA_PRIOR_MOST_CANDIDATES,
              "KeyChoice's priors as belief_hoods.comp reads them");

namespace sva {

namespace {

using gpu::ensure;
using gpu::hi;
using gpu::lo;
using gpu::push_bytes;

// The most slots a table may have (its index is a 32-bit uint in the shaders).
constexpr std::uint64_t kMaxSlots = std::uint64_t{1} << 31;

// The state's words: the fixed ones, the per-object arrays, the band's histogram and the table's.
std::size_t state_words(std::uint32_t objects) {
  return SVA_STATE_OBJECTS + SVA_STATE_ARRAYS * std::size_t{objects} + 2 * SVA_BELIEF_BUCKETS;
}
std::size_t object_word(std::uint32_t array, std::uint32_t objects) {
  return SVA_STATE_OBJECTS + std::size_t{array} * objects;
}
// The first word of the table's histogram (sva_state_table_bucket).
std::size_t table_histogram_word(std::uint32_t objects) {
  return object_word(SVA_STATE_ARRAYS, objects) + SVA_BELIEF_BUCKETS;
}
// Per-object arrays of the state (sva_belief_table.glsl).
constexpr std::uint32_t kTouched = 0, kBestOffset = 1, kBestKey = 2, kMass = 4;
// Entries per side of a new band list.
constexpr std::uint32_t kInitialBand = 1 << 12;

}  // namespace

std::uint64_t slot_invocations(std::uint64_t slots) {
  return (slots + SVA_SLOTS_PER_INVOCATION - 1) / SVA_SLOTS_PER_INVOCATION;
}

GpuBelief::GpuBelief(GpuBeliefKernels& kernels, double eps)
    : k_(&kernels),
      eps_units_(belief_math::eps_units(eps)),
      mass_bits_(belief_math::mass_bits(kernels.space->bins_per_object())),
      // sva_exp2_neg_units(d, mass_bits) is 0 from d = (mass_bits + 1) 2^32 on (as backends/cpu/belief.cpp).
      band_width_((std::uint64_t{mass_bits_} + 1) << 32) {}

std::uint64_t GpuBelief::bytes_at(std::uint64_t bins, std::uint32_t objects) {
  const std::uint64_t slots = std::bit_ceil(std::max<std::uint64_t>(2 * bins, 64));
  const std::uint64_t table = 2 * slots * sizeof(std::uint64_t) + slots / 32 * sizeof(std::uint32_t);
  return table + 2 * slots * sizeof(std::uint32_t) + state_words(objects) * sizeof(std::uint64_t);
}

std::size_t GpuBelief::table_bytes() const {
  return static_cast<std::size_t>(table_.size() + band_.size() + state_.size());
}

void GpuBelief::allocate_uncleared(vk::Buffer& b, std::uint32_t capacity) const {
  // The device's own memory: only kernels touch a belief.
  const std::size_t keys = std::size_t{capacity} * sizeof(std::uint64_t);
  b = k_->ctx->create_uncleared_device_buffer(2 * keys + capacity / 32 * sizeof(std::uint32_t));
  ++table_allocations_;
}

std::vector<vk::Fill> GpuBelief::clear_fills(vk::Buffer& b, std::uint64_t capacity) {
  const std::size_t keys = static_cast<std::size_t>(capacity) * sizeof(std::uint64_t);
  return {{&b, 0xffffffffu, 0, keys}, {&b, 0u, keys, 0}};
}

void GpuBelief::reset() {
  GpuBelief* self = this;
  reset_all(std::span(&self, 1));
}

void GpuBelief::reset_all(std::span<GpuBelief* const> beliefs) {
  if (beliefs.empty()) return;
  std::vector<vk::Fill> fills;
  for (GpuBelief* b : beliefs) {
    if (b->k_ != beliefs.front()->k_)
      throw std::logic_error("GpuBelief::reset_all: beliefs of two backends in one submission");
    const std::vector<vk::Fill> f = b->prepare_reset();
    fills.insert(fills.end(), f.begin(), f.end());
  }
  run(*beliefs.front()->k_, {}, fills);
  for (GpuBelief* b : beliefs) {
    b->band_stale_ = false;
    b->count_ = 0;
    b->pairs_ = 0;
    b->drop_floor();
    b->forget_cache();
  }
}

std::vector<vk::Fill> GpuBelief::prepare_reset() {
  // A reset session keeps its table and band list (emptied): the next session allocates none until it outgrows them.
  // New buffers are left uncleared: the fills below write every word that is read (the band list is read only up to
  // its count, a state word), and a cleared buffer cost a submission of its own on a GPU.
  if (table_.size() == 0) {
    capacity_ = static_cast<std::uint32_t>(std::bit_ceil(std::max<std::size_t>(k_->initial_slots, 64)));
    allocate_uncleared(table_, capacity_);
  }
  std::vector<vk::Fill> fills = clear_fills(table_, capacity_);
  const std::uint32_t objects = k_->space->objects();
  if (state_.size() == 0)
    state_ = k_->ctx->create_uncleared_device_buffer(state_words(objects) * sizeof(std::uint64_t));
  if (band_.size() == 0) {
    band_capacity_ = std::min<std::uint32_t>(kInitialBand, capacity_);
    band_ = k_->ctx->create_uncleared_device_buffer(2 * std::size_t{band_capacity_} * sizeof(std::uint32_t));
  }
  // Every state word 0 but the best keys (none yet: the largest key, so that atomicMin finds the first).
  const std::size_t best_key = object_word(kBestKey, objects) * sizeof(std::uint64_t);
  const std::size_t best_key_bytes = std::size_t{objects} * sizeof(std::uint64_t);
  fills.push_back({&state_, 0u, 0, best_key});
  fills.push_back({&state_, 0xffffffffu, best_key, best_key_bytes});
  fills.push_back({&state_, 0u, best_key + best_key_bytes, 0});
  return fills;
}

void GpuBelief::record(std::uint64_t inserted, std::size_t folded) {
  count_ += inserted;
  pairs_ += folded;
  if (folded > 0) {
    // An estimate asked for fewer bins than the floor holds (a light one after a full one): no selection raised it.
    if (asked_since_fold_ > 0 && asked_since_fold_ < next_floor_k_) ++floor_age_;
    asked_since_fold_ = 0;
  }
  forget_cache();
}

std::uint64_t GpuBelief::grown_slots(std::uint64_t slots) const {
  return std::bit_ceil(std::max<std::uint64_t>({slots, 2 * std::uint64_t{capacity_}, 64}));
}

void GpuBelief::grow(std::uint64_t slots) { move_to(grown_slots(slots), false, 0); }

void GpuBelief::prepare_move(Move* m, std::uint64_t slots, bool forget, std::uint64_t below) {
  if (slots > kMaxSlots)
    throw Error("GPU belief table would need more than 2^31 slots (" + std::to_string(count_) + " touched bins)");
  const std::uint32_t objects = k_->space->objects();
  m->slots = slots;
  m->forget = forget;
  allocate_uncleared(m->next, static_cast<std::uint32_t>(slots));
  if (move_status_.size() == 0) move_status_ = k_->ctx->create_buffer(sizeof(std::uint32_t));
  *move_status_.as<std::uint32_t>() = 0;
  gpu::SvaRehashParams p{lo(table_.device_address()),  hi(table_.device_address()),  capacity_,
                         lo(m->next.device_address()), hi(m->next.device_address()), static_cast<std::uint32_t>(slots)};
  p.forget = forget ? 1u : 0u;
  p.keep_lo = lo(below);
  p.keep_hi = hi(below);
  p.keep_count = forget ? keep_count_ : 0u;
  p.state_lo = lo(state_.device_address());
  p.state_hi = hi(state_.device_address());
  p.objects = objects;
  p.object_shift = k_->bins.object_shift();
  const vk::Grid g = k_->ctx->grid(slot_invocations(capacity_));
  ensure(*k_->ctx, keep_, sizeof(std::uint64_t));
  m->rehash = vk::Dispatch{k_->rehash, {&move_status_, &keep_}, push_bytes(p), g.x};
  m->rehash.groups_y = g.y;
  m->fills = clear_fills(m->next, slots);  // in the rehash's submission
  if (forget) {                            // forgetting counts the kept bins afresh
    const std::size_t touched = object_word(kTouched, objects) * sizeof(std::uint64_t);
    m->fills.push_back({&state_, 0u, touched, std::size_t{objects} * sizeof(std::uint64_t)});
  }
}

bool GpuBelief::adopt(Move& m) {
  if (*move_status_.as<std::uint32_t>() != 0) return false;  // a probe run too long even at this load
  table_ = std::move(m.next);
  capacity_ = static_cast<std::uint32_t>(m.slots);
  // The band list names slots of the old table; later folds append to it
  // harmlessly (the rebuild starts it afresh). A move that forgot no bin keeps what was read: the same bins, the
  // same offsets (a batch's reads ahead, made before its tables grew).
  band_stale_ = true;
  if (m.forget) {
    forget_cache();
    drop_floor();  // the bins above it may be gone: it no longer holds its k
  }
  return true;
}

void GpuBelief::move_to(std::uint64_t slots, bool forget, std::uint64_t below) {
  for (std::uint64_t cap = std::bit_ceil(std::max<std::uint64_t>(slots, 64));; cap *= 2) {  // spread further
    Move m;
    prepare_move(&m, cap, forget, below);
    std::vector<double> ms;
    k_->ctx->run({m.rehash}, &ms, m.fills);
    for (double t : ms) k_->kernel_ms += t;
    if (adopt(m)) return;
  }
}

void GpuBelief::keep_half_empty(std::span<GpuBelief* const> beliefs) {
  std::vector<GpuBelief*> growing;
  std::vector<std::uint64_t> slots;
  for (GpuBelief* b : beliefs)
    if (2 * b->count_ > b->capacity_) growing.push_back(b), slots.push_back(2 * b->count_);
  grow_all(growing, slots, [](std::size_t, const vk::OutOfMemory&) {});
}

void GpuBelief::grow_all(std::span<GpuBelief* const> beliefs, std::span<const std::uint64_t> slots,
                         const std::function<void(std::size_t, const vk::OutOfMemory&)>& out_of_memory) {
  if (beliefs.empty()) return;
  std::vector<Move> moves(beliefs.size());    // sized once: the dispatches and fills point into it
  std::vector<std::vector<vk::Dispatch>> ds;  // each belief's rehash into its own new table: side by side
  std::vector<vk::Fill> fills;
  for (std::size_t i = 0; i < beliefs.size(); ++i) {
    GpuBelief& b = *beliefs[i];
    if (b.k_ != beliefs.front()->k_)
      throw std::logic_error("GpuBelief::grow_all: beliefs of two backends in one submission");
    try {
      b.prepare_move(&moves[i], b.grown_slots(slots[i]), false, 0);
    } catch (const vk::OutOfMemory& e) {
      out_of_memory(i, e);
      throw;
    }
    ds.push_back({moves[i].rehash});
    fills.insert(fills.end(), moves[i].fills.begin(), moves[i].fills.end());
  }
  GpuBeliefKernels& k = *beliefs.front()->k_;
  std::vector<double> ms;
  k.ctx->run(vk::side_by_side(std::move(ds)), &ms, fills);
  for (double t : ms) k.kernel_ms += t;
  for (std::size_t i = 0; i < beliefs.size(); ++i) {
    if (beliefs[i]->adopt(moves[i])) continue;
    try {
      beliefs[i]->move_to(2 * moves[i].slots, false, 0);  // a probe ran too long: spread further, alone
    } catch (const vk::OutOfMemory& e) {
      out_of_memory(i, e);
      throw;
    }
  }
}

std::size_t GpuBelief::forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) {
  if (count_ == 0) return 0;
  const std::uint32_t objects = k_->space->objects();
  std::vector<std::uint64_t> linear;
  for (std::uint64_t key : keep) linear.push_back(k_->bins.linear(key));
  std::sort(linear.begin(), linear.end());  // the kernel's binary search
  ensure(*k_->ctx, keep_, linear.size() * sizeof(std::uint64_t));
  if (!linear.empty()) std::memcpy(keep_.data(), linear.data(), linear.size() * sizeof(std::uint64_t));
  keep_count_ = static_cast<std::uint32_t>(linear.size());
  move_to(capacity_, true, below);
  std::vector<std::uint64_t> touched(objects);
  k_->ctx->download(state_, touched.data(), touched.size() * sizeof(std::uint64_t),
                    object_word(kTouched, objects) * sizeof(std::uint64_t));
  std::size_t kept = 0;
  for (std::uint64_t t : touched) kept += t;
  const std::size_t forgotten = count_ - kept;
  count_ = kept;
  // Give the memory back: a table at most a quarter full moves to one at about a quarter load.
  if (4 * count_ < capacity_ / 2) move_to(std::max<std::size_t>(4 * count_, k_->initial_slots), false, 0);
  return forgotten;
}

gpu::SvaReduceParams GpuBelief::reduce_params(std::uint32_t pass) const {
  gpu::SvaReduceParams p{};
  p.table_lo = lo(table_.device_address());
  p.table_hi = hi(table_.device_address());
  p.capacity = capacity_;
  p.pass = pass;
  p.objects = k_->space->objects();
  p.mass_bits = mass_bits_;
  p.object_shift = k_->bins.object_shift();
  p.state_lo = lo(state_.device_address());
  p.state_hi = hi(state_.device_address());
  p.band_lo = lo(band_.device_address());
  p.band_hi = hi(band_.device_address());
  p.band_capacity = band_capacity_;
  p.band_width_lo = lo(band_width_);
  p.band_width_hi = hi(band_width_);
  p.floor_lo = lo(floor_);
  p.floor_hi = hi(floor_);
  return p;
}

std::vector<vk::Dispatch> GpuBelief::reduce_dispatches(const std::vector<std::uint32_t>& passes,
                                                       std::uint64_t entries) const {
  ensure(*k_->ctx, candidates_, 2 * sizeof(std::uint64_t));
  std::vector<vk::Dispatch> ds;
  for (std::uint32_t pass : passes) {
    const vk::Grid g = k_->ctx->grid(pass == SVA_REDUCE_FLIP ? 1 : slot_invocations(entries));
    vk::Dispatch d{k_->reduce, {&candidates_}, push_bytes(reduce_params(pass)), g.x};
    d.groups_y = g.y;
    d.pass = gpu::reduce_pass_name(pass);
    ds.push_back(std::move(d));
  }
  return ds;
}

void GpuBelief::run(GpuBeliefKernels& k, const std::vector<vk::Dispatch>& ds, const std::vector<vk::Fill>& fills,
                    const std::vector<vk::Copy>& reads) {
  if (ds.empty() && fills.empty() && reads.empty()) return;
  std::vector<double> ms;
  k.ctx->run(ds, &ms, fills, reads);
  for (double m : ms) k.kernel_ms += m;
}

void GpuBelief::run_reduce(const std::vector<std::uint32_t>& passes, std::uint64_t entries, std::vector<vk::Fill> fills,
                           const std::vector<vk::Copy>& reads) const {
  run(*k_, reduce_dispatches(passes, entries), fills, reads);
}

std::vector<vk::Copy> GpuBelief::state_reads(std::size_t word, std::size_t words) const {
  if (state_.mapped()) return {};
  if (state_mirror_.size() < state_.size()) state_mirror_ = k_->ctx->create_readback_buffer(state_.size());
  const std::size_t at = word * sizeof(std::uint64_t);
  return {{&state_, &state_mirror_, at, at, words * sizeof(std::uint64_t)}};
}

void GpuBelief::read_state_words(std::uint64_t* out, std::size_t word, std::size_t words) const {
  const vk::Buffer& from = state_.mapped() ? state_ : state_mirror_;
  if (from.size() < (word + words) * sizeof(std::uint64_t))
    throw std::logic_error("GPU belief: state words read before a submission copied them");
  std::memcpy(out, from.as<std::uint64_t>() + word, words * sizeof(std::uint64_t));
}

void GpuBelief::add_rebuild_if_stale(std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills) const {
  if (!band_stale_) return;
  const std::vector<vk::Fill> f = prepare_rebuild(band_capacity_);
  fills->insert(fills->end(), f.begin(), f.end());
  for (vk::Dispatch& d : reduce_dispatches({SVA_REDUCE_REBUILD}, capacity_)) ds->push_back(std::move(d));
}

std::vector<vk::Fill> GpuBelief::prepare_rebuild(std::uint64_t entries) const {
  // A side never needs more entries than the table has slots.
  const std::uint64_t want = std::min<std::uint64_t>(std::bit_ceil(std::max<std::uint64_t>(entries, 64)), capacity_);
  if (want > band_capacity_ || band_.size() == 0) {
    band_capacity_ = static_cast<std::uint32_t>(want);
    // Uncleared: the list is read only up to its count, which the fills below set (a cleared one cost a submission).
    band_ = k_->ctx->create_uncleared_device_buffer(2 * std::size_t{band_capacity_} * sizeof(std::uint32_t));
  }
  // Empty list on side 0, no marks, then every bin in the band joins.
  const std::size_t marks = 2 * std::size_t{capacity_} * sizeof(std::uint64_t);
  return {{&table_, 0u, marks, 0},
          {&state_, 0u, SVA_STATE_BAND_COUNT * sizeof(std::uint64_t), 4 * sizeof(std::uint64_t)}};
}

void GpuBelief::rebuilt() const {
  band_stale_ = false;
  ++k_->band_rebuilds;
}

std::vector<vk::Fill> GpuBelief::mass_fills() const {
  const std::size_t mass = object_word(kMass, k_->space->objects()) * sizeof(std::uint64_t);
  return {{&state_, 0u, mass, 0}, {&state_, 0u, SVA_STATE_NEXT_COUNT * sizeof(std::uint64_t), 8}};
}

bool GpuBelief::read_state() const {
  const std::uint32_t objects = k_->space->objects();
  const std::size_t words = state_words(objects);
  std::vector<std::uint64_t> w(words);
  read_state_words(w.data(), 0, words);  // copied by the submission of the passes (state_reads)
  if (w[SVA_STATE_BAND_LOST] != 0) return false;
  BeliefSummary s;
  s.max_offset = w[SVA_STATE_MAX];
  const auto array = [&](std::uint32_t a) {
    const std::uint64_t* o = w.data() + object_word(a, objects);
    return std::vector<std::uint64_t>(o, o + objects);
  };
  s.touched = array(kTouched);
  s.touched_mass = array(kMass);
  s.best_offset = array(kBestOffset);
  s.best_key = array(kBestKey);
  for (std::uint32_t i = 0; i < objects; ++i) s.best_key[i] = s.touched[i] > 0 ? k_->bins.key(s.best_key[i]) : 0;
  const std::uint64_t* h = w.data() + object_word(SVA_STATE_ARRAYS, objects);
  histogram_.assign(h, h + SVA_BELIEF_BUCKETS);
  summary_cache_ = std::move(s);
  return true;
}

void GpuBelief::enlarge_band() const {
  band_stale_ = true;
  band_capacity_ = std::min<std::uint32_t>(2 * band_capacity_, capacity_);
  band_ = {};
}

void GpuBelief::reduce() const {
  const GpuBelief* self = this;
  read_summaries(std::vector<const GpuBelief*>{self}, 0);
}

std::uint64_t GpuBelief::selection_room(std::size_t k) {
  // Room for the bins of the buckets up to the k-th best: the bucket holding it holds more (ties and neighbours).
  return std::max<std::uint64_t>(8 * std::uint64_t{k}, 1024);
}

bool GpuBelief::passes_over_table() const { return k_->ctx->info().type != "cpu" || k_->ctx->force_staging(); }

vk::Dispatch GpuBelief::bucket_dispatch(std::uint32_t pass, std::size_t k) const {
  gpu::SvaReduceParams p = reduce_params(pass);
  p.select_capacity = static_cast<std::uint32_t>(k);
  const vk::Grid g = k_->ctx->grid(1);
  vk::Dispatch d{k_->reduce, {&candidates_}, push_bytes(p), g.x};
  d.groups_y = g.y;
  d.pass = gpu::reduce_pass_name(pass);
  return d;
}

void GpuBelief::add_selection_ahead(std::size_t k, std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                                    std::vector<vk::Copy>* reads) const {
  const std::uint64_t room = selection_room(k);
  ds->push_back(bucket_dispatch(SVA_REDUCE_BUCKET, k));
  ds->push_back(select_dispatch(SVA_REDUCE_SELECT, SVA_SELECT_FROM_STATE, room, band_capacity_));
  fills->push_back(select_fill());
  // The count is the device's choice: the room comes back, of which the host reads what the count says.
  gpu::add_mirror_read(*k_->ctx, candidates_, candidates_mirror_, room * 2 * sizeof(std::uint64_t), reads);
  // A CPU device reads its table on the host instead. Where the band's floor holds k bins or more, so does the list:
  // no pass over the table's slots (on a sharp belief they were most of an update's device time).
  table_ahead_ = passes_over_table() && (floor_ == kNoFloor || floor_k_ < k);
  if (!table_ahead_) return;
  // Where the band holds fewer than k bins (a sharp belief asked for its next modes): the table's histogram and its
  // selection, each pass a no-op elsewhere.
  fills->push_back(table_histogram_fill());
  for (vk::Dispatch& d : reduce_dispatches({SVA_REDUCE_TABLE_HISTOGRAM}, capacity_)) {
    gpu::SvaReduceParams p = reduce_params(SVA_REDUCE_TABLE_HISTOGRAM);
    p.select_bucket = SVA_SELECT_FROM_STATE;
    d.push = push_bytes(p);
    ds->push_back(std::move(d));
  }
  ds->push_back(bucket_dispatch(SVA_REDUCE_TABLE_BUCKET, k));
  ds->push_back(select_dispatch(SVA_REDUCE_TABLE_SELECT, SVA_SELECT_FROM_STATE, room, capacity_));
}

void GpuBelief::keep_selection_ahead(std::size_t k) const {
  auto [bucket, n] = bucket_holding(histogram_, k);
  if (bucket == SVA_BELIEF_BUCKETS && table_ahead_) std::tie(bucket, n) = bucket_holding(read_table_histogram(), k);
  // Past every bucket, or more candidates than the room: best_bins' own ways (read_best_ahead, or alone).
  if (bucket == SVA_BELIEF_BUCKETS || n > selection_room(k)) return;
  keep_best(read_candidates(n), k);
}

void GpuBelief::read_summaries(std::vector<const GpuBelief*> pending, std::size_t k) {
  for (int attempt = 0; !pending.empty(); ++attempt) {
    GpuBeliefKernels& kernels = *pending.front()->k_;
    std::vector<std::vector<vk::Dispatch>> ds(pending.size());  // each belief's passes, side by side
    std::vector<vk::Fill> fills;
    std::vector<vk::Copy> reads;
    // One submission: a stale band rebuilt first (a table moved since the last estimate: each growth of an update's
    // sessions), then the belief's MASS and FLIP passes, and their state words back. The rebuild's fills (the
    // band's marks and counts) and the passes' (the masses) touch different words, and every fill precedes every pass.
    // With k, each belief's best k bins are selected in the same submission, from the bucket its histogram gives on
    // the device (the BUCKET pass): the summary and the best bins in one round trip, where they took two.
    const auto asked = [k](const GpuBelief* b) { return std::min(k, b->count_); };
    for (std::size_t i = 0; i < pending.size(); ++i) {
      pending[i]->take_floor();
      pending[i]->add_rebuild_if_stale(&ds[i], &fills);
      pending[i]->add_summary_reads(asked(pending[i]), &ds[i], &fills, &reads);
    }
    run(kernels, vk::side_by_side(std::move(ds)), fills, reads);
    std::vector<const GpuBelief*> lost;
    for (const GpuBelief* b : pending) {
      if (b->band_stale_) b->rebuilt();
      if (!b->read_state())
        lost.push_back(b);
      else if (asked(b) > 1)
        b->keep_selection_ahead(asked(b));
    }
    // A fold found those lists full: what the passes read was incomplete. Rebuilt larger, they are read again together
    // (early in a batch every session's list fills at the same update).
    for (const GpuBelief* b : lost) {
      if (attempt > 0 && b->band_capacity_ >= b->capacity_)
        throw std::logic_error("GPU belief: the band list lost bins at full size");
      b->enlarge_band();
    }
    pending = std::move(lost);
  }
}

void GpuBelief::read_ahead(std::span<const GpuBelief* const> beliefs, std::size_t k, std::span<const KeyChoice> keys) {
  if (beliefs.empty()) return;
  for (std::size_t i = 0; i < beliefs.size(); ++i) {
    const GpuBelief* b = beliefs[i];
    if (b->k_ != beliefs.front()->k_)
      throw std::logic_error("GpuBelief::read_ahead: beliefs of two backends in one submission");
    b->ahead_k_ = std::max<std::size_t>(k, 1);  // the next update reads the same ahead
    b->asked_since_fold_ = std::max(b->asked_since_fold_, b->ahead_k_);
    b->ahead_keys_ = i < keys.size() ? keys[i] : KeyChoice{};
  }
  std::vector<const GpuBelief*> unread;
  for (const GpuBelief* b : beliefs)
    if (!b->summary_cache_) unread.push_back(b);
  read_summaries(std::move(unread), k);
  read_best_ahead(beliefs, k);  // those whose best bins lie past the band, or did not fit the room
}

bool GpuBelief::add_reads_after_fold(std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                                     std::vector<vk::Copy>* reads) const {
  keys_chosen_ = false;
  if (ahead_k_ == 0 || band_.size() == 0) return false;
  // Every fill precedes the fold: the words they clear are ones the fold never writes (masses, histograms, the
  // selection's count), or, where the table moved since the list was built, the list itself (the same list: no new
  // buffer to name), which the fold then joins afresh and the REBUILD pass after it completes (the marks keep each bin
  // on it once).
  take_floor();
  add_rebuild_if_stale(ds, fills);
  add_summary_reads(ahead_k_, ds, fills, reads);
  keys_chosen_ = ahead_keys_.on && add_key_choice(ds, reads);
  return true;
}

gpu::SvaHoodParams GpuBelief::hood_params(std::uint32_t pass, std::uint64_t steps, std::uint64_t keys) const {
  const PoseSpaceSpec& spec = k_->space->spec();
  gpu::SvaHoodParams p{};
  p.table_lo = lo(table_.device_address());
  p.table_hi = hi(table_.device_address());
  p.capacity = capacity_;
  p.state_lo = lo(state_.device_address());
  p.state_hi = hi(state_.device_address());
  p.pass = pass;
  p.objects = k_->space->objects();
  p.object_shift = k_->bins.object_shift();
  p.room = static_cast<std::uint32_t>(selection_room(ahead_k_));
  p.best = ahead_keys_.best;
  p.modes = ahead_keys_.modes;
  p.suppress = static_cast<std::uint32_t>(ahead_keys_.suppress);
  p.radius = static_cast<std::uint32_t>(ahead_keys_.radius);
  p.translation_bins = static_cast<std::uint32_t>(spec.translation_bins);
  p.rotation_bins = static_cast<std::uint32_t>(spec.rotation_bins);
  p.planar = k_->space->planar() ? 1u : 0u;
  p.keys = static_cast<std::uint32_t>(keys);
  p.steps = static_cast<std::uint32_t>(steps);
  p.mode_best = ahead_keys_.mode_best ? ahead_keys_.mode_best : ahead_keys_.best;
  p.prior_best = ahead_keys_.prior_best;
  p.priors = ahead_keys_.prior.empty() ? 0u : 1u;
  p.translation_min_mm = static_cast<float>(spec.translation_min_mm);
  p.translation_bin_mm =
      static_cast<float>((spec.translation_max_mm - spec.translation_min_mm) / spec.translation_bins);
  return p;
}

// The pose priors' terms where belief_hoods.comp reads them (its third buffer, bound with or without priors): the
// engine's zeros for a session without any (no allocation per session of a batch), else the session's own, written
// when they changed (a session's prior changes rarely, and its last submission has finished before this one is
// recorded).
vk::Buffer& GpuBelief::priors_buffer() const {
  const std::vector<float>& terms = ahead_keys_.prior;
  if (terms.empty() && k_->no_priors) return *k_->no_priors;
  const std::size_t bytes = std::max<std::size_t>(terms.size() * sizeof(float), 64);
  if (priors_.size() < bytes) {
    priors_ = k_->ctx->create_buffer(std::bit_ceil(bytes));
    priors_written_.clear();
  }
  if (terms != priors_written_) {
    std::memcpy(priors_.as<float>(), terms.data(), terms.size() * sizeof(float));
    priors_written_ = terms;
  }
  return priors_;
}

bool GpuBelief::add_key_choice(std::vector<vk::Dispatch>* ds, std::vector<vk::Copy>* reads) const {
  const KeyChoice& c = ahead_keys_;
  // The modes come from the best bins this submission selects: no more than it selects.
  if (c.best > 1 && c.best > ahead_k_) return false;
  const std::uint64_t steps = neighbourhood_steps(*k_->space, c.radius);  // belief_hoods.comp's axis_steps
  const std::uint64_t centres = std::uint64_t{c.modes} + k_->space->objects();
  // Room for every centre's every step, or, once an estimate has read its keys and where that bound is large (a
  // batch's sessions each hold one list), for as many and a quarter and two neighbourhoods more; a longer list is not
  // chosen here, and the estimate looks its keys up itself. A bound of at most kWholeKeys is held whole: with many
  // objects the touched ones outgrow the quarter (a map of 70 objects chose on 5 of 16 updates, a round trip each
  // of the rest), and 1 MiB per session is cheap beside a belief's tables.
  constexpr std::uint64_t kWholeKeys = std::uint64_t{1} << 16;
  const std::uint64_t bound = centres * steps;
  const std::uint64_t keys =
      last_keys_ == 0 || bound <= kWholeKeys ? bound : std::min(bound, last_keys_ + last_keys_ / 4 + 2 * steps);
  constexpr std::uint64_t kMostKeys = std::uint64_t{1} << 22;  // 64 MiB of keys and offsets
  if (keys > kMostKeys) return false;
  // In the device's memory, where the kernels read their own lists at its speed; on a discrete GPU its words come
  // back by a copy into cached host memory in the same submission (as the state's: state_reads).
  const std::size_t bytes = (SVA_HOODS_HEADER + 2 * (c.best + centres + keys)) * sizeof(std::uint64_t);
  if (hoods_.size() < bytes) hoods_ = k_->ctx->create_uncleared_device_buffer(std::bit_ceil(bytes));
  if (!hoods_.mapped()) {
    if (hoods_mirror_.size() < hoods_.size()) hoods_mirror_ = k_->ctx->create_readback_buffer(hoods_.size());
    reads->push_back({&hoods_, &hoods_mirror_, 0, 0, bytes});
  }
  vk::Buffer& priors = priors_buffer();
  const auto dispatch = [&](std::uint32_t pass, std::uint64_t invocations) {
    const vk::Grid g = k_->ctx->grid(invocations);
    vk::Dispatch d{k_->hoods, {&candidates_, &hoods_, &priors}, push_bytes(hood_params(pass, steps, keys)), g.x};
    d.groups_y = g.y;
    d.pass = gpu::hoods_pass_name(pass);
    ds->push_back(std::move(d));
  };
  if (c.best > 1) dispatch(SVA_HOODS_RANK, selection_room(ahead_k_));
  dispatch(SVA_HOODS_CENTRES, 1);
  dispatch(SVA_HOODS_KEYS, keys);
  return true;
}

void GpuBelief::keep_key_choice() const {
  const auto* h = (hoods_.mapped() ? hoods_ : hoods_mirror_).as<std::uint64_t>();
  if (h[0] == SVA_HOODS_NONE) return;  // not chosen on the device: the estimate looks its keys up
  const std::size_t first = SVA_HOODS_HEADER + 2 * (ahead_keys_.best + ahead_keys_.modes + k_->space->objects());
  looked_up_keys_.resize(h[0]);
  looked_up_offsets_.resize(h[0]);
  for (std::size_t i = 0; i < h[0]; ++i) {
    looked_up_keys_[i] = h[first + 2 * i];
    looked_up_offsets_[i] = h[first + 2 * i + 1];
  }
}

void GpuBelief::add_summary_reads(std::size_t k, std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                                  std::vector<vk::Copy>* reads) const {
  const std::vector<vk::Fill> f = mass_fills();
  fills->insert(fills->end(), f.begin(), f.end());
  for (vk::Dispatch& d : reduce_dispatches({SVA_REDUCE_MASS, SVA_REDUCE_FLIP}, band_capacity_))
    ds->push_back(std::move(d));
  if (k > 1) add_selection_ahead(k, ds, fills, reads);
  for (const vk::Copy& c : state_reads(0, state_words(k_->space->objects()))) reads->push_back(c);
}

void GpuBelief::keep_reads_after_fold(std::span<const GpuBelief* const> beliefs) {
  std::vector<const GpuBelief*> lost;
  std::size_t k = 0;
  for (const GpuBelief* b : beliefs) {
    if (b->band_stale_) b->rebuilt();
    const std::size_t kb = std::min(b->ahead_k_, b->count_);
    if (!b->read_state()) {
      b->enlarge_band();
      lost.push_back(b);
      k = std::max(k, b->ahead_k_);
    } else {
      if (kb > 1) b->keep_selection_ahead(kb);  // the device chose the bucket for as many bins as the fold left
      if (b->keys_chosen_) b->keep_key_choice();
    }
  }
  // A fold found those lists full: rebuilt larger now, together, as an estimate's read would, before a later fold
  // writes to them.
  if (!lost.empty()) read_summaries(std::move(lost), k);
}

BeliefSummary GpuBelief::summarise() const {
  if (!summary_cache_) reduce();
  return *summary_cache_;
}

void GpuBelief::forget_cache() const {
  summary_cache_.reset();
  looked_up_keys_.clear();
  looked_up_offsets_.clear();
  kept_best_.clear();
  kept_asked_ = 0;
}

std::vector<BinOffset> GpuBelief::best_bins(std::size_t k) const {
  k = std::min(k, count_);
  if (k == 0) return {};
  asked_since_fold_ = std::max(asked_since_fold_, k);
  if (!summary_cache_) reduce();
  // An estimate asks for the best bins several times (top bins, modes, hypotheses, the surface check's objects),
  // each a selection pass and a round trip: the best `kept_asked_` stay until the belief changes, and a smaller k
  // is their prefix (best first, ties to the smaller key: the same order for any k).
  if (k <= kept_asked_) return {kept_best_.begin(), kept_best_.begin() + static_cast<std::ptrdiff_t>(k)};
  return keep_best(select_best(k), k);
}

std::vector<BinOffset> GpuBelief::keep_best(std::vector<BinOffset> out, std::size_t k) const {
  const auto best_first = [](const BinOffset& a, const BinOffset& b) {
    return a.offset != b.offset ? a.offset > b.offset : a.key < b.key;
  };
  keep_floor(out, k);
  k = std::min(k, out.size());
  std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k), out.end(), best_first);
  out.resize(k);
  kept_best_ = out;
  kept_asked_ = k;
  return out;
}

void GpuBelief::keep_floor(std::span<const BinOffset> candidates, std::size_t asked) const {
  // The floor holds as many bins as any selection asked since it was dropped: a smaller one that found that many
  // candidates raises it too (a light estimate's after a full one's), else risers would pile up on the list.
  const std::size_t k = std::max(asked, next_floor_k_);
  // Every bin (a floor would put the whole table on the list), or fewer candidates than k: nothing to learn.
  if (k < 2 || k >= count_ || candidates.size() < k || !summary_cache_) return;
  std::vector<std::uint64_t> offsets(candidates.size());
  std::transform(candidates.begin(), candidates.end(), offsets.begin(), [](const BinOffset& b) { return b.offset; });
  std::nth_element(offsets.begin(), offsets.begin() + static_cast<std::ptrdiff_t>(k - 1), offsets.end(),
                   std::greater<>());
  const std::uint64_t f = offsets[k - 1];
  next_floor_ = f;
  next_floor_k_ = k;
  floor_age_ = 0;
  // At once where nothing changes on the list: a lower floor whose bins are all within the band width of the
  // maximum the list was compacted at (on it already; a rebuild now would make the same list). A higher floor waits
  // for the next MASS pass, which drops the bins below it: a rebuild before then (a table that moved) would leave
  // the list shorter than the histogram that the selections count.
  if (f < floor_ && summary_cache_->max_offset - f < band_width_) {
    floor_ = f;
    floor_k_ = k;
  }
}

void GpuBelief::take_floor() const {
  // Two estimates in a row asked for fewer bins than the floor holds (light ones after a full one, the best bin read
  // from the summary): it no longer rises with the best bins, and the bins rising above it would pile up on the list.
  // Dropped, it is a rise (the MASS pass leaves the band's bins only); a later full estimate passes over the table
  // once. Updates without an estimate leave it: the next full one raises it, and the MASS pass drops the rest.
  if (floor_age_ >= 2) {
    next_floor_ = kNoFloor;
    next_floor_k_ = 0;
    floor_age_ = 0;
  }
  if (next_floor_ == floor_) {
    floor_k_ = next_floor_k_;
    return;
  }
  // A lower floor puts bins on the list that no fold joined: a rebuild from the table (where the belief first grew
  // sharper than its band, or a full estimate follows light ones that dropped it; later floors rise with its best
  // bins).
  if (next_floor_ < floor_) band_stale_ = true;
  floor_ = next_floor_;
  floor_k_ = next_floor_k_;
}

void GpuBelief::drop_floor() const {
  floor_ = next_floor_ = kNoFloor;
  floor_k_ = next_floor_k_ = 0;
  floor_age_ = 0;
}

std::vector<BinOffset> GpuBelief::select_best(std::size_t k) const {
  if (k == 1) {
    // The best bin overall is the best of the objects' best bins (largest
    // offset, then smaller key): the state already holds it.
    const BeliefSummary& s = *summary_cache_;
    BinOffset best;
    bool found = false;
    for (std::size_t o = 0; o < s.touched.size(); ++o) {
      if (s.touched[o] == 0) continue;
      const BinOffset c{s.best_key[o], s.best_offset[o]};
      if (!found || c.offset > best.offset || (c.offset == best.offset && c.key < best.key)) best = c;
      found = true;
    }
    return {best};
  }
  // The smallest bucket bound that holds at least k bins: those bins contain the top k. The band's histogram
  // first; when the band holds fewer than k bins (a sharp belief asked for its next modes), every slot's.
  // On a GPU two passes over the slots cost microseconds where the table would cross the bus; a CPU device
  // (lavapipe) runs the passes on the host's own cores, slower than reading its memory directly.
  std::uint32_t pass = SVA_REDUCE_SELECT;
  std::uint64_t entries = band_capacity_;
  auto [bucket, n] = bucket_holding(histogram_, k);
  if (bucket == SVA_BELIEF_BUCKETS && passes_over_table()) {
    std::tie(bucket, n) = bucket_holding(table_histogram(), k);
    pass = SVA_REDUCE_TABLE_SELECT;
    entries = capacity_;
  }
  if (bucket == SVA_BELIEF_BUCKETS || n * 2 * sizeof(std::uint64_t) > k_->ctx->info().max_storage_buffer_range) {
    // The whole table on the host: a CPU device, or so many bins tied near the k-th that their list would not
    // fit one binding (same answer).
    return unsorted_table();
  }
  return select_candidates(pass, bucket, n, entries);
}

void GpuBelief::read_best_ahead(std::span<const GpuBelief* const> beliefs, std::size_t k) {
  std::vector<BestRead> sel;
  for (const GpuBelief* b : beliefs) {
    const std::size_t kb = std::min(k, b->count_);
    // One bin is the summary's; a belief read alone, or already read this far, needs no selection.
    if (kb > 1 && b->summary_cache_ && kb > b->kept_asked_) sel.push_back({b, kb, b->histogram_});
  }
  if (sel.empty()) return;
  read_table_histograms_ahead(sel);
  std::vector<std::vector<vk::Dispatch>> ds;  // each belief's passes, side by side
  std::vector<vk::Fill> fills;
  std::vector<vk::Copy> reads;  // each selection's count comes back in the same submission
  std::vector<std::pair<const BestRead*, std::uint64_t>> made;
  for (const BestRead& s : sel) {
    const GpuBelief& b = *s.belief;
    const auto [bucket, n] = bucket_holding(s.histogram, s.k);
    // Past every bucket, or past one binding: best_bins' own ways, alone.
    if (bucket == SVA_BELIEF_BUCKETS || n * 2 * sizeof(std::uint64_t) > b.k_->ctx->info().max_storage_buffer_range)
      continue;
    std::vector<vk::Dispatch>& own = ds.emplace_back();
    if (s.pass == SVA_REDUCE_SELECT) b.add_rebuild_if_stale(&own, &fills);  // its table moved since it was read
    own.push_back(b.select_dispatch(s.pass, bucket, n, s.pass == SVA_REDUCE_SELECT ? b.band_capacity_ : b.capacity_));
    fills.push_back(b.select_fill());
    for (const vk::Copy& c : b.state_reads(SVA_STATE_CANDIDATES, 1)) reads.push_back(c);
    gpu::add_mirror_read(*b.k_->ctx, b.candidates_, b.candidates_mirror_, n * 2 * sizeof(std::uint64_t), &reads);
    made.emplace_back(&s, n);
  }
  if (made.empty()) return;
  run(*made.front().first->belief->k_, vk::side_by_side(std::move(ds)), fills, reads);
  for (const auto& [s, n] : made) {
    if (s->pass == SVA_REDUCE_SELECT && s->belief->band_stale_) s->belief->rebuilt();
    s->belief->keep_best(s->belief->read_candidates(n), s->k);
  }
}

void GpuBelief::read_table_histograms_ahead(std::vector<BestRead>& sel) {
  // A CPU device reads its table on the host instead (best_bins' own way, alone): its passes run on the same cores.
  GpuBeliefKernels& kernels = *sel.front().belief->k_;
  if (!sel.front().belief->passes_over_table()) return;
  std::vector<BestRead*> past;
  std::vector<std::vector<vk::Dispatch>> ds;  // each belief's pass, side by side
  std::vector<vk::Fill> fills;
  std::vector<vk::Copy> reads;
  for (BestRead& s : sel) {
    if (bucket_holding(s.histogram, s.k).first != SVA_BELIEF_BUCKETS) continue;
    s.belief->add_table_histogram(&ds.emplace_back(), &fills, &reads);
    past.push_back(&s);
  }
  if (past.empty()) return;
  run(kernels, vk::side_by_side(std::move(ds)), fills, reads);
  for (BestRead* s : past) {
    s->histogram = s->belief->read_table_histogram();
    s->pass = SVA_REDUCE_TABLE_SELECT;
  }
}

std::pair<std::uint32_t, std::uint64_t> GpuBelief::bucket_holding(std::span<const std::uint64_t> histogram,
                                                                  std::size_t k) {
  std::uint64_t n = 0;
  for (std::uint32_t bucket = 0; bucket < histogram.size(); ++bucket)
    if ((n += histogram[bucket]) >= k) return {bucket, n};
  return {SVA_BELIEF_BUCKETS, n};
}

std::vector<std::uint64_t> GpuBelief::table_histogram() const {
  std::vector<vk::Dispatch> ds;
  std::vector<vk::Fill> fills;
  std::vector<vk::Copy> reads;
  add_table_histogram(&ds, &fills, &reads);
  run(*k_, ds, fills, reads);
  return read_table_histogram();
}

void GpuBelief::add_table_histogram(std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                                    std::vector<vk::Copy>* reads) const {
  for (vk::Dispatch& d : reduce_dispatches({SVA_REDUCE_TABLE_HISTOGRAM}, capacity_)) ds->push_back(std::move(d));
  fills->push_back(table_histogram_fill());
  for (const vk::Copy& c : state_reads(table_histogram_word(k_->space->objects()), SVA_BELIEF_BUCKETS))
    reads->push_back(c);
}

vk::Fill GpuBelief::table_histogram_fill() const {
  return {&state_, 0u, table_histogram_word(k_->space->objects()) * sizeof(std::uint64_t),
          SVA_BELIEF_BUCKETS * sizeof(std::uint64_t)};
}

std::vector<std::uint64_t> GpuBelief::read_table_histogram() const {
  std::vector<std::uint64_t> h(SVA_BELIEF_BUCKETS);
  read_state_words(h.data(), table_histogram_word(k_->space->objects()), SVA_BELIEF_BUCKETS);
  return h;
}

vk::Dispatch GpuBelief::select_dispatch(std::uint32_t pass, std::uint32_t bucket, std::uint64_t n,
                                        std::uint64_t entries) const {
  ensure(*k_->ctx, candidates_, n * 2 * sizeof(std::uint64_t));
  gpu::SvaReduceParams p = reduce_params(pass);
  p.select_bucket = bucket;
  p.select_capacity = static_cast<std::uint32_t>(n);
  const vk::Grid g = k_->ctx->grid(slot_invocations(entries));
  vk::Dispatch d{k_->reduce, {&candidates_}, push_bytes(p), g.x};
  d.groups_y = g.y;
  d.pass = gpu::reduce_pass_name(pass);
  return d;
}

vk::Fill GpuBelief::select_fill() const { return {&state_, 0u, SVA_STATE_CANDIDATES * sizeof(std::uint64_t), 8}; }

std::vector<BinOffset> GpuBelief::read_candidates(std::uint64_t n) const {
  std::uint64_t found = 0;
  read_state_words(&found, SVA_STATE_CANDIDATES, 1);  // copied by the selection's submission
  if (found != n)
    throw std::logic_error("GPU belief: top-k selection found " + std::to_string(found) +
                           " bins where its histogram has " + std::to_string(n));
  const auto* c = gpu::mirror_of(*k_->ctx, candidates_, candidates_mirror_).as<std::uint64_t>();
  std::vector<BinOffset> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = {k_->bins.key(c[2 * i]), c[2 * i + 1]};
  return out;
}

std::vector<BinOffset> GpuBelief::select_candidates(std::uint32_t pass, std::uint32_t bucket, std::uint64_t n,
                                                    std::uint64_t entries) const {
  std::vector<vk::Dispatch> ds;
  std::vector<vk::Fill> fills;
  const bool rebuild = pass == SVA_REDUCE_SELECT && band_stale_;  // its table moved since it was read
  if (rebuild) add_rebuild_if_stale(&ds, &fills);
  ds.push_back(select_dispatch(pass, bucket, n, entries));
  fills.push_back(select_fill());
  std::vector<vk::Copy> reads = state_reads(SVA_STATE_CANDIDATES, 1);
  gpu::add_mirror_read(*k_->ctx, candidates_, candidates_mirror_, n * 2 * sizeof(std::uint64_t), &reads);
  run(*k_, ds, fills, reads);
  if (rebuild) rebuilt();
  return read_candidates(n);
}

vk::Dispatch GpuBelief::lookup_dispatch(std::span<const std::uint64_t> keys, std::vector<vk::Copy>* reads) const {
  ensure(*k_->ctx, queries_, keys.size() * sizeof(std::uint64_t));
  gpu::add_mirror_read(*k_->ctx, queries_, queries_mirror_, keys.size() * sizeof(std::uint64_t), reads);
  auto* q = queries_.as<std::uint64_t>();
  for (std::size_t i = 0; i < keys.size(); ++i) q[i] = k_->bins.linear(keys[i]);
  gpu::SvaLookupParams p{lo(table_.device_address()), hi(table_.device_address()), capacity_,
                         static_cast<std::uint32_t>(keys.size())};
  const vk::Grid g = k_->ctx->grid(keys.size());
  vk::Dispatch d{k_->lookup, {&queries_}, push_bytes(p), g.x};
  d.groups_y = g.y;
  return d;
}

std::vector<std::uint64_t> GpuBelief::read_lookup(std::size_t n) const {
  // The kernel wrote the offsets over the keys, in place.
  const auto* q = gpu::mirror_of(*k_->ctx, queries_, queries_mirror_).as<std::uint64_t>();
  return std::vector<std::uint64_t>(q, q + n);
}

std::vector<std::uint64_t> GpuBelief::offsets(std::span<const std::uint64_t> keys) const {
  if (keys.empty()) return {};
  std::vector<std::uint64_t> out;
  if (looked_up(keys, &out)) return out;
  std::vector<vk::Copy> reads;
  const vk::Dispatch d = lookup_dispatch(keys, &reads);
  run(*k_, {d}, {}, reads);
  return read_lookup(keys.size());
}

bool GpuBelief::looked_up(std::span<const std::uint64_t> keys, std::vector<std::uint64_t>* out) const {
  // The hypotheses ask for exactly the keys looked up, in the same order; a parabola for a dozen of them. A sorted
  // copy or a hash of the several thousand keys cost more host time than the round trip it saves on a GPU.
  const std::span<const std::uint64_t> known(looked_up_keys_);
  if (known.empty()) return false;
  if (std::equal(keys.begin(), keys.end(), known.begin(), known.end())) {
    *out = looked_up_offsets_;
    return true;
  }
  constexpr std::size_t kScanned = 64;  // a few keys: found by a scan of the list
  if (keys.size() > kScanned) return false;
  for (std::uint64_t key : keys) {
    const auto at = std::find(known.begin(), known.end(), key);
    if (at == known.end()) return false;
    out->push_back(looked_up_offsets_[static_cast<std::size_t>(at - known.begin())]);
  }
  return true;
}

void GpuBelief::look_up_ahead(std::span<const GpuBelief* const> beliefs,
                              std::span<const std::vector<std::uint64_t>> keys) {
  std::vector<std::vector<vk::Dispatch>> ds(beliefs.size());  // each belief's passes, side by side
  std::vector<vk::Copy> reads;
  std::vector<std::uint8_t> asked(beliefs.size(), 0);
  for (std::size_t i = 0; i < beliefs.size(); ++i) {
    beliefs[i]->last_keys_ = keys[i].size();  // the room of the next update's choice
    // Chosen and looked up already, in the update's submission (belief_hoods.comp): the same keys, read nothing.
    if (keys[i].empty() || keys[i] == beliefs[i]->looked_up_keys_) continue;
    ds[i].push_back(beliefs[i]->lookup_dispatch(keys[i], &reads));
    asked[i] = 1;
  }
  if (std::find(asked.begin(), asked.end(), 1) == asked.end()) return;
  for (const GpuBelief* b : beliefs)
    if (b->k_ != beliefs.front()->k_)
      throw std::logic_error("GpuBelief::look_up_ahead: beliefs of two backends in one submission");
  // A band list that a table's move left stale (its summary read before the move) is rebuilt here, in a submission
  // the estimate makes anyway, so that the next update reads that belief ahead again.
  std::vector<vk::Fill> fills;
  for (std::size_t i = 0; i < beliefs.size(); ++i) beliefs[i]->add_rebuild_if_stale(&ds[i], &fills);
  run(*beliefs.front()->k_, vk::side_by_side(std::move(ds)), fills, reads);
  for (const GpuBelief* b : beliefs)
    if (b->band_stale_) b->rebuilt();
  for (std::size_t i = 0; i < beliefs.size(); ++i) {
    if (!asked[i]) continue;
    beliefs[i]->looked_up_offsets_ = beliefs[i]->read_lookup(keys[i].size());
    beliefs[i]->looked_up_keys_ = keys[i];
  }
}

std::vector<BinOffset> GpuBelief::unsorted_table() const {
  std::vector<std::uint64_t> words(std::size_t{capacity_} * 2);
  k_->ctx->download(table_, words.data(), words.size() * sizeof(std::uint64_t));
  const std::uint64_t* keys = words.data();
  const std::uint64_t* offsets = keys + capacity_;
  std::vector<BinOffset> out;
  out.reserve(count_);
  for (std::uint32_t i = 0; i < capacity_; ++i)
    if (keys[i] != ~std::uint64_t{0}) out.push_back({k_->bins.key(keys[i]), offsets[i]});
  return out;
}

std::vector<BinOffset> GpuBelief::table() const {
  std::vector<BinOffset> out = unsorted_table();
  std::sort(out.begin(), out.end(), [](const BinOffset& a, const BinOffset& b) { return a.key < b.key; });
  return out;
}

std::vector<std::uint64_t> GpuBelief::band_keys() const {
  forget_cache();
  reduce();
  std::uint64_t words[2];  // BAND_COUNT, BAND_SIDE
  k_->ctx->download(state_, words, sizeof words, SVA_STATE_BAND_COUNT * sizeof(std::uint64_t));
  std::vector<std::uint32_t> slots(words[0]);
  if (!slots.empty())
    k_->ctx->download(band_, slots.data(), slots.size() * sizeof(std::uint32_t),
                      words[1] * band_capacity_ * sizeof(std::uint32_t));
  std::vector<std::uint64_t> keys(capacity_);
  k_->ctx->download(table_, keys.data(), keys.size() * sizeof(std::uint64_t));
  std::vector<std::uint64_t> out;
  for (std::uint32_t slot : slots) out.push_back(k_->bins.key(keys.at(slot)));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace sva
