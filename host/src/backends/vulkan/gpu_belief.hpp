#pragma once
// A session's belief in device memory: the Vulkan backend's BeliefState. The
// offsets live in an open-addressing table reached by device address (it may
// outgrow one binding's range); the fold writes it (belief_fold.comp, run by
// the backend) and keeps the estimate's state current: the maximum, each
// object's touched bins and best bin, and the band list of the bins near the
// maximum. The estimate's passes visit the band list only (belief_reduce.comp),
// and lookups a few bins (belief_lookup.comp). Only the state's few integers
// come back to the host, which finishes the estimate with the same code as
// the CPU reference.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "backends/vulkan/context.hpp"
#include "backends/vulkan/gpu_layout.hpp"
#include "backends/vulkan/linear_bins.hpp"
#include "backends/vulkan/vk_check.hpp"
#include "belief/belief_state.hpp"

namespace sva {

// Invocations of a kernel that visits `slots` table slots, SVA_SLOTS_PER_INVOCATION each.
std::uint64_t slot_invocations(std::uint64_t slots);

// The pipelines and constants every GpuBelief of one backend shares.
struct GpuBeliefKernels {
  vk::Context* ctx = nullptr;
  const PoseSpace* space = nullptr;
  LinearBins bins;
  const vk::Pipeline* rehash = nullptr;  // the engine's (backends/vulkan/vulkan_engine.hpp)
  const vk::Pipeline* reduce = nullptr;
  const vk::Pipeline* lookup = nullptr;
  const vk::Pipeline* hoods = nullptr;  // belief_hoods.comp: the keys an estimate reads, chosen after an update
  vk::Buffer* no_priors = nullptr;      // its priors buffer for a session without any: one for all (zeros)
  std::size_t initial_slots = 1 << 12;
  // Counted by the beliefs of many sessions at once: a batch's estimates read their beliefs on the workers.
  std::atomic<double> kernel_ms = 0.0;      // GPU time of belief work since the backend last reset it
  std::atomic<unsigned> band_rebuilds = 0;  // band lists rebuilt from a whole table (BackendStats::band_rebuilds)
};

class GpuBelief final : public BeliefState {
 public:
  // A new belief is empty once its maker has run reset_all on it, with the other new beliefs of a batch in one
  // submission (VoteBackend::make_beliefs; one each was a round trip per session). Until then it must not be used.
  GpuBelief(GpuBeliefKernels& kernels, double eps);

  void reset() override;
  // reset() of many beliefs of one backend (a batch's group), all in one submission.
  static void reset_all(std::span<GpuBelief* const> beliefs);
  std::size_t table_allocations() const override { return table_allocations_; }
  std::size_t pairs_folded() const override { return pairs_; }
  std::size_t touched() const override { return count_; }
  std::size_t table_bytes() const override;
  BeliefSummary summarise() const override;
  std::vector<BinOffset> best_bins(std::size_t k) const override;
  std::vector<std::uint64_t> offsets(std::span<const std::uint64_t> keys) const override;
  std::vector<BinOffset> table() const override;
  std::size_t forget_below(std::uint64_t below, std::span<const std::uint64_t> keep) override;
  // The keys on the band list after an estimate's compaction, sorted (tests:
  // every bin within band_width() of the maximum must be there).
  std::vector<std::uint64_t> band_keys() const;

