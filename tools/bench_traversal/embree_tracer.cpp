#include "embree_tracer.h"

#include <chrono>
#include <cstring>

#ifdef ZZ_BENCH_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace zz::bench {

#ifdef ZZ_BENCH_HAVE_EMBREE
struct EmbreeTracer::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

bool EmbreeTracer::available() { return true; }

EmbreeTracer::EmbreeTracer(const std::vector<glm::vec3>& positions) : impl_(new Impl) {
  auto start = std::chrono::steady_clock::now();
  impl_->device = rtcNewDevice(nullptr);
  impl_->scene = rtcNewScene(impl_->device);
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  size_t n = positions.size() / 3;
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                             RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  for (size_t i = 0; i < 3 * n; ++i) {
    v[3 * i] = positions[i].x, v[3 * i + 1] = positions[i].y, v[3 * i + 2] = positions[i].z;
    idx[i] = unsigned(i);
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeTracer::~EmbreeTracer() {
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

namespace {
void to_embree(const RayPacket4& r, RTCRay4& e) {
  r.ox.store(e.org_x), r.oy.store(e.org_y), r.oz.store(e.org_z);
  r.dx.store(e.dir_x), r.dy.store(e.dir_y), r.dz.store(e.dir_z);
  r.tmax.store(e.tfar);
  for (int i = 0; i < 4; ++i) e.tnear[i] = 0.0f, e.time[i] = 0.0f, e.mask[i] = ~0u, e.id[i] = 0, e.flags[i] = 0;
}
}  // namespace

void EmbreeTracer::intersect4(const RayPacket4& rays, int mask, HitPacket4& hits) const {
  alignas(16) RTCRayHit4 rh;
  to_embree(rays, rh.ray);
  alignas(16) int valid[4];
  for (int i = 0; i < 4; ++i) {
    valid[i] = (mask >> i & 1) ? -1 : 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect4(valid, impl_->scene, &ctx, &rh);
  alignas(16) int32_t prim[4];
  alignas(16) float t[4];
  for (int i = 0; i < 4; ++i) {
    bool hit = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    prim[i] = hit ? int32_t(rh.hit.primID[i]) : -1;
    t[i] = hit ? rh.ray.tfar[i] : kInfinity;
  }
  hits.prim = _mm_load_si128(reinterpret_cast<const __m128i*>(prim));
  hits.t = float4::load(t);
  hits.u = float4::load(rh.hit.u), hits.v = float4::load(rh.hit.v);
}

int EmbreeTracer::occluded4(const RayPacket4& rays, int mask) const {
  alignas(16) RTCRay4 r;
  to_embree(rays, r);
  alignas(16) int valid[4];
  for (int i = 0; i < 4; ++i) valid[i] = (mask >> i & 1) ? -1 : 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded4(valid, impl_->scene, &ctx, &r);
  int out = 0;
  for (int i = 0; i < 4; ++i) out |= (valid[i] && r.tfar[i] < 0.0f) << i;  // -inf = blocked
  return out;
}

Hit EmbreeTracer::intersect1(const Ray& ray) const {
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x, rh.ray.org_y = ray.origin.y, rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.dir.x, rh.ray.dir_y = ray.dir.y, rh.ray.dir_z = ray.dir.z;
  rh.ray.tnear = 0.0f, rh.ray.tfar = ray.tmax, rh.ray.time = 0.0f;
  rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit{};
  return Hit{rh.ray.tfar, rh.hit.u, rh.hit.v, int32_t(rh.hit.primID)};
}

bool EmbreeTracer::occluded1(const Ray& ray) const {
  RTCRay r;
  r.org_x = ray.origin.x, r.org_y = ray.origin.y, r.org_z = ray.origin.z;
  r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
  r.tnear = 0.0f, r.tfar = ray.tmax, r.time = 0.0f, r.mask = ~0u, r.id = 0, r.flags = 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0.0f;
}
#else
struct EmbreeTracer::Impl {};
bool EmbreeTracer::available() { return false; }
EmbreeTracer::EmbreeTracer(const std::vector<glm::vec3>&) {}
EmbreeTracer::~EmbreeTracer() = default;
void EmbreeTracer::intersect4(const RayPacket4&, int, HitPacket4& h) const { h.prim = int4(-1); }
int EmbreeTracer::occluded4(const RayPacket4&, int) const { return 0; }
Hit EmbreeTracer::intersect1(const Ray&) const { return {}; }
bool EmbreeTracer::occluded1(const Ray&) const { return false; }
#endif

}  // namespace zz::bench
