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
  float weight;
};

// A run of map entries (local to one chunk) matched against one key item.
struct SvaGpuWorkItem {
  uint key_item;
  uint entry_begin;
};

// One training reading of the map: position, normConf, normal, object.
struct SvaGpuReading {
  float px, py, pz, conf;
  float nx, ny, nz;
  uint object;
};

// Push constants of match_votes.comp (<= 128 bytes).
struct SvaMatchParams {
  uint base;             // first work index of this dispatch
  uint total;            // work indices in this chunk
  uint work_items;       // SvaGpuWorkItem count (work_offset has one more)
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

// Probes of the binary search over work offsets: enough for 2^32 items.
#define SVA_MAX_SEARCH_STEPS 33

#endif