  // For the backend's fold.
  std::uint64_t eps_units() const { return eps_units_; }
  std::uint32_t capacity() const { return capacity_; }
  VkDeviceAddress address() const { return table_.device_address(); }
  VkDeviceAddress state_address() const { return state_.device_address(); }
  VkDeviceAddress band_address() const { return band_.device_address(); }
  std::uint32_t band_capacity() const { return band_capacity_; }
  // A bin is on the band list when M - offset < band_width() (belief units), or when its offset is at least
  // band_floor() (sva_on_band).
  std::uint64_t band_width() const { return band_width_; }
  // The band's floor: the offset of the k-th best bin of the last selection of k bins (k as large as any asked
  // since), so that the list keeps the best k bins when the belief grows sharp and a later selection of them reads
  // the list, not every slot of the table. kNoFloor: none yet.
  std::uint64_t band_floor() const { return floor_; }
  static constexpr std::uint64_t kNoFloor = ~std::uint64_t{0};
  // Records a fold pass: `inserted` new keys; `folded` more pairs.
  void record(std::uint64_t inserted, std::size_t folded);
  // Moves the table into one of at least `slots` slots (a power of two).
  void grow(std::uint64_t slots);
  // Keeps each belief's load at most one half for the next update (those of one backend: a batch's sessions), their
  // tables moved in one submission: in a batch many sessions outgrow their half together, and two submissions each
  // were a suspect for the batch's host time on a GPU (docs/vulkan-backend.md, "The fifth GPU run").
  static void keep_half_empty(std::span<GpuBelief* const> beliefs);
  // Moves each belief's table into one of at least slots[i] slots, all in one submission (a batch's sessions whose
  // fold found their tables full grow together; one submission each was a round trip per session on a GPU). A table
  // that does not fit calls out_of_memory(i, error) (to name its session) before the error goes on.
  static void grow_all(std::span<GpuBelief* const> beliefs, std::span<const std::uint64_t> slots,
                       const std::function<void(std::size_t, const vk::OutOfMemory&)>& out_of_memory);
  // Reads ahead, for every belief of `beliefs` (one backend's), what an estimate asks first: the summary, and the
  // best k bins where the band's histogram holds them. Each pass runs once for all the beliefs (the stale bands'
  // rebuilds, the MASS and FLIP passes, the selections: three submissions) where each session's estimate made a
  // round trip per pass; later reads return what came back until the belief changes, the same answers as reading
  // one belief at a time. A belief whose band lost bins, or whose k best bins lie past its band, reads alone.
  static void read_ahead(std::span<const GpuBelief* const> beliefs, std::size_t k,
                         std::span<const KeyChoice> keys = {});
  // An estimate's first reads made in the next update's submission (a robot's touch: the update and the estimate's
  // summary in one round trip, where they took two). read_ahead marks each belief it read with its k; the next fold
  // of a marked belief adds the passes read_summaries runs (add_reads_after_fold: a stale list's rebuild, MASS, FLIP
  // and the best k's selection) after its own, and once that fold is complete keeps what came back
  // (keep_reads_after_fold) as the estimate's answers until the belief changes: the same answers as a read after the
  // update. A fold that found its table full runs again after the growth, its reads with it. The mark lasts one
  // update (end_update): a session updated without an estimate is not read ahead again until one asks. With a key
  // choice (keys[i]), the fold's submission also chooses the keys the estimate will read and looks them up
  // (belief_hoods.comp); the estimate that asks for exactly those keys then reads nothing (a touch: one round trip).
  bool add_reads_after_fold(std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                            std::vector<vk::Copy>* reads) const;
  static void keep_reads_after_fold(std::span<const GpuBelief* const> beliefs);
  void end_update() const {
    ahead_k_ = 0;
    ahead_keys_ = {};
  }
  // Looks up keys[i] in beliefs[i] for all of them in one submission; offsets() of keys among them then returns
  // what came back until the belief changes (a key not among them: every key of that call from the device).
  static void look_up_ahead(std::span<const GpuBelief* const> beliefs,
                            std::span<const std::vector<std::uint64_t>> keys);
  // The device memory a belief of `bins` touched bins holds at most: its table kept at most half full (a power of
  // two of slots: keys, offsets, band marks), a band list of two sides as long as the table, and its state words.
  static std::uint64_t bytes_at(std::uint64_t bins, std::uint32_t objects);

