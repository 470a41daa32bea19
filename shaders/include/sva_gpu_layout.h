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
  uint pad;
};

// One map key an observed pair looks up (VoteBatch::keys) and its weight.
struct SvaGpuKeyItem {
  uint pair;
  uint key;
  float weight;
  uint pad;
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
  uint bins_lo;          // pose bins per (object-inclusive) space, low and high words
  uint bins_hi;
};

// Probes of a binary search: enough for 2^32 items.
#define SVA_MAX_SEARCH_STEPS 33
// Invocations of the single-workgroup scan; each sums a contiguous block.
#define SVA_SCAN_WIDTH 256
// Key items per batch such that a scan block stays far below lavapipe's loop cut-off.
#define SVA_MAX_KEY_ITEMS (SVA_SCAN_WIDTH * 16384)

#endif
