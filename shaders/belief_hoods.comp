#version 460
// What an estimate reads by key, chosen on the device in an update's submission (after its fold, the summary's
// passes and the best bins' selection, belief_reduce.comp), so that a robot's touch is one round trip: the
// hypotheses' centres and their neighbourhoods' offsets, listed as host/src/estimate/hypotheses.cpp's
// hypothesis_keys lists them. The host still computes that list from what came back and uses these answers only
// where the two lists are equal; elsewhere it looks the keys up as before.
//  RANK:     per candidate of the selection: its place among them (offset descending, then key ascending, as the
//            host's best_bins), the first `best` written in order;
//  CENTRES:  one workgroup: up to `modes` distinct modes, greedily from the best bins (a bin within `suppress` grid
//            steps of a mode of its object is not one), then every touched object's best bin; for each, where its
//            neighbourhood starts in the list, and the list's length. With pose priors, the modes' candidates in
//            the order of evidence plus prior, and each object's best bin under its prior (estimate/pose_prior.hpp),
//            in floats: where a near tie orders otherwise than the host's doubles, the lists differ and the host
//            looks its own keys up;
//  KEYS:     per (centre, step): the neighbour's packed key and its offset (0 untouched) at its place in the list.
// The neighbourhood of a centre: the centre, then every step of (tx, ty, tz, rx, ry, rz) within `radius`, rz
// fastest, that stays in the grid (a planar space steps tx, ty and its angle only, the angle round the circle and
// cut to distinct bins). In-grid steps form a box, so a step's place is a mixed-radix count.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_hash.h"
#include "sva_belief_math.h"
#include "sva_gpu_layout.h"
#include "sva_belief_table.glsl"
#include "sva_pose_bins.h"
#include "sva_neighbourhood.h"

layout(local_size_x = SVA_WORKGROUP_SIZE) in;

layout(std430, set = 0, binding = 0) readonly buffer Candidates { uint64_t candidate[]; };  // (key, offset) pairs
layout(std430, set = 0, binding = 1) buffer Hoods { uint64_t hood[]; };
layout(std430, set = 0, binding = 2) readonly buffer Priors { float prior[]; };  // SVA_PRIOR_FLOATS per object

layout(push_constant) uniform Push { SvaHoodParams pc; };

SvaWords state() { return SvaWords(sva_address(pc.state_lo, pc.state_hi)); }
uint sorted_word(uint r) { return SVA_HOODS_HEADER + 2u * r; }
uint centre_word(uint c) { return SVA_HOODS_HEADER + 2u * pc.best + 2u * c; }
uint key_word(uint64_t i) { return centre_word(pc.modes + pc.objects) + 2u * uint(i); }

// The candidates the selection found (more than its room: none, the host selects again).
uint candidates_found() {
  uint64_t n = state().w[SVA_STATE_CANDIDATES];
  return n > uint64_t(pc.room) ? 0u : uint(n);
}

bool better(uint64_t ka, uint64_t oa, uint64_t kb, uint64_t ob) { return oa != ob ? oa > ob : ka < kb; }

void rank_candidate(uint i) {
  uint n = candidates_found();
  if (i >= n) return;
  uint64_t key = candidate[2u * i], offset = candidate[2u * i + 1u];
  uint r = 0u;
  for (uint j = 0u; j < n; ++j)
    if (better(candidate[2u * j], candidate[2u * j + 1u], key, offset)) ++r;
  if (r >= pc.best) return;
  hood[sorted_word(r)] = key;
  hood[sorted_word(r) + 1u] = offset;
}

// A bin's grid indices from its linear key (host/src/backends/vulkan/linear_bins.hpp's key()): t[0..2], r[0..2].
void indices(uint64_t linear, out int t[3], out int r[3]) {
  uint64_t tb = uint64_t(pc.translation_bins), rb = uint64_t(pc.rotation_bins);
  uint64_t tz = pc.planar != 0u ? 1ul : tb, rxy = pc.planar != 0u ? 1ul : rb;
  uint64_t i = linear & ((uint64_t(1) << pc.object_shift) - 1ul);
  r[2] = int(i % rb);
  i /= rb;
  r[1] = int(i % rxy);
  i /= rxy;
  r[0] = int(i % rxy);
  i /= rxy;
  t[2] = int(i % tz);
  i /= tz;
  t[1] = int(i % tb);
  t[0] = int(i / tb);
}

// The steps of axis a (tx, ty, tz, rx, ry, rz) a neighbourhood takes, the grid ignored: [lo, hi].
void axis_steps(uint a, out int lo, out int hi) {
  lo = sva_hood_step_lo(a, int(pc.radius), pc.planar != 0u, int(pc.rotation_bins));
  hi = sva_hood_step_hi(a, int(pc.radius), pc.planar != 0u, int(pc.rotation_bins));
}

