// Buffer layouts and limits of the Vulkan vote backend, shared by the C++ host
// (host/src/backends/vulkan/vulkan_vote_backend.cpp) and the GLSL kernels. Structs hold
// 4-byte scalars only, so std430 and C++ agree without padding rules.
#ifndef SVA_GPU_LAYOUT_H
#define SVA_GPU_LAYOUT_H

// One observed pair: both patches (robot frame) and its session.
struct SvaGpuPair {
  float ax, ay, az, aconf;
  float anx, any, anz;
  uint session;
  float bx, by, bz, bconf;
  float bnx, bny, bnz;
  uint fold_count;            // times the pair's factor is folded (2: both orders of Eq 5)
  uint item_begin, item_end;  // the pair's key items (they own its matches, sva_match_likelihood.h)
  uint pad0, pad1;
};

// Device addresses of one map chunk's entry arrays, so that a match finds its
// map pair under the pair's other keys wherever their entries lie.
struct SvaGpuChunk {
  uint a_lo, a_hi;
  uint b_lo, b_hi;
  uint w_lo, w_hi;
  uint pad0, pad1;
};

// One map key an observed pair looks up (VoteBatch::keys) and its weight.
struct SvaGpuKeyItem {
  uint pair;
  uint key;
  float weight;
  uint reversed;  // 1: the entries under this key match the observed pair with their ends swapped
};

// The map entries [begin, end) stored under a key item's key (empty if absent).
struct SvaGpuRange {
  uint begin;
  uint end;
};

// Written by scan_matches.comp: the indirect dispatch of match_votes.comp
// (VkDispatchIndirectCommand first) and the number of matches in the chunk.
struct SvaScanResult {
  uint groups_x, groups_y, groups_z;
  uint total;
  uint too_many;  // 1: more than 2^32 - 1 matches in one chunk (the host splits the batch)
};

// Push constants of expand_pair_keys.comp.
struct SvaExpandParams {
  uint key_items;
  uint map_keys;
};

// Push constants of scan_matches.comp.
struct SvaScanParams {
  uint key_items;
  uint chunk_begin;   // map entries of this chunk: [chunk_begin, chunk_end)
  uint chunk_end;
  uint max_groups_x;  // maxComputeWorkGroupCount[0]
};

// One training reading of the map: position, normConf, normal, object.
struct SvaGpuReading {
  float px, py, pz, conf;
  float nx, ny, nz;
  uint object;
};

// Push constants of match_votes.comp (<= 128 bytes).
struct SvaMatchParams {
  uint key_items;        // work_offset has key_items + 1 values
  uint chunk_begin;      // first map entry of the bound chunk
  uint chunk_end;
  uint capacity;         // hash table slots (power of two)
  uint objects;
  uint grid_kind;
  int translation_bins;
  float translation_min;
  float translation_width;
  int rotation_bins;
  float rotation_width;
  float likelihood_cutoff;
  uint dim_tz;           // 1 for planar spaces
  uint dim_rxy;          // 1 for planar spaces
  uint object_shift;     // linear bin = object << object_shift | index within the object
  uint pair_shift;       // vote key = pair << pair_shift | linear bin
  uint chunk_shift;      // log2 of the entries per map chunk (the last may hold fewer)
};
// Counters per pair written by match_votes.comp.
// Per pair: matches, votes inside, votes outside, votes inside of zero mass, and the vote table's atomics (the
// work `sva bench` counts): adds (one per vote after subgroup pre-aggregation) and key compare-and-swaps (probes).
#define SVA_PAIR_COUNTERS 6u

// One session of a fold: its belief table (device address of `capacity` keys
// followed by `capacity` offsets and capacity / 32 band marks, capacity a
// power of two), its estimate state (SVA_STATE_*) and band list, and whether
// this pass folds into it (0: the session's pairs only add to their totals).
struct SvaGpuSession {
  uint table_lo, table_hi;
  uint capacity;
  uint fold;
  uint state_lo, state_hi;
  uint band_lo, band_hi;
  uint band_capacity;  // entries per side of the band list
  // The band's floor (sva_on_band); all ones: none (no offset reaches
  // 2^64 - 1).
  uint floor_lo, floor_hi;
  uint pad0;
};

// What a fold pass reports per session.
struct SvaGpuSessionStatus {
  uint overflow;      // a key found no slot within SVA_HASH_MAX_PROBE: grow and fold again
  uint missing;       // internal error: the add pass did not find a reserved key
  uint inserted;      // keys new to the table
  uint vote_entries;  // vote-table entries of the session's pairs (bounds the new keys)
};

