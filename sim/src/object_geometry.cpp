// An object mesh in Embree. Embree reports errors through a callback that may
// not throw (it is called from C); the message is kept per thread and turned
// into sva::Error right after the Embree call that raised it.
#include <sva/error.hpp>
#include <sva/sim/tactile_sensor.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include <embree3/rtcore.h>

namespace sva::sim {

namespace {

thread_local std::string t_embree_error;

extern "C" void on_embree_error(void*, RTCError code, const char* message) {
  t_embree_error =
      "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "(no message)");
}

void check(const std::string& what) {
  if (!t_embree_error.empty()) {
    std::string e = std::move(t_embree_error);
    t_embree_error.clear();
    throw Error(what + ": " + e);
  }
}

// One device per process: creating devices is expensive and they are thread-safe.
RTCDevice device() {
  static std::mutex mutex;
  static RTCDevice dev = nullptr;
  std::lock_guard lock(mutex);
  if (!dev) {
    dev = rtcNewDevice("threads=1,set_affinity=0");  // builds are small; our own threads do the ray work
    if (!dev)
      throw Error("cannot create an Embree device (error " +
                  std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(dev, on_embree_error, nullptr);
  }
  return dev;
}

}  // namespace

struct ObjectGeometry::Impl {
  Mesh mesh;
  RTCScene scene = nullptr;
  std::vector<double> cdf;  // cumulative triangle areas, for sampling by area
};

ObjectGeometry::ObjectGeometry(Mesh mesh) : impl_(std::make_unique<Impl>()) {
  impl_->mesh = std::move(mesh);
  const Mesh& m = impl_->mesh;
  if (m.triangles.empty()) throw Error("object geometry: mesh has no triangles");
  RTCDevice dev = device();
  t_embree_error.clear();
  impl_->scene = rtcNewScene(dev);
  check("creating the Embree scene");
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);  // rays along shared edges must not slip through
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  check("creating the Embree geometry");
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), m.positions.size()));
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), m.triangles.size()));
  if (!v || !t) {
    rtcReleaseGeometry(geom);
    check("allocating Embree buffers");
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
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
  try {
    check("building the Embree scene");
  } catch (...) {
    rtcReleaseScene(impl_->scene);
    throw;
  }
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

RTCRayHit make_ray(const glm::dvec3& o, const glm::dvec3& d, double tnear, double tfar, unsigned id) {
  RTCRayHit rh;
  rh.ray.org_x = static_cast<float>(o.x);
  rh.ray.org_y = static_cast<float>(o.y);
  rh.ray.org_z = static_cast<float>(o.z);
  rh.ray.dir_x = static_cast<float>(d.x);
  rh.ray.dir_y = static_cast<float>(d.y);
  rh.ray.dir_z = static_cast<float>(d.z);
  rh.ray.tnear = static_cast<float>(tnear);
  rh.ray.tfar = static_cast<float>(tfar);
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = id;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

ObjectGeometry::Hit hit_of(const RTCRayHit& rh) {
  ObjectGeometry::Hit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  h.triangle = rh.hit.primID;
  const glm::dvec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const double len = glm::length(n);
  h.normal = len > 0 ? n / len : glm::dvec3(0.0);
  return h;
}

}  // namespace

ObjectGeometry::Hit ObjectGeometry::intersect(const glm::dvec3& o, const glm::dvec3& d, double tnear,
                                              double tfar) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = make_ray(o, d, tnear, tfar, 0);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  return hit_of(rh);
}

void ObjectGeometry::intersect_parallel(const std::vector<glm::dvec3>& origins, const glm::dvec3& d, double tfar,
                                        std::vector<Hit>& hits) const {
  thread_local std::vector<RTCRayHit> rays;
  rays.resize(origins.size());
  for (std::size_t i = 0; i < origins.size(); ++i)
    rays[i] = make_ray(origins[i], d, 0.0, tfar, static_cast<unsigned>(i));
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  if (!rays.empty())
    rtcIntersect1M(impl_->scene, &ctx, rays.data(), static_cast<unsigned>(rays.size()), sizeof(RTCRayHit));
  hits.resize(origins.size());
  for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = hit_of(rays[i]);
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