// The steps of axis a that stay in the grid from index c: [lo, hi] (the planar angle wraps: all of them).
void inside_steps(uint a, int c, out int lo, out int hi) {
  axis_steps(a, lo, hi);
  if (pc.planar != 0u && a == 5u) return;
  int bins = int(a < 3u ? pc.translation_bins : pc.rotation_bins);
  lo = max(lo, -c);
  hi = min(hi, bins - 1 - c);
}

int axis_index(int t[3], int r[3], uint a) { return a < 3u ? t[a] : r[a - 3u]; }

// Keys in the neighbourhood of the bin with indices (t, r), the centre included.
uint64_t hood_size(int t[3], int r[3]) {
  uint64_t n = 1ul;
  for (uint a = 0u; a < 6u; ++a) {
    int lo, hi;
    inside_steps(a, axis_index(t, r, a), lo, hi);
    n *= uint64_t(hi - lo + 1);
  }
  return n;
}

// The pose prior's log2 weight at the centre of the bin with linear key `key` (PoseWeighting::log2_weight, in floats):
// 0 for an object without one.
float prior_log2_weight(uint64_t key) {
  uint object = uint(key >> pc.object_shift), at = object * uint(SVA_PRIOR_FLOATS);
  if (prior[at] == 0.0f) return 0.0f;
  int t[3], r[3];
  indices(key, t, r);
  const float rw = SVA_TWO_PI / float(pc.rotation_bins);
  vec3 position, turn;
  for (int k = 0; k < 3; ++k) {
    position[k] = pc.translation_min_mm + (float(t[k]) + 0.5f) * pc.translation_bin_mm;
    turn[k] = -SVA_PI + (float(r[k]) + 0.5f) * rw;
  }
  if (pc.planar != 0u) position.z = 0.0f, turn.x = 0.0f, turn.y = 0.0f;
  vec3 d = position - vec3(prior[at + 1u], prior[at + 2u], prior[at + 3u]);
  float nats_bits = prior[at + 4u] * dot(d, d);  // already per ln 2: bits
  if (prior[at + 5u] > 0.0f) {
    // The bin's rotation exp(turn), and its angle from the prior's mean: trace(M^T R) = sum of elementwise products.
    float a = length(turn);
    mat3 k = mat3(0.0f, turn.z, -turn.y, -turn.z, 0.0f, turn.x, turn.y, -turn.x, 0.0f);
    mat3 rot = a < 1e-6f ? mat3(1.0f) + k : mat3(1.0f) + (sin(a) / a) * k + ((1.0f - cos(a)) / (a * a)) * (k * k);
    float trace = 0.0f;
    for (uint c = 0u; c < 3u; ++c)
      for (uint j = 0u; j < 3u; ++j) trace += prior[at + 6u + 3u * c + j] * rot[c][j];
    float angle = acos(clamp(0.5f * (trace - 1.0f), -1.0f, 1.0f));
    nats_bits += prior[at + 5u] * angle * angle;
  }
  return -nats_bits;
}

// Evidence plus prior in bits, relative to the offset `top` (the best candidate's): floats order them.
float prior_score(uint64_t key, uint64_t offset, uint64_t top) {
  return -float(top - offset) / float(1ul << SVA_BELIEF_FRAC_BITS) + prior_log2_weight(key);
}

// Two bins of one object within `suppress` steps on every axis (the planar angle round the circle).
bool within(uint64_t a, uint64_t b) {
  if ((a >> pc.object_shift) != (b >> pc.object_shift)) return false;
  int ta[3], ra[3], tb[3], rb[3];
  indices(a, ta, ra);
  indices(b, tb, rb);
  for (uint k = 0u; k < 6u; ++k) {
    int d = k < 3u ? ta[k] - tb[k] : ra[k - 3u] - rb[k - 3u];
    if (!sva_hood_axis_within(k, d, int(pc.suppress), pc.planar != 0u, int(pc.rotation_bins))) return false;
  }
  return true;
}

// The best bin overall: the best of the objects' best bins (the host's best_bins(1)); none when nothing is touched.
bool best_bin(out uint64_t key) {
  SvaWords st = state();
  bool found = false;
  uint64_t offset = 0ul;
  key = 0ul;
  for (uint o = 0u; o < pc.objects; ++o) {
    if (st.w[sva_state_object(SVA_STATE_TOUCHED, pc.objects, o)] == 0ul) continue;
    uint64_t k = st.w[sva_state_object(SVA_STATE_BEST_KEY, pc.objects, o)];
    uint64_t off = st.w[sva_state_object(SVA_STATE_BEST_OFFSET, pc.objects, o)];
    if (!found || better(k, off, key, offset)) key = k, offset = off;
    found = true;
  }
  return found;
}

