// Buffer layouts and limits of the Vulkan vote backend, shared by the C++ host
// (host/src/vulkan/vulkan_vote_backend.cpp) and the GLSL kernels. Structs hold
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
  uint chunk_entries;    // entries per map chunk (the last may hold fewer)
};
// Counters per pair written by match_votes.comp.
#define SVA_PAIR_COUNTERS 4u  // matches, votes inside, votes outside, votes inside of zero mass

// One session of a fold: its belief table (device address of `capacity` keys
// followed by `capacity` offsets, capacity a power of two) and whether this
// pass folds into it (0: the session's pairs only add to their totals).
struct SvaGpuSession {
  uint table_lo, table_hi;
  uint capacity;
  uint fold;
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
  uint slots;             // vote-table slots
  uint pair_shift;        // vote key = pair << pair_shift | linear bin
  uint eps_lo, eps_hi;    // sva::belief_math::eps_units
  uint pass;              // SVA_FOLD_RESERVE or SVA_FOLD_ADD
  uint pairs;             // pairs of the batch (SVA_FOLD_PAIR_LOG)
};
#define SVA_FOLD_RESERVE 0u
#define SVA_FOLD_PAIR_LOG 1u  // per pair: log2(total eps), the term every bin of the pair subtracts
#define SVA_FOLD_ADD 2u

// Push constants of belief_rehash.comp: move every key of the old table into the new one.
struct SvaRehashParams {
  uint old_lo, old_hi, old_capacity;
  uint new_lo, new_hi, new_capacity;
};

// Push constants of belief_reduce.comp, one session's table per dispatch.
struct SvaReduceParams {
  uint table_lo, table_hi, capacity;
  uint pass;                   // SVA_REDUCE_MAX, SVA_REDUCE_MASS or SVA_REDUCE_SELECT
  uint objects;
  uint mass_bits;
  uint object_shift;           // object = linear bin >> object_shift
  uint select_bucket;          // SELECT: bins whose distance bucket is <= this
  uint select_capacity;        // SELECT: room in the candidate list
};
#define SVA_REDUCE_MAX 0u
#define SVA_REDUCE_MASS 1u
#define SVA_REDUCE_SELECT 2u

// The summary buffer of belief_reduce.comp (uint64 words): the maximum, the
// candidate count, four per-object arrays, then the histogram of distances
// below the maximum (bucket = SVA_BELIEF_BUCKET(d), see sva_belief_table.glsl).
#define SVA_SUMMARY_MAX 0
#define SVA_SUMMARY_CANDIDATES 1
#define SVA_SUMMARY_OBJECTS 2  // then touched[o], touched_mass[o], best_offset[o], best_key[o], each `objects` long
#define SVA_BELIEF_BUCKETS 1025  // 0 for d = 0, then 16 per bit of the highest set bit of d

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
