// An object mesh in Embree, on the process's one device (sva/base/embree.hpp).
//
// Embree only finds the candidate triangles; which one is hit, where and with
// what normal is decided by ray_triangle.hpp in double precision. Embree picks
// its kernels by the CPU (SSE2 to AVX-512) and they round differently in the
// last bits, so its own hits would make every simulated dataset depend on the
// CPU that made it (docs/reliability.md, "Same answers on every machine").
// Every triangle Embree reports anywhere along the ray is collected by a filter
// that rejects it (so traversal goes on); where the ray passes near a
// candidate's boundary, the triangles around its corners join them: a triangle
// that one kernel misses at its edge is then still a candidate through the
// neighbour that kernel hits (robust mode is watertight).
#include <sva/base/embree.hpp>
#include <sva/error.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include "ray_triangle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <span>
#include <string>

#include <embree3/rtcore.h>

namespace sva::sim {

namespace {

// The simulator's device: the process's one (sva/base/embree.hpp), which must have the filter functions the exact
// hits need.
RTCDevice device() {
  static std::once_flag checked;
  RTCDevice dev = embree::device();
  std::call_once(checked, [dev] {
    if (!rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
      throw Error("this Embree was built without filter functions, which the simulator's exact hits need");
  });
  return dev;
}

// The rays' context: where the filter collects every triangle Embree reports (for a stream of rays, tagged with the
// ray's id).
struct CandidateContext {
  RTCIntersectContext context;                   // first member: Embree hands the filter a pointer to it
  std::vector<std::uint32_t>* found = nullptr;   // one ray: its triangles
  std::vector<std::uint64_t>* tagged = nullptr;  // a stream: ray id << 32 | triangle
};

extern "C" void collect_candidate(const RTCFilterFunctionNArguments* args) {
  auto* ctx = reinterpret_cast<CandidateContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const std::uint32_t tri = RTCHitN_primID(args->hit, args->N, i);
    if (ctx->tagged)
      ctx->tagged->push_back(std::uint64_t{RTCRayN_id(args->ray, args->N, i)} << 32 | tri);
    else
      ctx->found->push_back(tri);
    args->valid[i] = 0;  // rejected: traversal goes on to every other triangle along the ray
  }
}

}  // namespace

struct ObjectGeometry::Impl {
  Mesh mesh;
  RTCScene scene = nullptr;
  std::vector<double> cdf;  // cumulative triangle areas, for sampling by area
  TriangleRings rings;      // the triangles around each triangle's corners, by position
  ObjectGeometry::Hit exact_hit(std::span<std::uint32_t> found, const glm::dvec3& o, const glm::dvec3& d, double tnear,
                                double tfar) const;
};

ObjectGeometry::ObjectGeometry(Mesh mesh) : impl_(std::make_unique<Impl>()) {
  impl_->mesh = std::move(mesh);
  const Mesh& m = impl_->mesh;
  if (m.triangles.empty()) throw Error("object geometry: mesh has no triangles");
  RTCDevice dev = device();
  embree::clear_error();
  impl_->scene = rtcNewScene(dev);
  embree::check("creating the Embree scene");
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);  // rays along shared edges must not slip through
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  embree::check("creating the Embree geometry");
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), m.positions.size()));
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), m.triangles.size()));
  if (!v || !t) {
    rtcReleaseGeometry(geom);
    embree::check("allocating Embree buffers");
    throw Error("cannot allocate Embree buffers");
  }
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    v[3 * i] = m.positions[i].x;
    v[3 * i + 1] = m.positions[i].y;
    v[3 * i + 2] = m.positions[i].z;
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    t[3 * i] = m.triangles[i].x;
    t[3 * i + 1] = m.triangles[i].y;
    t[3 * i + 2] = m.triangles[i].z;
  }
  rtcSetGeometryIntersectFilterFunction(geom, collect_candidate);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
  try {
    embree::check("building the Embree scene");
  } catch (...) {
    rtcReleaseScene(impl_->scene);
    throw;
  }
  impl_->rings = TriangleRings(m);
  impl_->cdf.resize(m.triangles.size());
  double acc = 0;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& tr = m.triangles[i];
    glm::dvec3 a(m.positions[tr.x]), b(m.positions[tr.y]), c(m.positions[tr.z]);
    acc += 0.5 * glm::length(glm::cross(b - a, c - a));
    impl_->cdf[i] = acc;
  }
  if (!(acc > 0)) {
    rtcReleaseScene(impl_->scene);
    throw Error("object geometry: mesh has zero area");
  }
}

ObjectGeometry::~ObjectGeometry() {
  if (impl_ && impl_->scene) rtcReleaseScene(impl_->scene);
}

const Mesh& ObjectGeometry::mesh() const { return impl_->mesh; }