// Push constants of belief_fold.comp.
struct SvaFoldParams {
  uint slots;                     // vote-table slots
  uint pair_shift;                // vote key = pair << pair_shift | linear bin
  uint eps_lo, eps_hi;            // sva::belief_math::eps_units
  uint pass;                      // SVA_FOLD_*
  uint pairs;                     // pairs of the batch (SVA_FOLD_PAIR_LOG)
  uint sessions;                  // sessions of the batch (SVA_FOLD_RESET)
  uint objects;
  uint object_shift;              // object = linear bin >> object_shift
  uint band_width_lo, band_width_hi;  // a bin is in the band when M - offset < band width (belief units)
};
#define SVA_FOLD_RESERVE 0u
#define SVA_FOLD_PAIR_LOG 1u  // per pair: log2(total eps), the term every bin of the pair subtracts
#define SVA_FOLD_ADD 2u    // also raises the maximum and each object's best offset
#define SVA_FOLD_RESET 3u  // per object whose best offset rose: forget its best key
#define SVA_FOLD_BEST 4u   // the smallest key at each best offset; bins new to the band join its list

// A session's estimate state (uint64 words, device memory), kept current by
// the fold because offsets only grow: the maximum M, each object's touched
// bins, best offset and smallest key at it, and the *band* list of the bins
// within the band width of M (the only ones whose mass 2^(offset - M) at
// mass_bits is not 0, see backends/cpu/belief.hpp) or at or above the band's
// floor (the estimate's k-th best offset, kept by the host: sva_on_band). The
// floor is an offset, not a distance below M: a bin above it stays above it,
// so the list keeps holding the best k bins however far the maximum runs
// ahead, and a selection of them needs no pass over the table. The band list
// has two sides: the estimate compacts the current side into the other, dropping
// bins that fell out of the band, then flips. Then per object, written by
// the estimate: the mass; and the histogram of distances below M of the
// band's bins (bucket = sva_distance_bucket(d)).
#define SVA_STATE_MAX 0
#define SVA_STATE_BAND_COUNT 1   // entries on the current side (may exceed its capacity: see BAND_LOST)
#define SVA_STATE_BAND_SIDE 2    // 0 or 1
#define SVA_STATE_NEXT_COUNT 3   // entries on the other side, during the estimate's compaction
#define SVA_STATE_BAND_LOST 4    // 1: an append found the list full; the host rebuilds it larger
#define SVA_STATE_CANDIDATES 5   // top-k candidates found by SVA_REDUCE_SELECT
#define SVA_STATE_SELECT_BUCKET 6  // the bucket SVA_REDUCE_BUCKET chose for a SELECT in the same submission
#define SVA_STATE_TABLE_BUCKET 7   // and SVA_REDUCE_TABLE_BUCKET for a TABLE_SELECT (when the band held too few)
#define SVA_STATE_OBJECTS 8      // then touched[o], best_offset[o], best_key[o], raised[o], mass[o]
#define SVA_STATE_ARRAYS 5
#define SVA_BELIEF_BUCKETS 1025  // 0 for d = 0, then 16 per bit of the highest set bit of d
// After the band's histogram, the whole table's (SVA_REDUCE_TABLE_HISTOGRAM), as many words.

// Push constants of belief_rehash.comp: move every key of the old table into
// the new one; with `forget`, only the bins at or above keep_lo/hi and those
// in the sorted keep list, counted per object into the state's touched array.
struct SvaRehashParams {
  uint old_lo, old_hi, old_capacity;
  uint new_lo, new_hi, new_capacity;
  uint forget;
  uint keep_lo, keep_hi;
  uint keep_count;
  uint state_lo, state_hi;
  uint objects, object_shift;
};

// Push constants of belief_reduce.comp, one session per dispatch: the
// estimate's passes over the session's band list (and, to rebuild that list,
// over its table).
struct SvaReduceParams {
  uint table_lo, table_hi, capacity;
  uint pass;                   // SVA_REDUCE_*
  uint objects;
  uint mass_bits;
  uint object_shift;           // object = linear bin >> object_shift
  uint select_bucket;          // SELECT: bins whose distance bucket is <= this
  uint select_capacity;        // SELECT: room in the candidate list
  uint state_lo, state_hi;     // SVA_STATE_* words
  uint band_lo, band_hi;       // the band list: two sides of band_capacity slot indices
  uint band_capacity;
  uint band_width_lo, band_width_hi;
  uint floor_lo, floor_hi;     // the band's floor (sva_on_band)
};
#define SVA_REDUCE_MASS 0u     // per band entry: object masses, distance histogram, compaction
#define SVA_REDUCE_FLIP 1u     // one invocation: the compacted side becomes the current one
#define SVA_REDUCE_SELECT 2u   // the band's bins up to select_bucket into the candidate list
#define SVA_REDUCE_REBUILD 3u  // per table slot: the band list from scratch (after a growth or a lost append)
#define SVA_REDUCE_TABLE_HISTOGRAM 4u  // per table slot: the distance histogram of every bin (top-k past the band)
#define SVA_REDUCE_TABLE_SELECT 5u     // per table slot: the bins up to select_bucket into the candidate list
// One workgroup: the first bucket of the band's histogram at which select_capacity bins are reached, into
// SVA_STATE_SELECT_BUCKET (SVA_BELIEF_BUCKETS: the band holds fewer), so that a SELECT after the MASS pass needs no
// round trip to the host between them.
#define SVA_REDUCE_BUCKET 6u
#define SVA_SELECT_FROM_STATE 0xffffffffu  // SELECT's select_bucket: the one SVA_REDUCE_BUCKET chose
// For a top-k past the band in the same submission: TABLE_HISTOGRAM with select_bucket SVA_SELECT_FROM_STATE runs
// only where BUCKET found the band short; TABLE_BUCKET (one workgroup) picks the bucket from the table's histogram
// there (SVA_BELIEF_BUCKETS elsewhere); TABLE_SELECT with SVA_SELECT_FROM_STATE selects with it.
#define SVA_REDUCE_TABLE_BUCKET 7u

