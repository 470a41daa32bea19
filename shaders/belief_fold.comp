#version 460
// Folds every voted pair into its session's belief (Eq 3-5 in the log domain):
// offset(x) += log2(1 + S_p(x) / eps), with S_p the pair's votes over its
// total, computed from the integers by sva_fold_units exactly as the CPU
// reference does. Per vote-table slot, in passes:
//  RESERVE: add the slot's mass to its pair's total and insert the bin into
//           the session's table (a full table raises the session's overflow
//           flag: the host grows that table and folds the session again);
//  PAIR_LOG: per pair, the log2(total eps) that all its bins subtract;
//  ADD:     add the slot's term to the reserved bin (integer atomics, so
//           the order of the additions does not change the sums), raise the
//           maximum and the object's best offset, and keep the bin's table
//           slot in the vote slot for BEST;
//  RESET, BEST: keep the session's estimate state current from the
//           bins this fold raised (offsets only grow, so nothing else can
//           change it): the maximum, each object's best offset and smallest
//           key at it, the band list; BEST clears the vote slot, so that the
//           next update finds the vote table empty without a fill of the
//           whole table.
// The passes run in the votes' submission: when the votes overflowed their
// table (vote_overflow), every pass does nothing and the host runs all again.
// Sessions whose `fold` is 0 are skipped (a rerun after a growth folds only
// the sessions that overflowed).
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

layout(std430, set = 0, binding = 0) buffer VoteKeys { uint64_t vote_key[]; };
layout(std430, set = 0, binding = 1) buffer VoteSums { int64_t vote_sum[]; };
layout(std430, set = 0, binding = 2) readonly buffer Pairs { SvaGpuPair pairs[]; };
layout(std430, set = 0, binding = 3) buffer PairTotals { uint64_t pair_total[]; };  // totals, then log2(total eps)
layout(std430, set = 0, binding = 4) readonly buffer Sessions { SvaGpuSession sessions[]; };
layout(std430, set = 0, binding = 5) buffer Status { SvaGpuSessionStatus status[]; };
layout(std430, set = 0, binding = 6) readonly buffer VoteStatus { uint vote_overflow; };

layout(push_constant) uniform Push { SvaFoldParams pc; };

// Per-session counters of this invocation's slots, added to the session's
// status once per run of slots of one session rather than once per slot: a
// batch's sessions are few, so this removes most contended atomics.
uint run_session = 0xffffffffu;
uint run_entries = 0u, run_inserted = 0u;

void flush_run() {
  if (run_session == 0xffffffffu) return;
  if (run_entries != 0u) atomicAdd(status[run_session].vote_entries, run_entries);
  if (run_inserted != 0u) atomicAdd(status[run_session].inserted, run_inserted);
  run_entries = 0u;
  run_inserted = 0u;
}

// Only this invocation reads slot i in the BEST pass; the next update's votes
// find it empty.
void clear_slot(uint i) {
  vote_key[i] = SVA_HASH_EMPTY_KEY;
  vote_sum[i] = 0l;
}

uint64_t band_width() { return uint64_t(pc.band_width_lo) | (uint64_t(pc.band_width_hi) << 32); }

SvaWords session_state(uint s) { return SvaWords(sva_address(sessions[s].state_lo, sessions[s].state_hi)); }

// The maximum and the object's best offset after an add that left `offset`
// in a bin: atomicAdd serialises the adds to one bin, so the largest `offset`
// any of them sees is the bin's final one. A plain read first: the words only
// grow, so a stale value only lets more through.
void raise_maximum(uint s, uint object, uint64_t offset) {
  SvaWords state = session_state(s);
  uint best = sva_state_object(SVA_STATE_BEST_OFFSET, pc.objects, object);
  if (offset > state.w[SVA_STATE_MAX]) atomicMax(state.w[SVA_STATE_MAX], offset);
  if (offset > state.w[best] && atomicMax(state.w[best], offset) < offset)
    state.w[sva_state_object(SVA_STATE_RAISED, pc.objects, object)] = 1ul;
}

// BEST, for a slot whose ADD pass ran: the bin's table slot is in the vote slot.
void track_slot(uint i, uint64_t bin, uint s) {
  uint capacity = sessions[s].capacity;
  uint slot = uint(vote_sum[i]);
  uint64_t offset = sva_table_offsets(sessions[s].table_lo, sessions[s].table_hi, capacity).w[slot];
  uint object = uint(bin >> pc.object_shift);
  SvaWords state = session_state(s);
  uint best = sva_state_object(SVA_STATE_BEST_OFFSET, pc.objects, object);
  if (offset == state.w[best]) atomicMin(state.w[sva_state_object(SVA_STATE_BEST_KEY, pc.objects, object)], bin);
  uint64_t band_floor = uint64_t(sessions[s].floor_lo) | (uint64_t(sessions[s].floor_hi) << 32);
  if (sva_on_band(state.w[SVA_STATE_MAX], offset, band_width(), band_floor))
    sva_band_join(state, sva_table_marks(sessions[s].table_lo, sessions[s].table_hi, capacity),
                  SvaWords32(sva_address(sessions[s].band_lo, sessions[s].band_hi)), sessions[s].band_capacity, slot);
  clear_slot(i);
}

