// The shared per-match math (sva_vote_math.h) against libm and double-precision
// geometry: its own exp / sincos / atan2, quaternion helpers, the two-point
// alignment with beta-hat, and the beta sampling.
#include <sva/base/rng.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "recognition/fixture.hpp"
#include "test_support.hpp"
#include "votes/vote_math.hpp"
#include "votes/vote_patches.hpp"

using namespace sva;
using namespace sva::test;
namespace vm = sva::vote_math;

namespace {
glm::dvec3 d3(const vm::vec3& v) { return glm::dvec3(v.x, v.y, v.z); }
glm::dmat3 mat_of(const vm::vec4& q) {
  // Rotation of each basis vector through the header's quaternion rotate.
  return glm::dmat3(d3(vm::sva_quat_rotate(q, vm::vec3(1, 0, 0))), d3(vm::sva_quat_rotate(q, vm::vec3(0, 1, 0))),
                    d3(vm::sva_quat_rotate(q, vm::vec3(0, 0, 1))));
}
}  // namespace

TEST_CASE("own exp, sincos and atan2 match libm to about 1e-6") {
  double worst_exp = 0, worst_sc = 0, worst_at = 0;
  for (int i = 0; i <= 2000; ++i) {
    const float x = -20.0f * static_cast<float>(i) / 2000.0f;
    worst_exp = std::max(
        worst_exp, std::fabs(vm::sva_exp_neg(x) - std::exp(static_cast<double>(x))) / std::exp(static_cast<double>(x)));
    const float a = -7.0f + 14.0f * static_cast<float>(i) / 2000.0f;
    const vm::vec2 sc = vm::sva_sincos(a);
    worst_sc = std::max({worst_sc, std::fabs(sc.x - std::sin(static_cast<double>(a))),
                         std::fabs(sc.y - std::cos(static_cast<double>(a)))});
    const double t = 2.0 * std::numbers::pi * i / 2000.0;
    const float y = static_cast<float>(std::sin(t) * (1 + i % 7)), xx = static_cast<float>(std::cos(t) * (1 + i % 5));
    worst_at = std::max(worst_at,
                        std::fabs(vm::sva_atan2(y, xx) - std::atan2(static_cast<double>(y), static_cast<double>(xx))));
  }
  CHECK(worst_exp < 2e-6);
  CHECK(worst_sc < 2e-6);
  CHECK(worst_at < 2e-6);
  CHECK(vm::sva_atan2(0.0f, 0.0f) == 0.0f);
  CHECK(vm::sva_exp_neg(-1000.0f) == 0.0f);
  CHECK(vm::sva_exp_neg(std::nanf("")) == 0.0f);
}

TEST_CASE("quaternion composition and Rodrigues vectors agree with the SO(3) exponential") {
  util::Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 ra = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal())) * rng.uniform(0.0, 3.1);
    const glm::dvec3 rb = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal())) * rng.uniform(0.0, 3.1);
    const vm::vec4 qa = vm::sva_quat_axis_angle(f3(glm::normalize(ra)), static_cast<float>(glm::length(ra)));
    const vm::vec4 qb = vm::sva_quat_axis_angle(f3(glm::normalize(rb)), static_cast<float>(glm::length(rb)));
    const glm::dmat3 Rab = so3::exp(ra) * so3::exp(rb);
    const glm::dmat3 Q = mat_of(vm::sva_quat_mul(qa, qb));
    for (int c = 0; c < 3; ++c) CHECK(glm::length(Q[c] - Rab[c]) < 1e-5);
    const glm::dvec3 r = d3(vm::sva_quat_to_rodrigues(vm::sva_quat_mul(qa, qb)));
    const glm::dvec3 r_ref = so3::log(Rab);
    CHECK(glm::length(r) <= std::numbers::pi + 1e-5);
    CHECK(so3::angle(glm::transpose(so3::exp(r)) * Rab) < 1e-4);
    if (glm::length(r_ref) < 3.1) CHECK(glm::length(r - r_ref) < 1e-4);
  }
}