namespace {

// Embree's interval is widened so that a triangle whose float test lands just outside [tnear, tfar] is still
// collected; the double-precision test applies the exact interval.
RTCRayHit make_ray(const glm::dvec3& o, const glm::dvec3& d, double tnear, double tfar) {
  const double margin = 1e-3 + 1e-4 * std::fabs(tfar);
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(o.x);
  rh.ray.org_y = static_cast<float>(o.y);
  rh.ray.org_z = static_cast<float>(o.z);
  rh.ray.dir_x = static_cast<float>(d.x);
  rh.ray.dir_y = static_cast<float>(d.y);
  rh.ray.dir_z = static_cast<float>(d.z);
  rh.ray.tnear = static_cast<float>(std::max(0.0, tnear - margin));
  rh.ray.tfar = std::isfinite(tfar) ? static_cast<float>(tfar + margin) : std::numeric_limits<float>::infinity();
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

// The nearest triangle among the candidates, by the exact test; equal distances go to the smaller triangle index, so
// the answer never depends on the order Embree found them in. Where the ray passes near a candidate's boundary, the
// triangles around that candidate's corners are tested too: one of them may be the one hit, and another kernel may
// have reported it instead. A triangle hit away from its boundary is reported by every kernel.
ObjectGeometry::Hit ObjectGeometry::Impl::exact_hit(std::span<std::uint32_t> found, const glm::dvec3& o,
                                                    const glm::dvec3& d, double tnear, double tfar) const {
  std::sort(found.begin(), found.end());
  const auto end = std::unique(found.begin(), found.end());
  Hit best;
  thread_local std::vector<std::uint32_t> edgy;
  edgy.clear();
  auto test = [&](std::uint32_t tri, bool candidate) {
    const glm::uvec3& t = mesh.triangles[tri];
    const TriangleTest h = intersect_triangle(o, d, glm::dvec3(mesh.positions[t.x]), glm::dvec3(mesh.positions[t.y]),
                                              glm::dvec3(mesh.positions[t.z]));
    if (candidate && h.near_edge) edgy.push_back(tri);
    if (!h.hit || h.t < tnear || h.t > tfar) return;
    if (best.hit && (h.t > best.t || (h.t == best.t && tri > best.triangle))) return;
    best.hit = true;
    best.t = h.t;
    best.triangle = tri;
  };
  for (auto it = found.begin(); it != end; ++it) test(*it, true);
  if (!edgy.empty()) {
    rings.expand(edgy);
    for (std::uint32_t tri : edgy)
      if (!std::binary_search(found.begin(), end, tri)) test(tri, false);
  }
  if (best.hit) best.normal = triangle_normal(mesh, best.triangle);
  return best;
}

ObjectGeometry::Hit ObjectGeometry::intersect(const glm::dvec3& o, const glm::dvec3& d, double tnear,
                                              double tfar) const {
  thread_local std::vector<std::uint32_t> found;
  found.clear();
  CandidateContext ctx;
  rtcInitIntersectContext(&ctx.context);
  ctx.found = &found;
  RTCRayHit rh = make_ray(o, d, tnear, tfar);
  rtcIntersect1(impl_->scene, &ctx.context, &rh);
  return impl_->exact_hit(found, o, d, tnear, tfar);
}

// A coherent stream (much faster than one ray at a time); the filter tags each candidate with its ray.
void ObjectGeometry::intersect_parallel(const std::vector<glm::dvec3>& origins, const glm::dvec3& d, double tfar,
                                        std::vector<Hit>& hits) const {
  thread_local std::vector<RTCRayHit> rays;
  thread_local std::vector<std::uint32_t> found;
  thread_local std::vector<std::uint64_t> tagged;
  rays.resize(origins.size());
  for (std::size_t i = 0; i < origins.size(); ++i) {
    rays[i] = make_ray(origins[i], d, 0.0, tfar);
    rays[i].ray.id = static_cast<unsigned>(i);
  }
  tagged.clear();
  CandidateContext ctx;
  rtcInitIntersectContext(&ctx.context);
  ctx.context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  ctx.tagged = &tagged;
  if (!rays.empty())
    rtcIntersect1M(impl_->scene, &ctx.context, rays.data(), static_cast<unsigned>(rays.size()), sizeof(RTCRayHit));
  std::sort(tagged.begin(), tagged.end());  // by ray, then triangle
  hits.resize(origins.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < origins.size(); ++i) {
    found.clear();
    for (; k < tagged.size() && (tagged[k] >> 32) == i; ++k) found.push_back(static_cast<std::uint32_t>(tagged[k]));
    hits[i] = impl_->exact_hit(found, origins[i], d, 0.0, tfar);
  }
}

void ObjectGeometry::sample_surface(double u0, double u1, double u2, glm::dvec3& point, glm::dvec3& normal) const {
  const auto& cdf = impl_->cdf;
  double target = u0 * cdf.back();
  auto it = std::upper_bound(cdf.begin(), cdf.end(), target);
  std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(it - cdf.begin()), cdf.size() - 1);
  while (i > 0 && cdf[i] == cdf[i - 1]) --i;  // never a zero-area triangle
  const auto& tr = impl_->mesh.triangles[i];
  glm::dvec3 a(impl_->mesh.positions[tr.x]), b(impl_->mesh.positions[tr.y]), c(impl_->mesh.positions[tr.z]);
  double s = std::sqrt(u1);
  point = a * (1.0 - s) + b * (s * (1.0 - u2)) + c * (s * u2);
  glm::dvec3 n = glm::cross(b - a, c - a);
  normal = n / glm::length(n);
}

}  // namespace sva::sim