 private:
  // The table a growth to at least `slots` slots takes: a power of two, at least twice the current one and 64.
  std::uint64_t grown_slots(std::uint64_t slots) const;
  // A move of the table prepared: the new table (allocated, not yet cleared), the fills that clear it and the rehash
  // into it, run alone (move_to) or with other sessions' moves in one submission (keep_half_empty).
  struct Move {
    vk::Buffer next;
    std::uint64_t slots = 0;
    bool forget = false;  // forget_below's: the bins change, and what was read of them is forgotten
    std::vector<vk::Fill> fills;
    vk::Dispatch rehash;
  };
  // Prepares *m (at a stable address: the dispatch and fills point into it) into a table of `slots` slots.
  void prepare_move(Move* m, std::uint64_t slots, bool forget, std::uint64_t below);
  // After the submission: true when the rehash placed every key (the new table is the belief's now).
  bool adopt(Move& m);
  // The new table of a move, not yet cleared (its fills clear it).
  void allocate_uncleared(vk::Buffer& b, std::uint32_t capacity) const;
  // The fills that empty a table of `capacity` slots in place (keys empty, offsets and band marks 0), for a
  // submission of the caller's.
  static std::vector<vk::Fill> clear_fills(vk::Buffer& b, std::uint64_t capacity);
  // reset_all's part for this belief: its buffers made where it has none, and the fills that empty them.
  std::vector<vk::Fill> prepare_reset();
  // Moves the table into one of at least `slots` slots (a power of two); with
  // `forget`, only the bins at or above `below` and those in `keep_` (sorted linear keys).
  void move_to(std::uint64_t slots, bool forget, std::uint64_t below);
  gpu::SvaReduceParams reduce_params(std::uint32_t pass) const;
  // Passes of belief_reduce.comp over `entries` entries (or slots) each, for a submission.
  std::vector<vk::Dispatch> reduce_dispatches(const std::vector<std::uint32_t>& passes, std::uint64_t entries) const;
  // Runs passes of belief_reduce.comp over `invocations` entries (or slots) each.
  void run_reduce(const std::vector<std::uint32_t>& passes, std::uint64_t entries, std::vector<vk::Fill> fills = {},
                  const std::vector<vk::Copy>& reads = {}) const;
  // Runs one submission (of one belief's passes or of many beliefs'), its GPU time counted; `reads` bring back what
  // the passes wrote (state_reads) in the same submission.
  static void run(GpuBeliefKernels& k, const std::vector<vk::Dispatch>& ds, const std::vector<vk::Fill>& fills,
                  const std::vector<vk::Copy>& reads = {});
  // The state's words [word, word + words) as the host reads them. Where the state is not host-mapped (a discrete
  // GPU), a copy into its readback mirror, for the submission of the passes that write them: one staged download per
  // belief after it cost every session of a batch a round trip of its own. Empty where the state is mapped.
  std::vector<vk::Copy> state_reads(std::size_t word, std::size_t words) const;
  // Those words after that submission: from the mapped state or from the mirror its copy filled.
  void read_state_words(std::uint64_t* out, std::size_t word, std::size_t words) const;
  // The band list from scratch, on a side of at least `entries` entries: the list made large enough and the fills
  // that empty it (prepare_rebuild), the REBUILD pass in the caller's submission, then the list is current (rebuilt).
  std::vector<vk::Fill> prepare_rebuild(std::uint64_t entries) const;
  void rebuilt() const;
  // Where the table moved since the list was built: its rebuild (fills and pass) for the caller's submission, ahead
  // of a pass that reads the list; rebuilt() after it.
  void add_rebuild_if_stale(std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills) const;
  // The fills that zero the masses and histogram before the MASS pass.
  std::vector<vk::Fill> mass_fills() const;
  // The state's words after the MASS and FLIP passes, to the summary; false when a fold found the band list full
  // (what the passes read was incomplete): the list is then to be rebuilt larger (enlarge_band) and read again.
  bool read_state() const;
  void enlarge_band() const;
  // The MASS and FLIP passes, then the state's words to the host.
  void reduce() const;
  // The summary's passes for a submission of the caller's (read_summaries', or after an update's fold): the MASS and
  // FLIP passes with their fills, the best k bins' selection where k > 1, and the state's words back.
  void add_summary_reads(std::size_t k, std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                         std::vector<vk::Copy>* reads) const;
  // The same for every belief of `pending` (one backend's), each pass in one submission for all of them; with k > 1,
  // each one's best k bins in that submission too, where the band holds them (add_selection_ahead).
  static void read_summaries(std::vector<const GpuBelief*> pending, std::size_t k);
  // The candidates' room of a selection made ahead of the host's bucket: when the bucket holds more bins, the host
  // selects again with the exact count.
  static std::uint64_t selection_room(std::size_t k);
  // The BUCKET and SELECT passes for the best k bins, after this belief's MASS and FLIP in one submission; then, from
  // what came back, the best k kept (keep_selection_ahead) unless they lie past the band or the room was short.
  void add_selection_ahead(std::size_t k, std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                           std::vector<vk::Copy>* reads) const;
  void keep_selection_ahead(std::size_t k) const;
  // Whether a top-k past the band takes passes over the table's slots (a GPU, or staged), or the host reads the table
  // (a CPU device, whose passes would run on the same cores).
  bool passes_over_table() const;
  // The BUCKET or TABLE_BUCKET pass for the best k bins.
  vk::Dispatch bucket_dispatch(std::uint32_t pass, std::size_t k) const;
  // The fill that empties the table's histogram (its own words, after the band's).
  vk::Fill table_histogram_fill() const;
  // The belief changed: its summary and best bins are to be read again.
  void forget_cache() const;
  // After a selection of the best `asked` bins from `candidates` (every bin nearer the maximum than some distance: a
  // band's or a table's buckets up to one, or the whole table; the summary current): the band's next floor, at the
  // k-th best offset, k the most bins asked since it was dropped. It takes effect at once where every bin above it is
  // on the list already; else at the next MASS pass (take_floor), with the list rebuilt where it comes down.
  void keep_floor(std::span<const BinOffset> candidates, std::size_t asked) const;
  // The next floor in effect, before a submission's rebuild and MASS pass: a lower one makes the list stale; none
  // where two estimates in a row asked for fewer bins than it holds.
  void take_floor() const;
  // No floor (a new or reset session, or bins forgotten).
  void drop_floor() const;
  // best_bins without the kept answer: the k best bins from the device.
  std::vector<BinOffset> select_best(std::size_t k) const;
  // The first bucket whose cumulative count reaches k, and that count (SVA_BELIEF_BUCKETS when none does).
  static std::pair<std::uint32_t, std::uint64_t> bucket_holding(std::span<const std::uint64_t> histogram,
                                                                std::size_t k);
  // The lookup of `keys` (in queries_) as a dispatch, and its answers read back.
  vk::Dispatch lookup_dispatch(std::span<const std::uint64_t> keys, std::vector<vk::Copy>* reads) const;
  std::vector<std::uint64_t> read_lookup(std::size_t n) const;
  // Every bin of the table, in slot order (table() sorts them by key).
  std::vector<BinOffset> unsorted_table() const;
  // The distance histogram of every bin of the table (a pass over every slot, into the state's words for it); its
  // pass, fill and read for a submission of the caller's, and what it read after it.
  std::vector<std::uint64_t> table_histogram() const;
  void add_table_histogram(std::vector<vk::Dispatch>* ds, std::vector<vk::Fill>* fills,
                           std::vector<vk::Copy>* reads) const;
  std::vector<std::uint64_t> read_table_histogram() const;
  // The bins up to `bucket` (n of them, from the histogram) of the band list or of the whole table.
  std::vector<BinOffset> select_candidates(std::uint32_t pass, std::uint32_t bucket, std::uint64_t n,
                                           std::uint64_t entries) const;
  // Its parts: the selection's dispatch and fill (for a submission), then its n bins read back.
  vk::Dispatch select_dispatch(std::uint32_t pass, std::uint32_t bucket, std::uint64_t n, std::uint64_t entries) const;
  vk::Fill select_fill() const;
  std::vector<BinOffset> read_candidates(std::uint64_t n) const;
  // The best k of `out` (candidates holding them), best first, kept as best_bins' answer for k.
  std::vector<BinOffset> keep_best(std::vector<BinOffset> out, std::size_t k) const;
  // read_ahead's selections: each belief's best k bins in one submission, from its band where the band's histogram
  // holds them, else (on a GPU) from its whole table, whose histograms come first in one submission of their own.
  struct BestRead {
    const GpuBelief* belief;
    std::size_t k;
    std::vector<std::uint64_t> histogram;  // the band's, or the table's for a selection past the band
    std::uint32_t pass = SVA_REDUCE_SELECT;
  };
  static void read_best_ahead(std::span<const GpuBelief* const> beliefs, std::size_t k);
  static void read_table_histograms_ahead(std::vector<BestRead>& sel);

