// The agreement contract of docs/vulkan-backend.md, stage by stage: the shared
// vote math of one match (sva_vote_math.h) run on the device and compiled as
// C++ must give the same bits at every stage - the alignment, the beta plan,
// the weight sum and scale, then each sample's weight, pose bin and mass - on
// random matches and on hard ones (coincident points, antiparallel normals,
// alignments whose Gaussian covers the circle). When the backends disagree,
// this names the first stage that does, which the whole-batch tests cannot.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <string>

#include "backends/vulkan/gpu_layout.hpp"
#include "recognition/fixture.hpp"
#include "spv/vote_math_stages.h"
#include "vk_test_support.hpp"
#include "votes/vote_math.hpp"

namespace {

namespace vm = sva::vote_math;

constexpr std::uint32_t kCaseFloats = 29;
constexpr std::uint32_t kHead = 26;
constexpr std::uint32_t kWords = kHead + 5 * SVA_MAX_BETA_SAMPLES;

struct GridPush {
  std::uint32_t n;
  std::int32_t kind, translation_bins;
  float translation_min, translation_width;
  std::int32_t rotation_bins;
  float rotation_width;
};

// The words the kernel writes for one case, computed by the C++ compile of the header.
std::array<std::uint32_t, kWords> cpu_words(const float* in, const GridPush& g) {
  std::array<std::uint32_t, kWords> w{};
  const auto patch = [&](int k) {
    vm::SvaPatch p;
    const float* f = in + 7 * k;
    p.p = {f[0], f[1], f[2]};
    p.n = {f[3], f[4], f[5]};
    p.conf = f[6];
    return p;
  };
  const vm::SvaAlignment al = vm::sva_align(patch(0), patch(1), patch(2), patch(3));
  const vm::SvaPoseGrid grid = vm::sva_pose_grid(g.kind, g.translation_bins, g.translation_min, g.translation_width,
                                                 g.rotation_bins, g.rotation_width);
  const vm::SvaBetaPlan plan = vm::sva_beta_plan(al, grid);
  const float sum = vm::sva_beta_weight_sum(plan);
  std::uint64_t units = vm::sva_likelihood_units(in[28]);
  units += vm::sva_likelihood_units(in[6] * in[20] * in[28]);
  const float likelihood = vm::sva_likelihood_of_units(units);
  const float scale = vm::sva_vote_scale(likelihood, sum);
  std::size_t o = 0;
  const auto put = [&](float x) { w[o++] = std::bit_cast<std::uint32_t>(x); };
  const auto put_u = [&](std::uint32_t x) { w[o++] = x; };
  for (float x : {al.q1.x, al.q1.y, al.q1.z, al.q1.w, al.axis.x, al.axis.y, al.axis.z, al.c_obs.x, al.c_obs.y,
                  al.c_obs.z, al.c_map_r.x, al.c_map_r.y, al.c_map_r.z, al.beta_hat, al.align_conf, al.sigma})
    put(x);
  put_u(static_cast<std::uint32_t>(al.valid));
  put_u(static_cast<std::uint32_t>(plan.n));
  put_u(static_cast<std::uint32_t>(plan.circle));
  put(plan.unit);
  put(plan.inv_sigma);
  put(sum);
  put(scale);
  put_u(static_cast<std::uint32_t>(units & 0xffffffffu));
  put_u(static_cast<std::uint32_t>(units >> 32));
  put(likelihood);
  for (int i = 0; i < plan.n && i < SVA_MAX_BETA_SAMPLES; ++i) {
    const float weight = vm::sva_beta_weight(plan, i) * scale;
    const vm::SvaVote v = vm::sva_vote(al, plan, grid, 1u, weight, i);
    put(weight);
    put_u(static_cast<std::uint32_t>(v.key & 0xffffffffu));
    put_u(static_cast<std::uint32_t>(v.key >> 32));
    put_u(static_cast<std::uint32_t>(v.mass));
    put_u(static_cast<std::uint32_t>(v.inside));
  }
  return w;
}

// The stage a word of the layout belongs to.
const char* stage_of(std::uint32_t word) {
  if (word < 13) return "alignment: R1, axis, midpoints";
  if (word == 13) return "alignment: beta-hat";
  if (word < 17) return "alignment: alignConf, sigma, valid";
  if (word < 21) return "beta plan";
  if (word == 21) return "weight sum";
  if (word == 22) return "vote scale";
  if (word < 25) return "likelihood units (two key terms)";
  if (word == 25) return "likelihood from its units";
  switch ((word - kHead) % 5) {
    case 0:
      return "sample weight";
    case 1:
    case 2:
      return "sample pose bin";
    case 3:
      return "sample mass";
    default:
      return "sample inside";
  }
}

void random_patch(sva::util::Rng& rng, float* f, float spread) {
  for (int k = 0; k < 3; ++k) f[k] = static_cast<float>((rng.uniform() - 0.5) * spread);
  double n[3], len = 0;
  do {
    len = 0;
    for (double& x : n) {
      x = rng.uniform() * 2 - 1;
      len += x * x;
    }
  } while (len < 1e-3 || len > 1);
  for (int k = 0; k < 3; ++k) f[3 + k] = static_cast<float>(n[k] / std::sqrt(len));
  f[6] = static_cast<float>(0.05 + 0.95 * rng.uniform());
}

// Random matches: an observed pair and a map pair of similar length, so that
// most align; every 16th case is a hard one.
std::vector<float> make_cases(std::uint32_t count) {
  sva::util::Rng rng(77, 3);
  std::vector<float> in(static_cast<std::size_t>(count) * kCaseFloats);
  for (std::uint32_t c = 0; c < count; ++c) {
    float* f = &in[static_cast<std::size_t>(c) * kCaseFloats];
    for (int k = 0; k < 4; ++k) random_patch(rng, f + 7 * k, 160.0f);
    switch (c % 16) {
      case 1:
        std::memcpy(f + 7, f, 3 * sizeof(float));
        break;  // observed points coincide: no alignment
      case 2:   // antiparallel normals in both pairs
        for (int k = 0; k < 3; ++k) f[7 + 3 + k] = -f[3 + k], f[21 + 3 + k] = -f[14 + 3 + k];
        break;
      case 3:
        f[6] = f[13] = f[20] = f[27] = 0.01f;
        break;  // low confidence: the Gaussian covers the circle
      case 4:
        std::memcpy(f + 14, f, 14 * sizeof(float));
        break;  // the map pair is the observed pair
      default:
        break;
    }
    f[28] = static_cast<float>(std::pow(10.0, -6.0 * rng.uniform()));
  }
  return in;
}

// Compares every case of `in` (kCaseFloats floats each) on the device and in C++; returns the cases compared.
void compare_cases(const std::vector<float>& in, const GridPush& grid_in, const char* name) {
  auto ctx = sva::test::vulkan_context_or_skip();
  const auto n = static_cast<std::uint32_t>(in.size() / kCaseFloats);
  GridPush g = grid_in;
  g.n = n;
  auto bin = ctx->create_buffer(in.size() * sizeof(float));
  auto bout = ctx->create_buffer(static_cast<std::size_t>(n) * kWords * sizeof(std::uint32_t));
  std::memcpy(bin.data(), in.data(), in.size() * sizeof(float));
  std::memset(bout.data(), 0, bout.size());
  const sva::vk::Pipeline pipe =
      ctx->create_pipeline("vote_math_stages", sva_spv_vote_math_stages, 2, sizeof(GridPush));
  std::vector<std::uint8_t> push(sizeof(GridPush));
  std::memcpy(push.data(), &g, sizeof(GridPush));
  ctx->run({sva::vk::Dispatch{&pipe, {&bin, &bout}, push, (n + 63) / 64}});
  const auto* gpu = bout.as<std::uint32_t>();
  std::map<std::string, std::size_t> first_differing;  // cases whose first differing word is in this stage
  std::size_t votes = 0, aligned = 0;
  std::string example;
  for (std::uint32_t c = 0; c < n; ++c) {
    const auto want = cpu_words(&in[static_cast<std::size_t>(c) * kCaseFloats], g);
    aligned += want[16] != 0;
    votes += want[17];
    for (std::uint32_t k = 0; k < kWords; ++k) {
      if (want[k] == gpu[static_cast<std::size_t>(c) * kWords + k]) continue;
      ++first_differing[stage_of(k)];
      if (example.empty()) {
        std::ostringstream os;
        os << "case " << c << " word " << k << " (" << stage_of(k) << "): cpu 0x" << std::hex << want[k] << " gpu 0x"
           << gpu[static_cast<std::size_t>(c) * kWords + k];
        example = os.str();
      }
      break;
    }
  }
  std::ostringstream summary;
  summary << name << " on " << ctx->info().name << ": " << n << " matches, " << aligned << " aligned, " << votes
          << " samples; cases differing, by first stage:";
  for (const auto& [stage, count] : first_differing) summary << " [" << stage << "] " << count;
  if (first_differing.empty()) summary << " none";
  WARN(summary.str());
  INFO(example);
  CHECK(first_differing.empty());
  CHECK(aligned > n / 2);
  CHECK(votes > 4 * n);
}

void compare_on_device(const GridPush& grid, const char* name) { compare_cases(make_cases(8192), grid, name); }

void put_patch(std::vector<float>& in, const float* p, const float* n, float conf) {
  in.insert(in.end(), {p[0], p[1], p[2], n[0], n[1], n[2], conf});
}

// The matches a recognizer's batch really makes: every map entry under every key of the pairs of a few sessions
// of the test world, as (observed pair, map pair with the key's orientation, key weight x entry weight).
std::vector<float> world_cases(const sva::PoseSpace& space, std::size_t max_cases) {
  using namespace sva;
  test::WorldSpec spec;
  auto w = test::make_world(spec);
  auto backend = make_cpu_vote_backend(*w.map, space, {});
  VoteBatch batch;
  for (std::uint32_t s = 0; s < 3; ++s) {
    BayesFilter f(*w.map, space, FilterOptions{}, *backend);
    const RigidPose pose = test::random_pose(200 + s, 150.0);
    for (int r = 0; r < 4; ++r)
      f.add(test::observe(w.objects[s][static_cast<std::size_t>(r * 11 % spec.points)], pose));
    f.queue_pairs(test::observe(w.objects[s][static_cast<std::size_t>(53 % spec.points)], pose), s, &batch);
  }
  const PairMap& m = *w.map;
  std::vector<float> in;
  for (const PairQuery& q : batch.pairs) {
    for (std::uint32_t k = q.key_begin; k < q.key_end; ++k) {
      const auto it = std::lower_bound(m.keys.begin(), m.keys.end(), batch.keys[k].key);
      if (it == m.keys.end() || *it != batch.keys[k].key) continue;
      const auto i = static_cast<std::size_t>(it - m.keys.begin());
      for (std::uint32_t e = m.offsets[i]; e < m.offsets[i + 1] && in.size() < max_cases * kCaseFloats; ++e) {
        std::uint32_t ra = m.entry_a[e], rb = m.entry_b[e];
        if (batch.keys[k].reversed) std::swap(ra, rb);
        put_patch(in, q.a.position, q.a.normal, q.a.norm_conf);
        put_patch(in, q.b.position, q.b.normal, q.b.norm_conf);
        for (std::uint32_t r : {ra, rb}) {
          const float p[3] = {m.readings.px[r], m.readings.py[r], m.readings.pz[r]};
          const float n[3] = {m.readings.nx[r], m.readings.ny[r], m.readings.nz[r]};
          put_patch(in, p, n, m.readings.norm_conf[r]);
        }
        in.push_back(batch.keys[k].weight * m.entry_weight[e]);
      }
    }
  }
  return in;
}

}  // namespace

TEST_CASE("the vote math of one match on the device equals the CPU's at every stage (spatial)") {
  compare_on_device({0, SVA_POSE_SPATIAL, 60, -150.0f, 5.0f, 36, 6.28318530717959f / 36}, "spatial");
}

TEST_CASE("the vote math of one match on the device equals the CPU's at every stage (a test world's matches)") {
  sva::PoseSpace space(sva::test::paper_space(), 3);
  const auto g = space.grid();
  compare_cases(
      world_cases(space, 16384),
      {0, g.kind, g.translation_bins, g.translation_min, g.translation_width, g.rotation_bins, g.rotation_width},
      "test world");
}

TEST_CASE("the vote math of one match on the device equals the CPU's at every stage (planar)") {
  compare_on_device({0, SVA_POSE_PLANAR, 60, -150.0f, 5.0f, 72, 6.28318530717959f / 72}, "planar");
}