// Push constants of belief_hoods.comp: what an estimate reads by key (host/src/estimate/hypotheses.cpp's
// hypothesis_keys), chosen on the device after an update's fold and its best bins' selection, so that the estimate
// after a touch needs no round trip of its own: up to `modes` distinct modes among the best `best` bins (greedy,
// no two within `suppress` grid steps of one object), then every touched object's best bin, and the neighbourhood of
// each (within `radius` steps, the centre first), with their offsets, in the host's order. With pose priors
// (`priors` 1: the third buffer holds SVA_PRIOR_FLOATS per object, PoseWeighting::device_terms), the modes' `mode_best`
// candidates are ordered by evidence plus prior first, and an object's best bin is the best under its prior among the
// `prior_best` best bins (host/src/estimate/pose_prior.hpp), each in floats: a near tie that floats order otherwise
// makes the host's list differ, and the host then reads its keys itself.
struct SvaHoodParams {
  uint table_lo, table_hi, capacity;
  uint state_lo, state_hi;
  uint pass;  // SVA_HOODS_*
  uint objects, object_shift;
  uint room;  // entries of the candidate list (SELECT's select_capacity)
  uint best, modes, suppress, radius;
  uint translation_bins, rotation_bins, planar;
  uint keys;   // room for keys in the output
  uint steps;  // neighbour steps per centre, the grid's edges ignored (the KEYS pass's invocations per centre)
  uint mode_best;   // of the best `best`, the modes' candidates (`best` without priors)
  uint prior_best;  // of the best `best`, an object's best bin's under its prior
  uint priors;      // 1: pose priors in the third buffer
  float translation_min_mm, translation_bin_mm;  // the grid's corner and bin width (a bin's centre, for the priors)
};
// A pose prior's terms per object, in floats (PoseWeighting::device_terms): [0] 1 where the object has one, [1..3]
// its mean position in the grid's frame, [4] log2 weight per mm^2 of distance, [5] per rad^2 of turn (0: position
// only), [6..14] its mean rotation in the grid's frame (column-major), [15] unused.
#define SVA_PRIOR_FLOATS 16
// The most candidates a prior orders on the device (one invocation sorts them); more: the host chooses the keys.
#define SVA_PRIOR_MOST_CANDIDATES 256u
#define SVA_HOODS_RANK 0u     // per candidate: its place among them (offset descending, key ascending); the best kept
#define SVA_HOODS_CENTRES 1u  // one workgroup: the centres and the place of each one's neighbourhood
#define SVA_HOODS_KEYS 2u     // per (centre, step): the neighbour's packed key and offset at its place
// The output's u64 words: [0] keys in all (SVA_HOODS_NONE: not chosen here, the host reads them), [1] centres, then
// the best `best` (linear key, offset) pairs in order, then per centre its linear key and the place of its first key,
// then the (packed key, offset) pairs.
#define SVA_HOODS_HEADER 2
#define SVA_HOODS_NONE 0xffffffffffffffffUL

// Push constants of belief_lookup.comp.
struct SvaLookupParams {
  uint table_lo, table_hi, capacity;
  uint queries;
};

// Table slots each invocation of the fold, rehash and reduction kernels visits
// (a bounded loop): fewer, fuller workgroups; a workgroup covers
// SVA_WORKGROUP_SIZE * SVA_SLOTS_PER_INVOCATION consecutive slots.
#define SVA_SLOTS_PER_INVOCATION 16u

// Probes of a binary search: enough for 2^32 items.
#define SVA_MAX_SEARCH_STEPS 33
// Invocations of the single-workgroup scan; each sums a contiguous block.
#define SVA_SCAN_WIDTH 256
// Key items per batch such that a scan block stays far below lavapipe's loop cut-off.
#define SVA_MAX_KEY_ITEMS (SVA_SCAN_WIDTH * 16384)

#endif