// Adds the centre `key` after `c` others, its neighbourhood starting at *next.
void add_centre(uint c, uint64_t key, inout uint64_t next) {
  int t[3], r[3];
  indices(key, t, r);
  hood[centre_word(c)] = key;
  hood[centre_word(c) + 1u] = next;
  next += hood_size(t, r);
}

// The first m candidates' places in the order of evidence plus prior, best first (a stable insertion sort: equal
// scores keep the offsets' order, as the host's stable sort does).
void order_by_prior(uint m, out uint order[SVA_PRIOR_MOST_CANDIDATES]) {
  float score[SVA_PRIOR_MOST_CANDIDATES];
  uint64_t top = hood[sorted_word(0u) + 1u];
  for (uint i = 0u; i < m; ++i) {
    float s = prior_score(hood[sorted_word(i)], hood[sorted_word(i) + 1u], top);
    uint j = i;
    for (; j > 0u && score[j - 1u] < s; --j) score[j] = score[j - 1u], order[j] = order[j - 1u];
    score[j] = s, order[j] = i;
  }
}

// Object o's best bin: its summary's, or under a prior the best by evidence plus prior among it and its bins among
// the first `n` candidates' `prior_best` (ties to the smaller key), as best_bin_under_prior chooses.
uint64_t object_best(uint o, uint n) {
  SvaWords st = state();
  uint64_t best = st.w[sva_state_object(SVA_STATE_BEST_KEY, pc.objects, o)];
  if (pc.priors == 0u || prior[o * uint(SVA_PRIOR_FLOATS)] == 0.0f) return best;
  uint64_t top = hood[sorted_word(0u) + 1u];
  float score = prior_score(best, st.w[sva_state_object(SVA_STATE_BEST_OFFSET, pc.objects, o)], top);
  for (uint i = 0u; i < min(n, pc.prior_best); ++i) {
    uint64_t key = hood[sorted_word(i)];
    if (uint(key >> pc.object_shift) != o) continue;
    float s = prior_score(key, hood[sorted_word(i) + 1u], top);
    if (s > score || (s == score && key < best)) best = key, score = s;
  }
  return best;
}

// The header and the modes' centres, by invocation 0: false where the device chooses nothing (nothing touched, a
// selection that missed bins, a prior over more candidates than one invocation sorts).
bool choose_modes(inout uint c, inout uint64_t next) {
  SvaWords st = state();
  uint64_t touched = 0ul;
  for (uint o = 0u; o < pc.objects; ++o) touched += st.w[sva_state_object(SVA_STATE_TOUCHED, pc.objects, o)];
  hood[0] = SVA_HOODS_NONE;
  hood[1] = 0ul;
  if (touched == 0ul) {  // nothing to read
    hood[0] = 0ul;
    return false;
  }
  if (pc.best <= 1u) {  // one mode at most: the best bin itself
    uint64_t key;
    if (pc.modes > 0u && best_bin(key)) add_centre(c++, key, next);
    return true;
  }
  uint n = min(candidates_found(), pc.best);
  if (uint64_t(n) < min(uint64_t(pc.best), touched)) return false;  // the selection missed bins: the host reads them
  uint m = min(n, pc.mode_best);
  uint order[SVA_PRIOR_MOST_CANDIDATES];
  if (pc.priors != 0u) {
    if (m > SVA_PRIOR_MOST_CANDIDATES) return false;  // more than one invocation sorts: the host chooses (key_choice)
    order_by_prior(m, order);
  }
  for (uint i = 0u; i < m && c < pc.modes; ++i) {
    uint64_t key = hood[sorted_word(pc.priors != 0u ? order[i] : i)];
    bool suppressed = false;
    for (uint j = 0u; j < c && !suppressed; ++j) suppressed = within(key, hood[centre_word(j)]);
    if (!suppressed) add_centre(c++, key, next);
  }
  return true;
}

// What invocation 0 found, for the workgroup: go on, the centres so far, where the next neighbourhood starts; and a
// chunk of objects' centres and neighbourhood sizes (0: untouched).
shared uint centres_go, centres_count;
shared uint64_t centres_next;
shared uint64_t chunk_key[SVA_WORKGROUP_SIZE], chunk_size[SVA_WORKGROUP_SIZE];

