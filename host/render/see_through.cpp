#include "render/see_through.h"

#include <algorithm>
#include <bit>

#include "render/surface_material.h"

namespace zz {

namespace {

// Where a ray going on along `dir` past the hit at barycentrics (u, v) of the triangle at
// t3 starts: just behind the surface, on the side `dir` leaves it by.
glm::vec3 origin_behind(const Scene& scene, size_t t3, float u, float v, const glm::vec3& dir) {
  const glm::vec3 &p0 = scene.positions[t3], &p1 = scene.positions[t3 + 1], &p2 = scene.positions[t3 + 2];
  glm::vec3 n = triangle_normal(p0, p1, p2);
  if (glm::dot(n, dir) < 0.0f) n = -n;
  return offset_ray_origin(interpolate_hit(p0, p1, p2, u, v), n);
}

// Traces the `lanes` of `rays` again and takes their hits (a continuation: counted so).
void continue_lanes(const Bvh& bvh, const PacketBuilder& rays, int lanes, LaneHits& hits, RayCounters& counters) {
  counters.continuation += uint64_t(std::popcount(unsigned(lanes)));
  HitPacket4 next;
  bvh.intersect4(rays.packet(), mask4::from_bits(lanes), next);
  for (int i = 0; i < 4; ++i)
    if ((lanes >> i) & 1) hits.take(next, i);
}

// Lane i's hit point, interpolated on its triangle.
glm::vec3 hit_point(const Scene& scene, const LaneHits& hits, int i) {
  const size_t t3 = size_t(hits.prim[i]) * 3;
  return interpolate_hit(scene.positions[t3], scene.positions[t3 + 1], scene.positions[t3 + 2], hits.u[i], hits.v[i]).p;
}

}  // namespace

void pass_cutouts(const Scene& scene, const Bvh& bvh, const RayPacket4& rays, int active_bits, LaneHits& hits,
                  float skipped[4], RayCounters& counters) {
  for (int layer = 0;; ++layer) {
    PacketBuilder behind;
    int again = 0;
    for (int i = 0; i < 4; ++i) {
      if (!((active_bits >> i) & 1) || hits.prim[i] < 0) continue;
      const size_t t3 = size_t(hits.prim[i]) * 3;
      const Material& m = scene.materials[scene.material_of[size_t(hits.prim[i])]];
      if (!m.see_through() || coverage(scene, m, Texcoords(scene, t3, hits.u[i], hits.v[i])) > 0.0f) continue;
      if (layer == kMaxSeeThroughLayers) {
        hits.prim[i] = -1;
        ++counters.layer_limit;
        continue;
      }
      const glm::vec3 dir = rays.direction(i);
      const glm::vec3 origin = origin_behind(scene, t3, hits.u[i], hits.v[i], dir);
      skipped[i] += hits.t[i] * glm::length(dir);
      behind.set(i, origin, dir, kInfinity);
      again |= 1 << i;
    }
    if (again == 0) break;
    continue_lanes(bvh, behind, again, hits, counters);
  }
}

void clip_near(const Scene& scene, const Bvh& bvh, const RayPacket4& rays, int active_bits, LaneHits& hits,
               float skipped[4], const CameraClip& clip, RayCounters& counters) {
  if (!(clip.znear > 0.0f)) return;
  PacketBuilder from_plane;
  int again = 0;
  for (int i = 0; i < 4; ++i) {
    if (!((active_bits >> i) & 1) || hits.prim[i] < 0) continue;
    if (clip.depth(hit_point(scene, hits, i)) >= clip.znear) continue;
    const glm::vec3 origin = rays.origin(i), dir = rays.direction(i);
    const float along = glm::dot(dir, clip.forward);
    if (!(along > 0.0f)) {
      hits.prim[i] = -1;
      continue;
    }
    const float s = std::max(0.0f, (clip.znear - clip.depth(origin)) / along);  // in units of |dir|
    from_plane.set(i, origin + dir * s, dir, kInfinity);
    skipped[i] += s * glm::length(dir);
    again |= 1 << i;
  }
  if (again != 0) continue_lanes(bvh, from_plane, again, hits, counters);
}

void clip_far(const Scene& scene, int active_bits, LaneHits& hits, const CameraClip& clip) {
  if (!(clip.zfar < kInfinity)) return;
  for (int i = 0; i < 4; ++i) {
    if (!((active_bits >> i) & 1) || hits.prim[i] < 0) continue;
    if (clip.depth(hit_point(scene, hits, i)) > clip.zfar) hits.prim[i] = -1;
  }
}

template <bool kTextured, bool kSeeThrough, bool kGlass>
void shadow_transmittance(const Scene& scene, const Bvh& bvh, const Light& light, PacketBuilder& rays, int lanes,
                          glm::vec3 through[4], RayCounters& counters) {
  for (int i = 0; i < 4; ++i) through[i] = glm::vec3((lanes >> i) & 1 ? 1.0f : 0.0f);
  for (int layer = 0; layer <= kMaxSeeThroughLayers && lanes != 0; ++layer) {
    counters.shadow += uint64_t(std::popcount(unsigned(lanes)));
    HitPacket4 packet_hits;
    bvh.intersect4(rays.packet(), mask4::from_bits(lanes), packet_hits);
    const LaneHits hits(packet_hits);
    int next = 0;
    for (int i = 0; i < 4; ++i) {
      if (!((lanes >> i) & 1) || hits.prim[i] < 0) continue;  // reached the light
      const size_t t3 = size_t(hits.prim[i]) * 3;
      const uint32_t index = scene.material_of[size_t(hits.prim[i])];
      const Material& m = scene.materials[index];
      const glm::vec3 &p0 = scene.positions[t3], &p1 = scene.positions[t3 + 1], &p2 = scene.positions[t3 + 2];
      const glm::vec3 dir(rays.d[0][i], rays.d[1][i], rays.d[2][i]);
      const Texcoords tc(scene, t3, hits.u[i], hits.v[i]);
      const float alpha = kSeeThrough ? coverage(scene, m, tc) : 1.0f;
      glm::vec3 tint(0.0f);
      bool exits_volume = false;
      if constexpr (kGlass) {
        WhittedMaterial local;
        glm::vec3 albedo;
        const WhittedMaterial& w = material_at<kTextured>(scene, index, &tc, local, albedo);
        tint = w.transmission;
        const glm::vec3 ng = glm::cross(p1 - p0, p2 - p0);
        exits_volume = w.transmits() && glm::dot(ng, dir) > 0.0f;  // hit from inside
      }
      glm::vec3 f = glm::vec3(1.0f - alpha) + alpha * tint;
      if constexpr (kGlass) {
        if (exits_volume) {
          const glm::vec3 sigma = scene.whitted[index].absorption;
          const float d = hits.t[i] * glm::length(dir);
          f *= glm::exp(-sigma * d);
        }
      }
      through[i] *= f;
      if (!(through[i].r > 0.0f || through[i].g > 0.0f || through[i].b > 0.0f)) {
        through[i] = glm::vec3(0.0f);
        continue;
      }
      if (layer == kMaxSeeThroughLayers) {  // a surface that lets light through, one too many
        through[i] = glm::vec3(0.0f);
        ++counters.layer_limit;
        continue;
      }
      // Continue from just behind the surface, towards the same light.
      const glm::vec3 origin = origin_behind(scene, t3, hits.u[i], hits.v[i], dir);
      if (light.type == Light::Type::Directional) rays.set(i, origin, dir, kInfinity);
      else rays.set(i, origin, light.position - origin, 1.0f - kShadowEpsilon);
      next |= 1 << i;
    }
    lanes = next;
  }
}

// The kernels' combinations (render/shader.cpp).
#define ZZ_SHADOW_TRANSMITTANCE(textured, see_through, glass)                                                   \
  template void shadow_transmittance<textured, see_through, glass>(const Scene&, const Bvh&, const Light&,        \
                                                                   PacketBuilder&, int, glm::vec3[4], RayCounters&);
ZZ_SHADOW_TRANSMITTANCE(false, false, false)
ZZ_SHADOW_TRANSMITTANCE(false, false, true)
ZZ_SHADOW_TRANSMITTANCE(false, true, false)
ZZ_SHADOW_TRANSMITTANCE(false, true, true)
ZZ_SHADOW_TRANSMITTANCE(true, false, false)
ZZ_SHADOW_TRANSMITTANCE(true, false, true)
ZZ_SHADOW_TRANSMITTANCE(true, true, false)
ZZ_SHADOW_TRANSMITTANCE(true, true, true)
#undef ZZ_SHADOW_TRANSMITTANCE

}  // namespace zz
