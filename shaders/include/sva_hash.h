// Hash of 64-bit pose-bin keys, shared verbatim by C++ and GLSL so the GPU hash
// table and any CPU mirror probe the same slots. Needs uint64_t in scope and
// (GLSL) GL_EXT_shader_explicit_arithmetic_types_int64.
#ifndef SVA_HASH_H
#define SVA_HASH_H
#ifdef __cplusplus
#define SVA_INLINE inline
#else
#define SVA_INLINE
#endif

// The 64-bit finaliser of MurmurHash3: every key bit affects every slot bit,
// so structured keys (bit fields of bin indices) spread evenly.
SVA_INLINE uint64_t sva_hash64(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdUL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53UL;
  k ^= k >> 33;
  return k;
}

// Keys never take this value (pose keys use at most 62 bits).
#define SVA_HASH_EMPTY_KEY 0xffffffffffffffffUL

#endif