TEST_CASE("the Rodrigues scale is 2 phi / sin(phi) of w = cos(phi) within 1.5e-7, relative, at every w") {
  // Every 64th float from 0 to 1 (and the roundings just above 1 that a composition of unit quaternions reaches).
  double worst = 0;
  float at = 0;
  const auto check = [&](float w) {
    const double wd = w;
    const double s = std::sqrt(std::fabs((1.0 - wd) * (1.0 + wd)));
    // Above 1, the function's continuation: 2 acosh(w) / sqrt(w^2 - 1).
    const double want = s == 0 ? 2.0 : wd < 1 ? 2.0 * std::atan2(s, wd) / s : 2.0 * std::acosh(wd) / s;
    const double err = std::fabs(vm::sva_rodrigues_scale(w) - want) / want;
    if (err > worst) worst = err, at = w;
  };
  for (float w = 0.0f; w <= 1.0f; w = std::nextafter(w, 2.0f)) {
    check(w);
    for (int k = 0; k < 63 && w < 1.0f; ++k) w = std::nextafter(w, 2.0f);
  }
  for (float w = 1.0f; w < 1.000001f; w = std::nextafter(w, 2.0f)) check(w);
  INFO("worst relative error " << worst << " at w = " << std::hexfloat << at);
  CHECK(worst < 1.5e-7);  // 1.08e-7 measured; the atan2 it replaced erred by as much
  // And the whole Rodrigues vector: the angle of random unit quaternions, every half angle from 0 to pi / 2.
  util::Rng rng(41);
  double worst_angle = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const double angle = std::numbers::pi * i / 20000.0;
    const vm::vec3 r = vm::sva_quat_to_rodrigues(vm::sva_quat_axis_angle(f3(axis), static_cast<float>(angle)));
    worst_angle = std::max(worst_angle, glm::length(d3(r) - axis * static_cast<double>(static_cast<float>(angle))));
  }
  CHECK(worst_angle < 1.5e-6);  // 0.99e-6 measured: a few units in the last place of pi
}

TEST_CASE("quat_between: generic, parallel and anti-parallel axes") {
  util::Rng rng(5);
  for (int i = 0; i < 100; ++i) {
    const glm::dvec3 a = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const glm::dvec3 b = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    for (const glm::dvec3& to : {b, a, -a}) {
      const vm::vec4 q = vm::sva_quat_between(f3(a), f3(to));
      INFO("case " << i);
      CHECK(std::fabs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1.0) < 1e-5);
      CHECK(glm::length(d3(vm::sva_quat_rotate(q, f3(a))) - to) < 1e-5);
    }
    // Anti-parallel: a half turn.
    const vm::vec4 q = vm::sva_quat_between(f3(a), f3(-a));
    CHECK(std::fabs(q.w) < 1e-6);
  }
  // The exact axes too (the perpendicular is built from the smallest component).
  for (const glm::dvec3& a : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, -1)}) {
    const vm::vec4 q = vm::sva_quat_between(f3(a), f3(-a));
    CHECK(glm::length(d3(vm::sva_quat_rotate(q, f3(a))) + a) < 1e-6);
  }
}

TEST_CASE("Rodrigues vectors near |r| = pi are canonicalised") {
  // r and -r at angle pi are the same rotation: both give one Rodrigues vector.
  util::Rng rng(9);
  for (int i = 0; i < 100; ++i) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const vm::vec4 qp = vm::sva_quat_axis_angle(f3(axis), static_cast<float>(std::numbers::pi));
    const vm::vec4 qm = vm::sva_quat_axis_angle(f3(-axis), static_cast<float>(std::numbers::pi));
    const glm::dvec3 rp = d3(vm::sva_quat_to_rodrigues(qp));
    const glm::dvec3 rm = d3(vm::sva_quat_to_rodrigues(qm));
    CHECK(glm::length(rp - rm) < 1e-4);
    CHECK(std::fabs(glm::length(rp) - std::numbers::pi) < 1e-4);
    // The double-precision log follows the same rule.
    const glm::dvec3 dp = so3::log(so3::exp(axis * std::numbers::pi));
    const glm::dvec3 dm = so3::log(so3::exp(-axis * std::numbers::pi));
    CHECK(glm::length(dp - dm) < 1e-6);
    CHECK(glm::length(dp - rp) < 1e-4);
  }
  // And the bins agree.
  const vm::SvaPoseGrid g = grid_of(paper_space());
  const vm::vec4 q1 = vm::sva_quat_axis_angle(vm::vec3(0.6f, -0.8f, 0.0f), static_cast<float>(std::numbers::pi));
  const vm::vec4 q2 = vm::sva_quat_axis_angle(vm::vec3(-0.6f, 0.8f, 0.0f), static_cast<float>(std::numbers::pi));
  const vm::vec3 r1 = vm::sva_quat_to_rodrigues(q1), r2 = vm::sva_quat_to_rodrigues(q2);
  CHECK(vm::sva_rotation_bin(r1.x, g) == vm::sva_rotation_bin(r2.x, g));
  CHECK(vm::sva_rotation_bin(r1.y, g) == vm::sva_rotation_bin(r2.y, g));
}

