// GLSL only: fixed-point scatter into the open-addressing hash table with
// 64-bit keys, shared by every kernel that scatters votes. The includer
// declares the buffers `table_key[]` (uint64_t, empty = SVA_HASH_EMPTY_KEY),
// `table_sum[]` (int64_t) and `overflow` (uint), and includes sva_hash.h.
// Linear probing is bounded by SVA_HASH_MAX_PROBE; a key that finds no slot
// raises `overflow` so that the host grows the table and runs again.
// Returns the slots probed (compare-and-swaps), for the work counted.
uint sva_hash_scatter(uint64_t key, int64_t units, uint capacity) {
  uint mask = capacity - 1u;
  uint slot = uint(sva_hash64(key)) & mask;
  for (uint probe = 0u; probe < SVA_HASH_MAX_PROBE; ++probe) {
    uint64_t prev = atomicCompSwap(table_key[slot], SVA_HASH_EMPTY_KEY, key);
    if (prev == SVA_HASH_EMPTY_KEY || prev == key) {
      atomicAdd(table_sum[slot], units);
      return probe + 1u;
    }
    slot = (slot + 1u) & mask;
  }
  atomicOr(overflow, 1u);
  return SVA_HASH_MAX_PROBE;
}
