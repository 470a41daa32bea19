// GLSL only: a session's belief table on the device, reached through its
// device address (GL_EXT_buffer_reference) because it grows past what one
// binding may span. Layout: `capacity` keys (uint64, SVA_HASH_EMPTY_KEY when
// free), `capacity` offsets (uint64 belief units), then capacity / 32 words
// of band marks (bit set: the slot is on the band list); capacity is a power
// of two. Keys are linear pose-bin indices (object included), whose
// order is the packed keys' order. Open addressing with the vote table's hash
// and probe bound. The includer enables GL_EXT_buffer_reference and
// GL_EXT_shader_explicit_arithmetic_types_int64 and includes sva_shared.h and
// sva_hash.h.
layout(buffer_reference, std430, buffer_reference_align = 8) buffer SvaWords { uint64_t w[]; };

layout(buffer_reference, std430, buffer_reference_align = 4) buffer SvaWords32 { uint w[]; };

uint64_t sva_address(uint lo, uint hi) { return uint64_t(lo) | (uint64_t(hi) << 32); }
SvaWords sva_table_keys(uint lo, uint hi) { return SvaWords(sva_address(lo, hi)); }
SvaWords sva_table_offsets(uint lo, uint hi, uint capacity) {
  return SvaWords(sva_address(lo, hi) + uint64_t(capacity) * 8ul);
}
SvaWords32 sva_table_marks(uint lo, uint hi, uint capacity) {
  return SvaWords32(sva_address(lo, hi) + uint64_t(capacity) * 16ul);
}

// Word of per-object array `a` (0 touched, 1 best offset, 2 best key, 3
// raised, 4 mass) of a session's estimate state, and of histogram bucket b.
uint sva_state_object(uint a, uint objects, uint object) { return SVA_STATE_OBJECTS + a * objects + object; }
uint sva_state_bucket(uint objects, uint b) { return SVA_STATE_OBJECTS + SVA_STATE_ARRAYS * objects + b; }
uint sva_state_table_bucket(uint objects, uint b) { return sva_state_bucket(objects, SVA_BELIEF_BUCKETS + b); }
#define SVA_STATE_TOUCHED 0u
#define SVA_STATE_BEST_OFFSET 1u
#define SVA_STATE_BEST_KEY 2u
#define SVA_STATE_RAISED 3u
#define SVA_STATE_MASS 4u

// Whether a bin belongs on the band list, with the maximum `max`: within the band width below it (its mass is not
// 0), or at or above the band's floor (sva_gpu_layout.h). Both are bounds on M - offset at one M, so the list holds
// every bin nearer M than some distance: the best k bins wherever it holds k.
bool sva_on_band(uint64_t max, uint64_t offset, uint64_t band_width, uint64_t band_floor) {
  return max - offset < band_width || offset >= band_floor;
}

// Puts table slot `slot` on the band list unless its mark says it is there:
// one append per bin however many invocations find it. A full side raises
// BAND_LOST (the host rebuilds the list larger before the estimate reads it).
void sva_band_join(SvaWords state, SvaWords32 marks, SvaWords32 band, uint band_capacity, uint slot) {
  uint bit = 1u << (slot & 31u);
  if ((marks.w[slot >> 5] & bit) != 0u) return;
  if ((atomicOr(marks.w[slot >> 5], bit) & bit) != 0u) return;
  uint64_t n = atomicAdd(state.w[SVA_STATE_BAND_COUNT], 1ul);
  if (n >= uint64_t(band_capacity)) {
    state.w[SVA_STATE_BAND_LOST] = 1ul;
    return;
  }
  band.w[uint(state.w[SVA_STATE_BAND_SIDE]) * band_capacity + uint(n)] = slot;
}

// The slot holding `key`, inserting it when absent (`inserted` tells); capacity
// when no slot was found within SVA_HASH_MAX_PROBE.
uint sva_table_reserve(SvaWords keys, uint capacity, uint64_t key, out bool inserted) {
  uint mask = capacity - 1u;
  uint slot = uint(sva_hash64(key)) & mask;
  inserted = false;
  for (uint probe = 0u; probe < SVA_HASH_MAX_PROBE; ++probe) {
    uint64_t prev = atomicCompSwap(keys.w[slot], SVA_HASH_EMPTY_KEY, key);
    if (prev == SVA_HASH_EMPTY_KEY) inserted = true;
    if (prev == SVA_HASH_EMPTY_KEY || prev == key) return slot;
    slot = (slot + 1u) & mask;
  }
  return capacity;
}

// The slot holding `key`, or capacity when absent. Reads only: every insert
// happened in an earlier dispatch.
uint sva_table_find(SvaWords keys, uint capacity, uint64_t key) {
  uint mask = capacity - 1u;
  uint slot = uint(sva_hash64(key)) & mask;
  for (uint probe = 0u; probe < SVA_HASH_MAX_PROBE; ++probe) {
    uint64_t k = keys.w[slot];
    if (k == key) return slot;
    if (k == SVA_HASH_EMPTY_KEY) return capacity;
    slot = (slot + 1u) & mask;
  }
  return capacity;
}

// Histogram bucket of a distance d below the maximum: monotone in d, 16
// buckets per power of two, so a top-k threshold rarely takes many extra bins.
uint sva_distance_bucket(uint64_t d) {
  if (d == 0ul) return 0u;
  uint p = sva_msb64(d);
  uint sub = p >= 4u ? uint(d >> (p - 4u)) & 15u : uint(d << (4u - p)) & 15u;
  return 1u + p * 16u + sub;
}

// Flat invocation index of a 2-D grid of SVA_WORKGROUP_SIZE-wide groups (vk::Context::grid).
uint sva_flat_index() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * SVA_WORKGROUP_SIZE + gl_LocalInvocationID.x;
}

// The k-th slot (k < SVA_SLOTS_PER_INVOCATION) of this invocation, for
// kernels launched over ceil(slots / SVA_SLOTS_PER_INVOCATION) invocations:
// neighbouring invocations read neighbouring slots at every k.
uint sva_table_slot(uint k) {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  return (group * SVA_SLOTS_PER_INVOCATION + k) * SVA_WORKGROUP_SIZE + gl_LocalInvocationID.x;
}