TEST_CASE("two-point alignment recovers a known pose") {
  util::Rng rng(31);
  for (int i = 0; i < 100; ++i) {
    const RigidPose pose = random_pose(1000 + i, 150.0);
    const glm::dvec3 pa(rng.uniform(-30, 30), rng.uniform(-30, 30), rng.uniform(-30, 30));
    const glm::dvec3 pb = pa + glm::dvec3(rng.uniform(-40, 40), rng.uniform(-40, 40), rng.uniform(-40, 40));
    if (glm::length(pb - pa) < 5.0) continue;
    const glm::dvec3 na = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const glm::dvec3 nb = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const vm::SvaAlignment al = vm::sva_align(patch(pose.apply(pa), pose.rotate(na)),
                                              patch(pose.apply(pb), pose.rotate(nb)), patch(pa, na), patch(pb, nb));
    REQUIRE(al.valid == 1);
    const vm::vec4 q = vm::sva_quat_mul(vm::sva_quat_axis_angle(al.axis, al.beta_hat), al.q1);
    const glm::dmat3 R = mat_of(q);
    INFO("case " << i << " conf " << al.align_conf);
    CHECK(angle_between(R, pose.R) < 1e-3);
    const glm::dvec3 T = d3(al.c_obs - vm::sva_quat_rotate(vm::sva_quat_axis_angle(al.axis, al.beta_hat), al.c_map_r));
    CHECK(glm::length(T - pose.T) < 1e-2);
    CHECK(al.align_conf > 0.0f);
    CHECK(al.align_conf <= 1.0f);
    CHECK(std::fabs(al.sigma - SVA_SIGMA_INIT / std::max(al.align_conf, SVA_MIN_ALIGN_CONF)) < 1e-6f * al.sigma);
  }
}

TEST_CASE("two-point alignment of anti-parallel axes (180-degree rotations)") {
  // The object is turned half way round an axis perpendicular to the pair:
  // the observed axis is the map axis reversed, R1 takes the fixed half-turn
  // branch and beta-hat must still recover the pose exactly.
  util::Rng rng(37);
  for (int i = 0; i < 50; ++i) {
    const glm::dvec3 u = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    glm::dvec3 perp = glm::normalize(glm::cross(u, glm::dvec3(rng.normal(), rng.normal(), rng.normal())));
    RigidPose pose;
    pose.R = so3::exp(perp * std::numbers::pi);
    pose.T = glm::dvec3(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100));
    const glm::dvec3 pa(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20));
    const glm::dvec3 pb = pa + 30.0 * u;
    const glm::dvec3 na = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const glm::dvec3 nb = glm::normalize(glm::dvec3(rng.normal(), rng.normal(), rng.normal()));
    const vm::SvaAlignment al = vm::sva_align(patch(pose.apply(pa), pose.rotate(na)),
                                              patch(pose.apply(pb), pose.rotate(nb)), patch(pa, na), patch(pb, nb));
    REQUIRE(al.valid == 1);
    CHECK(glm::dot(d3(al.axis), u) < -0.99999);
    const glm::dmat3 R = mat_of(vm::sva_quat_mul(vm::sva_quat_axis_angle(al.axis, al.beta_hat), al.q1));
    CHECK(angle_between(R, pose.R) < 1e-3);
    const glm::dvec3 T = d3(al.c_obs - vm::sva_quat_rotate(vm::sva_quat_axis_angle(al.axis, al.beta_hat), al.c_map_r));
    CHECK(glm::length(T - pose.T) < 1e-2);
  }
}