void fold_slot(uint i) {
  if (i >= pc.slots) return;
  uint64_t key = vote_key[i];
  if (key == SVA_HASH_EMPTY_KEY) return;
  int64_t mass = vote_sum[i];
  if (mass <= 0l && pc.pass <= SVA_FOLD_ADD) {  // the scatter adds positive masses only; kept for safety
    if (pc.pass == SVA_FOLD_ADD) clear_slot(i);
    return;
  }
  uint q = uint(key >> pc.pair_shift);
  uint64_t bin = key & ((1ul << pc.pair_shift) - 1ul);
  uint s = pairs[q].session;
  if (pc.pass == SVA_FOLD_RESERVE) atomicAdd(pair_total[q], uint64_t(mass));
  if (sessions[s].fold == 0u) return;
  SvaWords keys = sva_table_keys(sessions[s].table_lo, sessions[s].table_hi);
  uint capacity = sessions[s].capacity;
  if (pc.pass == SVA_FOLD_RESERVE) {
    if (s != run_session) {
      flush_run();
      run_session = s;
    }
    ++run_entries;
    bool inserted;
    uint slot = sva_table_reserve(keys, capacity, bin, inserted);
    if (slot == capacity) atomicOr(status[s].overflow, 1u);
    else if (inserted) {
      ++run_inserted;
      atomicAdd(session_state(s).w[sva_state_object(SVA_STATE_TOUCHED, pc.objects, uint(bin >> pc.object_shift))], 1ul);
    }
    return;
  }
  if (status[s].overflow != 0u) return;  // the session folds again after its table grows
  if (pc.pass != SVA_FOLD_ADD) {
    track_slot(i, bin, s);
    return;
  }
  uint slot = sva_table_find(keys, capacity, bin);
  if (slot == capacity) {
    atomicOr(status[s].missing, 1u);
    return;
  }
  uint64_t eps_units = uint64_t(pc.eps_lo) | (uint64_t(pc.eps_hi) << 32);
  SvaWords offsets = sva_table_offsets(sessions[s].table_lo, sessions[s].table_hi, capacity);
  uint64_t floor_log = pair_total[pc.pairs + q];
  // fold_count 2: both orders of Eq 5 cast the same votes, so the term counts twice.
  uint64_t term =
      sva_fold_units_given(uint64_t(mass), pair_total[q], eps_units, floor_log) * uint64_t(pairs[q].fold_count);
  raise_maximum(s, uint(bin >> pc.object_shift), atomicAdd(offsets.w[slot], term) + term);
  vote_sum[i] = int64_t(slot);  // for BEST: the mass is spent
}

// Per (session, object): an object whose best offset rose forgets its best
// key; BEST finds the smallest key at the new offset among the raised bins.
void reset_object(uint i) {
  uint s = i / max(pc.objects, 1u), object = i % max(pc.objects, 1u);
  if (s >= pc.sessions || sessions[s].fold == 0u || status[s].overflow != 0u) return;
  SvaWords state = session_state(s);
  uint raised = sva_state_object(SVA_STATE_RAISED, pc.objects, object);
  if (state.w[raised] == 0ul) return;
  state.w[raised] = 0ul;
  state.w[sva_state_object(SVA_STATE_BEST_KEY, pc.objects, object)] = SVA_HASH_EMPTY_KEY;
}

void main() {
  if (vote_overflow != 0u) return;
  if (pc.pass == SVA_FOLD_PAIR_LOG) {
    uint q = sva_flat_index();
    if (q < pc.pairs && pair_total[q] != 0ul) {
      uint64_t eps_units = uint64_t(pc.eps_lo) | (uint64_t(pc.eps_hi) << 32);
      pair_total[pc.pairs + q] = sva_floor_log(pair_total[q], eps_units);
    }
    return;
  }
  if (pc.pass == SVA_FOLD_RESET) {
    reset_object(sva_flat_index());
    return;
  }
  for (uint k = 0u; k < SVA_SLOTS_PER_INVOCATION; ++k) fold_slot(sva_table_slot(k));
  flush_run();
}
