#version 460
// The estimate's passes over one session's band list: the bins within the
// band width of the maximum M, the only ones whose mass is not 0. The fold
// keeps M, the touched counts and the best bins current (belief_fold.comp),
// so no pass visits every slot of the belief table, except REBUILD, which
// the host runs only after the table grew or the list ran out of room.
//  MASS:    per band entry of the current side: a bin still in the band adds
//           sva_exp2_neg_units(M - offset) to its object's mass and counts in
//           the histogram of distances below M (top-k), and moves to the other
//           side; a bin that fell out of the band loses its mark (the band:
//           sva_on_band, within the band width or at or above its floor);
//  FLIP:    one invocation: the other side becomes the current one;
//  SELECT:  the band's bins whose distance bucket is at most select_bucket,
//           appended to the candidate list (the host sorts the few it gets);
//  BUCKET:  one workgroup: the bucket that SELECT needs for the best k bins,
//           from the histogram MASS made, so that the summary and the best
//           bins come back in one submission (the host checks it again);
//           TABLE_BUCKET the same from the table's histogram, where the band
//           held fewer than k bins;
//  REBUILD: per table slot: every bin in the band joins an empty list.
//  TABLE_HISTOGRAM, TABLE_SELECT: the histogram and the selection over every
//           slot, for a top-k that reaches past the band (an estimate's
//           next modes on a sharp belief): two passes and a few hundred
//           words back, where the whole table would cross the bus. Once a
//           session, in practice (again after light estimates that dropped
//           the floor): the band's floor then keeps those bins on the list
//           (sva_on_band).
// Integer sums, so the results equal the CPU reference's
// (host/src/backends/cpu/belief.cpp) whatever the order.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_hash.h"
#include "sva_belief_math.h"
#include "sva_gpu_layout.h"
#include "sva_belief_table.glsl"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) buffer Candidates { uint64_t candidate[]; };  // (key, offset) pairs

layout(push_constant) uniform Push { SvaReduceParams pc; };

SvaWords state() { return SvaWords(sva_address(pc.state_lo, pc.state_hi)); }
SvaWords32 band() { return SvaWords32(sva_address(pc.band_lo, pc.band_hi)); }
SvaWords32 marks() { return sva_table_marks(pc.table_lo, pc.table_hi, pc.capacity); }
uint64_t band_width() { return uint64_t(pc.band_width_lo) | (uint64_t(pc.band_width_hi) << 32); }
uint64_t band_floor() { return uint64_t(pc.floor_lo) | (uint64_t(pc.floor_hi) << 32); }

// Entry i of the current side of the band list, or capacity when past its end.
uint band_entry(uint i) {
  uint side = uint(state().w[SVA_STATE_BAND_SIDE]);
  uint64_t count = min(state().w[SVA_STATE_BAND_COUNT], uint64_t(pc.band_capacity));
  return uint64_t(i) < count ? band().w[side * pc.band_capacity + i] : pc.capacity;
}

void mass_entry(uint i) {
  uint slot = band_entry(i);
  if (slot == pc.capacity) return;
  SvaWords st = state();
  uint64_t key = sva_table_keys(pc.table_lo, pc.table_hi).w[slot];
  uint64_t offset = sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[slot];
  if (!sva_on_band(st.w[SVA_STATE_MAX], offset, band_width(), band_floor())) {
    atomicAnd(marks().w[slot >> 5], ~(1u << (slot & 31u)));
    return;
  }
  uint64_t d = st.w[SVA_STATE_MAX] - offset;
  uint object = uint(key >> pc.object_shift);
  // A bin on the list by the floor alone has mass 0 (past the band width): it adds nothing.
  if (d < band_width())
    atomicAdd(st.w[sva_state_object(SVA_STATE_MASS, pc.objects, object)], sva_exp2_neg_units(d, pc.mass_bits));
  atomicAdd(st.w[sva_state_bucket(pc.objects, sva_distance_bucket(d))], 1ul);
  uint other = 1u - uint(st.w[SVA_STATE_BAND_SIDE]);
  uint n = uint(atomicAdd(st.w[SVA_STATE_NEXT_COUNT], 1ul));  // <= the current side's entries: fits
  band().w[other * pc.band_capacity + n] = slot;
}

void select_slot(uint slot) {
  if (slot >= pc.capacity) return;
  // A bucket chosen on the device (ahead of the host) is checked first: where there is none, the pass reads nothing.
  SvaWords st = state();
  uint chosen = uint(st.w[pc.pass == SVA_REDUCE_TABLE_SELECT ? SVA_STATE_TABLE_BUCKET : SVA_STATE_SELECT_BUCKET]);
  uint bucket = pc.select_bucket == SVA_SELECT_FROM_STATE ? chosen : pc.select_bucket;
  if (bucket >= SVA_BELIEF_BUCKETS) return;  // too few bins for k here: another selection or the host's
  if (sva_table_keys(pc.table_lo, pc.table_hi).w[slot] == SVA_HASH_EMPTY_KEY) return;
  uint64_t offset = sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[slot];
  if (sva_distance_bucket(st.w[SVA_STATE_MAX] - offset) > bucket) return;
  uint64_t n = atomicAdd(st.w[SVA_STATE_CANDIDATES], 1ul);
  if (n < uint64_t(pc.select_capacity)) {
    candidate[2u * uint(n)] = sva_table_keys(pc.table_lo, pc.table_hi).w[slot];
    candidate[2u * uint(n) + 1u] = offset;
  }
}