TEST_CASE("reflection case: normals that only a reflection would align still give a proper rotation") {
  // The map normal at a is the mirror image of the observed one (through the
  // plane holding the axis and b's normal): an unconstrained SVD fit of
  // H = sum pm pn^T can return det < 0; Eq 18's fix and the closed form give the
  // best proper rotation about the axis.
  const glm::dvec3 pa(0, 0, 0), pb(20, 0, 0);
  const glm::dvec3 na = glm::normalize(glm::dvec3(0, 1, 1)), nb(0, 1, 0);
  const glm::dvec3 ma = glm::normalize(glm::dvec3(0, 1, -1)), mb(0, 1, 0);
  const vm::SvaAlignment al = vm::sva_align(patch(pa, na), patch(pb, nb), patch(pa, ma), patch(pb, mb));
  REQUIRE(al.valid == 1);
  CHECK(al.beta_hat == Approx(std::atan2(1.0, 1.0)).epsilon(1e-5));
  CHECK(al.align_conf == Approx(1.0f).epsilon(1e-5));
  const glm::dmat3 R = mat_of(vm::sva_quat_mul(vm::sva_quat_axis_angle(al.axis, al.beta_hat), al.q1));
  CHECK(glm::determinant(R) == Approx(1.0).epsilon(1e-5));
  // Brute force: no rotation about the axis fits better in least squares.
  auto cost = [&](double b) {
    const glm::dmat3 Rb = so3::exp(glm::dvec3(b, 0, 0));
    const glm::dvec3 ea = Rb * ma - na, eb = Rb * mb - nb;
    return glm::dot(ea, ea) + glm::dot(eb, eb);
  };
  for (int k = 0; k < 360; ++k) CHECK(cost(al.beta_hat) <= cost(k * std::numbers::pi / 180.0) + 1e-6);
  // Exact mirror images on both ends leave beta unconstrained (H has rank < 2):
  // any beta is optimal, and the answer is finite.
  const vm::SvaAlignment flat = vm::sva_align(patch(pa, na), patch(pb, ma), patch(pa, ma), patch(pb, na));
  CHECK(std::isfinite(flat.beta_hat));
  CHECK(std::isfinite(flat.sigma));
}

TEST_CASE("degenerate alignments: coincident points, normals along the axis, edge contacts") {
  const vm::SvaPoseGrid g = grid_of(paper_space());
  // Coincident observed points: no axis, no vote.
  vm::SvaAlignment al = vm::sva_align(patch({1, 2, 3}, {0, 0, 1}), patch({1, 2, 3}, {0, 0, 1}),
                                      patch({0, 0, 0}, {0, 0, 1}), patch({10, 0, 0}, {0, 0, 1}));
  CHECK(al.valid == 0);
  CHECK(vm::sva_beta_plan(al, g).n == 0);
  // Normals parallel to the axis, and edge contacts (normConf = 0): alignConf 0,
  // sigma huge: the whole circle, capped, evenly weighted, mass preserved.
  for (int c = 0; c < 2; ++c) {
    const float conf = c == 0 ? 1.0f : 0.0f;
    const glm::dvec3 n = c == 0 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
    al = vm::sva_align(patch({0, 0, 0}, n, conf), patch({20, 0, 0}, n, conf), patch({0, 0, 0}, n, conf),
                       patch({0, 20, 0}, n, conf));
    REQUIRE(al.valid == 1);
    CHECK(al.align_conf == 0.0f);
    CHECK(std::isfinite(al.sigma));
    const vm::SvaBetaPlan plan = vm::sva_beta_plan(al, g);
    const int n_samples = plan.n;
    CHECK(n_samples >= 8);
    CHECK(n_samples < SVA_MAX_BETA_SAMPLES);
    const float ws = vm::sva_beta_weight_sum(plan);
    CHECK(std::isfinite(ws));
    CHECK(ws == Approx(n_samples).epsilon(1e-3));
    std::int64_t total = 0;
    for (int s = 0; s < n_samples; ++s) {
      const vm::SvaVote v =
          vm::sva_vote(al, plan, g, 0, vm::sva_beta_weight(plan, s) * vm::sva_vote_scale(0.5f, ws), s);
      CHECK(v.inside == 1);
      total += v.mass;
    }
    CHECK(std::fabs(static_cast<double>(total) / SVA_FIXED_ONE - 0.5) < 1e-3);
  }
}