  GpuBeliefKernels* k_;
  std::uint64_t eps_units_;
  std::uint32_t mass_bits_;
  std::uint64_t band_width_;
  // Mutable for the band marks at its end, which the estimate's compaction clears.
  mutable vk::Buffer table_;
  std::uint32_t capacity_ = 0;
  mutable std::size_t table_allocations_ = 0;
  std::size_t count_ = 0, pairs_ = 0;
  // The estimate's state (SVA_STATE_* words) and the band list's two sides.
  mutable vk::Buffer state_, band_;
  mutable vk::Buffer state_mirror_;  // state_reads' copies of the state words (a readback buffer), where unmapped
  mutable std::uint32_t band_capacity_ = 0;
  mutable bool band_stale_ = false;  // the table moved (its slots changed): rebuild before reading the list
  mutable vk::Buffer candidates_, queries_;
  // Where the host reads the two on a discrete GPU: host-cached copies made in the submission (gpu::add_mirror_read).
  mutable vk::Buffer candidates_mirror_, queries_mirror_;
  vk::Buffer keep_;         // forget_below's kept keys
  vk::Buffer move_status_;  // a move's rehash: nonzero when a probe ran too long (one word, kept between moves)
  std::uint32_t keep_count_ = 0;
  // The band's floor in effect (the passes' and the fold's), the number of best bins it holds, and the next ones.
  mutable std::uint64_t floor_ = kNoFloor, next_floor_ = kNoFloor;
  mutable std::size_t floor_k_ = 0, next_floor_k_ = 0;
  // Estimates in a row, one an update, that asked for fewer bins than the next floor holds since a selection last
  // kept it (take_floor drops it at two), and the most bins best_bins or read_ahead was asked since the last fold.
  mutable unsigned floor_age_ = 0;
  mutable std::size_t asked_since_fold_ = 0;
  // Whether the update's submission selected past the band (its table's histogram read with the band's).
  mutable bool table_ahead_ = false;
  mutable std::optional<BeliefSummary> summary_cache_;
  // best_bins' last answer (the best kept_asked_ bins), until the belief changes.
  mutable std::vector<BinOffset> kept_best_;
  mutable std::size_t kept_asked_ = 0;
  mutable std::vector<std::uint64_t> histogram_;
  // The best bins the last read_ahead asked (0: none since the last update) and how its keys are chosen: what the next
  // fold reads ahead; whether that fold's submission chose the keys (hoods_ holds them).
  mutable std::size_t ahead_k_ = 0;
  mutable KeyChoice ahead_keys_;
  mutable bool keys_chosen_ = false;
  mutable std::size_t last_keys_ = 0;          // how many keys the last estimate read
  mutable vk::Buffer hoods_, hoods_mirror_;    // belief_hoods.comp's output, and its copy where unmapped
  mutable vk::Buffer priors_;                  // its pose priors' terms (KeyChoice::prior), mapped
  mutable std::vector<float> priors_written_;  // what priors_ holds
  // The key choice's dispatches, after the selection in the fold's submission; false where it cannot be made there.
  bool add_key_choice(std::vector<vk::Dispatch>* ds, std::vector<vk::Copy>* reads) const;
  gpu::SvaHoodParams hood_params(std::uint32_t pass, std::uint64_t steps, std::uint64_t keys) const;
  vk::Buffer& priors_buffer() const;
  // The keys it chose and their offsets, as look_up_ahead's answers.
  void keep_key_choice() const;
  // look_up_ahead's keys and their offsets, in the order asked, until the belief changes.
  mutable std::vector<std::uint64_t> looked_up_keys_, looked_up_offsets_;
  // The offsets of `keys` from look_up_ahead's answers; false when one is not among them.
  bool looked_up(std::span<const std::uint64_t> keys, std::vector<std::uint64_t>* out) const;
};

}  // namespace sva