// CENTRES, by the dispatch's one workgroup: the modes by invocation 0, then every touched object's best bin a chunk
// of objects at a time, each invocation one object's centre and neighbourhood size (the grid's 64-bit arithmetic side
// by side, where one invocation did it for every object in turn: a map of 78 objects had 78 in a row), listed in
// order by invocation 0.
void choose_centres() {
  uint t = gl_LocalInvocationID.x;
  if (t == 0u) {
    uint c = 0u;
    uint64_t next = 0ul;
    centres_go = choose_modes(c, next) ? 1u : 0u;
    centres_count = c;
    centres_next = next;
  }
  barrier();
  if (centres_go == 0u) return;  // the same shared word for the whole workgroup
  SvaWords st = state();
  uint found = min(candidates_found(), pc.best);
  for (uint first = 0u; first < pc.objects; first += SVA_WORKGROUP_SIZE) {
    uint o = first + t;
    chunk_size[t] = 0ul;
    if (o < pc.objects && st.w[sva_state_object(SVA_STATE_TOUCHED, pc.objects, o)] > 0ul) {
      int ti[3], ri[3];
      chunk_key[t] = object_best(o, found);
      indices(chunk_key[t], ti, ri);
      chunk_size[t] = hood_size(ti, ri);  // at least 1: the centre
    }
    barrier();
    if (t == 0u) {
      for (uint j = 0u; j < SVA_WORKGROUP_SIZE; ++j) {
        if (chunk_size[j] == 0ul) continue;
        hood[centre_word(centres_count)] = chunk_key[j];
        hood[centre_word(centres_count) + 1u] = centres_next;
        centres_next += chunk_size[j];
        ++centres_count;
      }
    }
    barrier();
  }
  if (t != 0u || centres_next > uint64_t(pc.keys)) return;  // more keys than the output holds: the host reads them
  hood[1] = uint64_t(centres_count);
  hood[0] = centres_next;
}

// Step s of a centre's neighbourhood (mixed radix over the axes' steps, rz fastest) and its place after the centre.
void neighbour(uint i) {
  uint c = i / pc.steps, s = i % pc.steps;
  if (hood[0] == SVA_HOODS_NONE || uint64_t(c) >= hood[1]) return;
  uint64_t key = hood[centre_word(c)];
  int t[3], r[3];
  indices(key, t, r);
  int d[6];
  for (int a = 5; a >= 0; --a) {
    int lo, hi;
    axis_steps(uint(a), lo, hi);
    uint span = uint(hi - lo + 1);
    d[a] = lo + int(s % span);
    s /= span;
  }
  // Its place among the in-grid steps (the centre's own step included), then after the centre.
  uint64_t place = 0ul, zero = 0ul;
  bool centre = true;
  for (uint a = 0u; a < 6u; ++a) {
    int c0 = axis_index(t, r, a), lo, hi;
    inside_steps(a, c0, lo, hi);
    if (d[a] < lo || d[a] > hi) return;  // outside the grid
    uint64_t span = uint64_t(hi - lo + 1);
    place = place * span + uint64_t(d[a] - lo);
    zero = zero * span + uint64_t(-lo);
    centre = centre && d[a] == 0;
  }
  uint64_t at = hood[centre_word(c) + 1u] + (centre ? 0ul : (place < zero ? place + 1ul : place));
  int n[6];
  for (uint a = 0u; a < 6u; ++a) n[a] = axis_index(t, r, a) + d[a];
  if (pc.planar != 0u) n[5] = (n[5] + int(pc.rotation_bins)) % int(pc.rotation_bins);
  uint object = uint(key >> pc.object_shift);
  uint64_t packed = sva_pack_bin_key(object, n[0], n[1], n[2], n[3], n[4], n[5]);
  uint dim_tz = pc.planar != 0u ? 1u : pc.translation_bins, dim_rxy = pc.planar != 0u ? 1u : pc.rotation_bins;
  uint64_t linear =
      sva_linear_bin(packed, pc.translation_bins, pc.rotation_bins, dim_tz, dim_rxy, pc.object_shift);
  uint slot = sva_table_find(sva_table_keys(pc.table_lo, pc.table_hi), pc.capacity, linear);
  hood[key_word(at)] = packed;
  hood[key_word(at) + 1u] = slot == pc.capacity ? 0ul : sva_table_offsets(pc.table_lo, pc.table_hi, pc.capacity).w[slot];
}

void main() {
  uint i = sva_flat_index();
  if (pc.pass == SVA_HOODS_RANK) {
    rank_candidate(i);
  } else if (pc.pass == SVA_HOODS_CENTRES) {
    if (gl_WorkGroupID.x == 0u && gl_WorkGroupID.y == 0u) choose_centres();  // the whole workgroup (barriers)
  } else {
    neighbour(i);
  }
}