void histogram_slot(uint slot) {
  if (slot >= pc.capacity) return;
  SvaWords st = state();
  // Ahead of the host (in the summary's submission): only where the band held too few bins.
  if (pc.select_bucket == SVA_SELECT_FROM_STATE && st.w[SVA_STATE_SELECT_BUCKET] < uint64_t(SVA_BELIEF_BUCKETS)) return;
  if (sva_table_keys(pc.table_lo, pc.table_hi).w[slot] == SVA_HASH_EMPTY_KEY) return;
  uint64_t d = st.w[SVA_STATE_MAX] - sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[slot];
  atomicAdd(st.w[sva_state_table_bucket(pc.objects, sva_distance_bucket(d))], 1ul);
}

// The workgroup's sums of its invocations' runs of buckets (first_bucket_holding).
shared uint64_t bucket_runs[SVA_WORKGROUP_SIZE];

uint64_t histogram_word(bool table, uint b) {
  return state().w[table ? sva_state_table_bucket(pc.objects, b) : sva_state_bucket(pc.objects, b)];
}

// The first bucket of the band's histogram (or, `table`, of the table's) whose cumulative count reaches
// select_capacity bins, or every touched bin where there are fewer (GpuBelief::bucket_holding of min(k, touched) on
// the host: an update's reads ahead ask for the k of the last estimate before its fold touched more bins);
// SVA_BELIEF_BUCKETS when none does. One workgroup: each invocation sums a run of buckets side by side, then
// invocation 0 walks the runs' sums and the one run that holds it (one invocation had walked up to 1,025 words of the
// device's memory one after another, once per session). Integer sums: the bucket the walk finds. The answer is
// invocation 0's; every invocation of the workgroup must call it (a barrier).
uint first_bucket_holding(bool table) {
  const uint per = (SVA_BELIEF_BUCKETS + SVA_WORKGROUP_SIZE - 1u) / SVA_WORKGROUP_SIZE;
  uint t = gl_LocalInvocationID.x, first = t * per, last = min(first + per, SVA_BELIEF_BUCKETS);
  uint64_t run = 0ul;
  for (uint b = first; b < last; ++b) run += histogram_word(table, b);
  bucket_runs[t] = run;
  barrier();
  if (t != 0u) return SVA_BELIEF_BUCKETS;
  SvaWords st = state();
  uint64_t touched = 0ul;
  for (uint o = 0u; o < pc.objects; ++o) touched += st.w[sva_state_object(SVA_STATE_TOUCHED, pc.objects, o)];
  uint64_t want = min(uint64_t(pc.select_capacity), touched);
  uint64_t n = 0ul;
  for (uint r = 0u; r < SVA_WORKGROUP_SIZE; ++r) {
    if (n + bucket_runs[r] < want) {
      n += bucket_runs[r];
      continue;
    }
    for (uint b = r * per; b < min(r * per + per, SVA_BELIEF_BUCKETS); ++b) {
      n += histogram_word(table, b);
      if (n >= want) return b;
    }
  }
  return SVA_BELIEF_BUCKETS;
}

// BUCKET and TABLE_BUCKET, by the one workgroup of their dispatch: the bucket into the state word that SELECT and
// TABLE_SELECT read.
void choose_bucket() {
  SvaWords st = state();
  if (pc.pass == SVA_REDUCE_BUCKET) {
    uint bucket = first_bucket_holding(false);
    if (gl_LocalInvocationID.x == 0u) st.w[SVA_STATE_SELECT_BUCKET] = uint64_t(bucket);
    return;
  }
  bool band_short = st.w[SVA_STATE_SELECT_BUCKET] >= uint64_t(SVA_BELIEF_BUCKETS);  // the same word for all
  uint bucket = band_short ? first_bucket_holding(true) : SVA_BELIEF_BUCKETS;
  if (gl_LocalInvocationID.x == 0u) st.w[SVA_STATE_TABLE_BUCKET] = uint64_t(bucket);
}

void rebuild_slot(uint slot) {
  if (slot >= pc.capacity) return;
  if (sva_table_keys(pc.table_lo, pc.table_hi).w[slot] == SVA_HASH_EMPTY_KEY) return;
  uint64_t offset = sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[slot];
  if (sva_on_band(state().w[SVA_STATE_MAX], offset, band_width(), band_floor()))
    sva_band_join(state(), marks(), band(), pc.band_capacity, slot);
}

void main() {
  if (pc.pass == SVA_REDUCE_BUCKET || pc.pass == SVA_REDUCE_TABLE_BUCKET) {
    if (gl_WorkGroupID.x == 0u && gl_WorkGroupID.y == 0u) choose_bucket();  // the whole workgroup (a barrier)
    return;
  }
  if (pc.pass == SVA_REDUCE_FLIP) {
    if (sva_flat_index() != 0u) return;
    SvaWords st = state();
    st.w[SVA_STATE_BAND_SIDE] = 1ul - st.w[SVA_STATE_BAND_SIDE];
    st.w[SVA_STATE_BAND_COUNT] = st.w[SVA_STATE_NEXT_COUNT];
    st.w[SVA_STATE_NEXT_COUNT] = 0ul;
    return;
  }
  for (uint k = 0u; k < SVA_SLOTS_PER_INVOCATION; ++k) {
    uint i = sva_table_slot(k);
    if (pc.pass == SVA_REDUCE_MASS) mass_entry(i);
    else if (pc.pass == SVA_REDUCE_SELECT) select_slot(band_entry(i));
    else if (pc.pass == SVA_REDUCE_TABLE_HISTOGRAM) histogram_slot(i);
    else if (pc.pass == SVA_REDUCE_TABLE_SELECT) select_slot(i);
    else rebuild_slot(i);
  }
}