TEST_CASE("a Gaussian narrower than a bin puts its mass in at least one bin") {
  PoseSpaceSpec spec = paper_space();
  spec.translation_bins = 2;  // bins of 200 mm, rotation bins of 2 pi / 3
  spec.rotation_bins = 3;
  const vm::SvaPoseGrid g = grid_of(spec);
  const vm::SvaAlignment al = vm::sva_align(patch({0, 0, 0}, {0, 1, 0}), patch({20, 0, 0}, {0, 1, 0}),
                                            patch({0, 0, 0}, {0, 1, 0}), patch({20, 0, 0}, {0, 1, 0}));
  REQUIRE(al.sigma == Approx(SVA_SIGMA_INIT));
  const vm::SvaBetaPlan plan = vm::sva_beta_plan(al, g);
  CHECK(plan.n % 2 == 1);  // the mean itself is sampled
  const float scale = vm::sva_vote_scale(1.0f, vm::sva_beta_weight_sum(plan));
  std::int64_t total = 0;
  for (int s = 0; s < plan.n; ++s) total += vm::sva_vote(al, plan, g, 0, vm::sva_beta_weight(plan, s) * scale, s).mass;
  CHECK(std::fabs(static_cast<double>(total) / SVA_FIXED_ONE - 1.0) < 1e-3);
}

TEST_CASE("likelihood units: each key term rounds to the nearest unit, and the sum converts to the nearest float") {
  // Exact references in double: a term below 2^24 units rounds half up, above it the float is already whole;
  // the sum (under 2^47 units) is exact in double, so its float is the correctly rounded one.
  sva::util::Rng rng(5, 1);
  for (int i = 0; i < 20000; ++i) {
    const float w = i < 4 ? std::array<float, 4>{0.0f, 1.0f, 0x1p-40f, 0x1p-17f}[i]
                          : static_cast<float>(std::pow(10.0, -14.0 * rng.uniform()));
    const double v = static_cast<double>(w) * 0x1p40;
    const auto want = static_cast<std::uint64_t>(v < 0x1p23 ? std::floor(v + 0.5) : v);
    REQUIRE(vm::sva_likelihood_units(w) == want);
  }
  CHECK(vm::sva_likelihood_units(-1.0f) == 0);
  CHECK(vm::sva_likelihood_units(std::nanf("")) == 0);
  CHECK(vm::sva_likelihood_units(3.0f) == (std::uint64_t{1} << 40));
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t units =
        (static_cast<std::uint64_t>(rng.uniform() * 0x1p32) << 15) ^ static_cast<std::uint64_t>(rng.uniform() * 0x1p32);
    units &= (std::uint64_t{1} << (1 + i % 47)) - 1;  // every magnitude up to 2^47
    if (i < 3) units = std::array<std::uint64_t, 3>{0, (std::uint64_t{1} << 24) - 1, (std::uint64_t{1} << 47) - 1}[i];
    REQUIRE(vm::sva_likelihood_of_units(units) == static_cast<float>(static_cast<double>(units) * 0x1p-40));
  }
}

TEST_CASE("the vote math header compiles as GLSL") {
  // One source of truth: the same text must be valid GLSL 4.60 for the Vulkan backend.
  if (std::system("command -v glslangValidator > /dev/null 2>&1") != 0) skip("glslangValidator not installed");
  const auto dir = temp_dir("vote-math-glsl");
  std::ofstream(dir / "check.comp") << R"(#version 460
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "sva_shared.h"
#include "sva_vote_math.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Out { uint64_t keys[]; };
layout(std430, binding = 1) buffer In { float v[]; };
void main() {
  SvaPatch a; a.p = vec3(v[0], v[1], v[2]); a.n = vec3(v[3], v[4], v[5]); a.conf = v[6];
  SvaPatch b = a; b.p.x += 10.0f;
  SvaAlignment al = sva_align(a, b, b, a);
  SvaPoseGrid g = sva_pose_grid(int(v[7]), 50, -200.0f, 8.0f, 9, 0.698f);
  SvaBetaPlan plan = sva_beta_plan(al, g);
  float scale = sva_vote_scale(0.5f, sva_beta_weight_sum(plan));
  int i = int(gl_GlobalInvocationID.x);
  SvaVote vt = sva_vote(al, plan, g, 1u, sva_beta_weight(plan, i) * scale, i);
  keys[gl_GlobalInvocationID.x] = vt.key + uint64_t(vt.mass);
}
)";
  // The source tree's shaders/include, from CMake: __FILE__ is relative to the build folder when ccache's
  // base_dir rewrites paths, and ctest runs the tests from another folder.
  const std::string shader_include = SVA_TEST_SHADER_INCLUDE;
  const std::string cmd = "glslangValidator -V --target-env vulkan1.2 -I" + shader_include + " -o " +
                          (dir / "check.spv").string() + " " + (dir / "check.comp").string() + " > " +
                          (dir / "log.txt").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream log(dir / "log.txt");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  INFO(text);
  CHECK(rc == 0);
}
