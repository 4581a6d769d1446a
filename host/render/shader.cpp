#include "render/shader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

namespace zz {

namespace {

constexpr float kInvPi = 0.318309886f;
constexpr float kRadianceMax = 1e30f;  // keeps sums finite however bright the lights

int count_lanes(mask4 m) { return std::popcount(unsigned(m.bits())); }

glm::vec3 lane(const float4& x, const float4& y, const float4& z, int i) { return {x[i], y[i], z[i]}; }

// What the shader needs at one lane's hit point.
struct SurfacePoint {
  SurfacePosition hit; // hit point from barycentrics + its rounding-error bound
  glm::vec3 ng;        // geometric normal facing the incoming ray
  glm::vec3 ns;        // shading normal facing the incoming ray, same hemisphere as ng
  glm::vec3 wo;        // unit direction back towards the ray origin
  glm::vec3 albedo;    // diffuse reflectance (texture applied)
  bool front = true;   // the ray hit the side the triangle's winding normal points to
  float distance = 0;  // length of the ray segment to the hit
  const WhittedMaterial* material = nullptr;
};

// Fills a packet lane by lane, then loads it once. Unused lanes stay harmless
// (zero origin, +z direction, tmax 0) and are masked off anyway.
struct PacketBuilder {
  alignas(16) float o[3][4] = {};
  alignas(16) float d[3][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {1, 1, 1, 1}};
  alignas(16) float tmax[4] = {};

  void set(int i, glm::vec3 origin, glm::vec3 dir, float t) {
    for (int c = 0; c < 3; ++c) {
      o[c][i] = origin[c];
      d[c][i] = dir[c];
    }
    tmax[i] = t;
  }
  RayPacket4 packet() const {
    return {float4::load(o[0]), float4::load(o[1]), float4::load(o[2]), float4::load(d[0]),
            float4::load(d[1]), float4::load(d[2]), float4::load(tmax)};
  }
};

// glTF KHR_lights_punctual: incident irradiance factor and unit direction to the light.
bool light_towards(const Light& light, glm::vec3 p, glm::vec3& to_light, float& tmax, glm::vec3& radiance_scale) {
  if (light.type == Light::Type::Directional) {
    to_light = -glm::normalize(light.direction);
    tmax = kInfinity;
    radiance_scale = light.intensity;
    return true;
  }
  glm::vec3 d = light.position - p;
  float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return false;
  float dist = std::sqrt(dist2);
  to_light = d / dist;
  tmax = dist;
  float falloff = 1.0f / dist2;
  if (light.range > 0.0f) {  // the glTF spec's recommended smooth window
    float r = dist / light.range;
    float w = std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
    falloff *= w * w;
  }
  if (light.type == Light::Type::Spot) {
    float cd = glm::dot(glm::normalize(light.direction), -to_light);
    float cos_outer = std::cos(light.outer_cone), cos_inner = std::cos(light.inner_cone);
    float scale = 1.0f / std::max(0.001f, cos_inner - cos_outer);
    float t = std::clamp((cd - cos_outer) * scale, 0.0f, 1.0f);
    falloff *= t * t;
  }
  radiance_scale = light.intensity * falloff;
  return falloff > 0.0f;
}

}  // namespace

float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
  float cos_t = std::sqrt(1.0f - sin2_t);
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

Shader::Shader(const Scene& scene, const Bvh& bvh) : scene_(scene), bvh_(bvh), effects_(scene.effects()) {
  unsigned bits = 0;
  if (effects_.shadows) bits |= kShadows;
  if (effects_.reflection) bits |= kReflection;
  if (effects_.refraction) bits |= kRefraction;
  if (effects_.textures) bits |= kTextures;
  kernel_ = pick_kernel(bits, std::make_integer_sequence<unsigned, kAllEffects + 1>{});
}

template <unsigned... kE>
Shader::Kernel Shader::pick_kernel(unsigned effects, std::integer_sequence<unsigned, kE...>) {
  static constexpr Kernel kernels[] = {&Shader::trace4_impl<kE>...};
  return kernels[effects];
}

template <unsigned kEffects>
Rgb4 Shader::trace4_impl(const RayPacket4& rays, mask4 active, int depth, float4 throughput,
                         RayCounters& counters) const {
  Rgb4 zero{float4(0.0f), float4(0.0f), float4(0.0f)};
  if (active.none()) return zero;

  HitPacket4 hits;
  bvh_.intersect4(rays, active, hits);

  alignas(16) float out[3][4] = {};
  SurfacePoint sp[4];
  bool shaded[4] = {false, false, false, false};
  const int active_bits = active.bits();
  for (int i = 0; i < 4; ++i) {
    if (!((active_bits >> i) & 1)) continue;
    const int prim = hits.prim[i];
    if (prim < 0) {
      out[0][i] = scene_.background.r;
      out[1][i] = scene_.background.g;
      out[2][i] = scene_.background.b;
      continue;
    }
    const glm::vec3 dir = lane(rays.dx, rays.dy, rays.dz, i);
    const float u = hits.u[i], v = hits.v[i], w = 1.0f - u - v;
    const size_t t3 = size_t(prim) * 3;
    const glm::vec3 &p0 = scene_.positions[t3], &p1 = scene_.positions[t3 + 1], &p2 = scene_.positions[t3 + 2];
    SurfacePoint& s = sp[i];
    s.hit = interpolate_hit(p0, p1, p2, u, v);
    const glm::vec3 ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    const float dir_len = glm::length(dir);
    s.wo = -dir / dir_len;
    s.distance = hits.t[i] * dir_len;
    s.front = glm::dot(ng, s.wo) >= 0.0f;
    s.ng = s.front ? ng : -ng;
    glm::vec3 ns = w * scene_.normals[t3] + u * scene_.normals[t3 + 1] + v * scene_.normals[t3 + 2];
    const float ns_len = glm::length(ns);
    ns = ns_len > 0.0f && std::isfinite(ns_len) ? ns / ns_len : ng;
    if (!s.front) ns = -ns;
    // A shading normal pointing away from the viewer would shade a lit side black.
    s.ns = glm::dot(ns, s.wo) > 0.0f ? ns : s.ng;
    const uint32_t mat_index = scene_.material_of[prim];
    s.material = &scene_.whitted[mat_index];
    s.albedo = s.material->diffuse;
    glm::vec3 emission = s.material->emission;
    if constexpr ((kEffects & kTextures) != 0) {
      const Material& gltf = scene_.materials[mat_index];
      if (gltf.base_color_texture >= 0 || gltf.emissive_texture >= 0) {
        const glm::vec2 uv = w * scene_.uvs[t3] + u * scene_.uvs[t3 + 1] + v * scene_.uvs[t3 + 2];
        if (gltf.base_color_texture >= 0)
          s.albedo *= glm::vec3(scene_.textures[size_t(gltf.base_color_texture)].sample(uv));
        if (gltf.emissive_texture >= 0 && emission != glm::vec3(0.0f))
          emission *= glm::vec3(scene_.textures[size_t(gltf.emissive_texture)].sample(uv));
      }
    }
    out[0][i] = emission.r;
    out[1][i] = emission.g;
    out[2][i] = emission.b;
    shaded[i] = true;
  }

  // Direct light: one shadow packet per light, lanes that face it.
  if constexpr ((kEffects & kShadows) != 0) {
    for (const Light& light : scene_.lights) {
      PacketBuilder shadow;
      glm::vec3 contribution[4];
      bool want[4] = {false, false, false, false};
      for (int i = 0; i < 4; ++i) {
        if (!shaded[i]) continue;
        const SurfacePoint& s = sp[i];
        glm::vec3 wi, scale;
        float dist;
        if (!light_towards(light, s.hit.p, wi, dist, scale)) continue;
        const float cos_s = glm::dot(s.ns, wi);
        if (cos_s <= 0.0f || glm::dot(s.ng, wi) <= 0.0f) continue;
        const WhittedMaterial& m = *s.material;
        // Normalised Phong: (n+2)/(2 pi) cos^n(R, wo), energy-conserving lobe.
        const glm::vec3 r = 2.0f * glm::dot(s.ns, wi) * s.ns - wi;
        const float cos_r = std::max(0.0f, glm::dot(r, s.wo));
        const float phong = (m.shininess + 2.0f) * 0.5f * kInvPi * std::pow(cos_r, m.shininess);
        const glm::vec3 f = s.albedo * kInvPi + m.specular * phong;
        contribution[i] = f * scale * cos_s;
        if (!(contribution[i].r > 0.0f || contribution[i].g > 0.0f || contribution[i].b > 0.0f)) continue;
        const glm::vec3 origin = offset_ray_origin(s.hit, s.ng);
        if (light.type == Light::Type::Directional)
          shadow.set(i, origin, wi, kInfinity);
        else
          shadow.set(i, origin, light.position - origin, 1.0f);  // t in (0, 1) reaches the light
        want[i] = true;
      }
      const mask4 lanes(want[0], want[1], want[2], want[3]);
      if (lanes.none()) continue;
      counters.shadow += uint64_t(count_lanes(lanes));
      const int blocked = bvh_.occluded4(shadow.packet(), lanes).bits();
      for (int i = 0; i < 4; ++i) {
        if (!want[i] || ((blocked >> i) & 1)) continue;
        out[0][i] += contribution[i].r;
        out[1][i] += contribution[i].g;
        out[2][i] += contribution[i].b;
      }
    }
  }

  // Mirror reflection and refraction, each as one secondary packet.
  if constexpr ((kEffects & (kReflection | kRefraction)) != 0) {
    if (depth < scene_.max_depth) {  // depth = bounces taken so far
      PacketBuilder reflected, refracted;
      glm::vec3 reflect_weight[4], refract_weight[4];
      alignas(16) float path[4], reflect_path[4] = {}, refract_path[4] = {};
      throughput.store(path);
      auto largest = [](const glm::vec3& w) { return std::max(w.r, std::max(w.g, w.b)); };
      bool do_reflect[4] = {false, false, false, false}, do_refract[4] = {false, false, false, false};
      for (int i = 0; i < 4; ++i) {
        if (!shaded[i]) continue;
        const SurfacePoint& s = sp[i];
        const WhittedMaterial& m = *s.material;
        const float cos_i = std::clamp(glm::dot(s.ns, s.wo), 0.0f, 1.0f);
        glm::vec3 kr = m.mirror;
        bool transmit = false;
        float eta = 1.0f;
        if constexpr ((kEffects & kRefraction) != 0) {
          if (m.transmits()) {
            eta = s.front ? 1.0f / m.ior : m.ior;  // n_incident / n_transmitted
            const float f = fresnel_dielectric(cos_i, eta);
            kr = glm::vec3(f);
            refract_weight[i] = (1.0f - f) * m.transmission;
            transmit = f < 1.0f;
          }
        }
        if (!transmit && m.fresnel_mirror && !m.transmits()) {  // Schlick from F0 = mirror
          const float c = 1.0f - cos_i, c5 = c * c * c * c * c;
          kr = m.mirror + (glm::vec3(1.0f) - m.mirror) * c5;
        }
        reflect_path[i] = path[i] * largest(kr);
        if ((kr.r > 0.0f || kr.g > 0.0f || kr.b > 0.0f) && reflect_path[i] >= kMinThroughput) {
          glm::vec3 r = 2.0f * glm::dot(s.ns, s.wo) * s.ns - s.wo;
          if (glm::dot(r, s.ng) <= 0.0f) r = 2.0f * glm::dot(s.ng, s.wo) * s.ng - s.wo;
          reflected.set(i, offset_ray_origin(s.hit, s.ng), r, kInfinity);
          reflect_weight[i] = kr;
          do_reflect[i] = true;
        }
        if constexpr ((kEffects & kRefraction) != 0) {
          if (transmit) refract_path[i] = path[i] * largest(refract_weight[i]);
          if (transmit && refract_path[i] >= kMinThroughput) {
            const float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
            const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin2_t));
            const glm::vec3 t = -eta * s.wo + (eta * cos_i - cos_t) * s.ns;  // Snell, vector form
            if (glm::dot(t, s.ng) < 0.0f) {
              refracted.set(i, offset_ray_origin(s.hit, -s.ng), t, kInfinity);
              do_refract[i] = true;
            }
          }
        }
      }
      const mask4 reflect_lanes(do_reflect[0], do_reflect[1], do_reflect[2], do_reflect[3]);
      if (reflect_lanes.any()) {
        counters.reflection += uint64_t(count_lanes(reflect_lanes));
        const Rgb4 c = trace4_impl<kEffects>(reflected.packet(), reflect_lanes, depth + 1,
                                              float4::load(reflect_path), counters);
        for (int i = 0; i < 4; ++i)
          if (do_reflect[i]) {
            out[0][i] += reflect_weight[i].r * c.r[i];
            out[1][i] += reflect_weight[i].g * c.g[i];
            out[2][i] += reflect_weight[i].b * c.b[i];
          }
      }
      if constexpr ((kEffects & kRefraction) != 0) {
        const mask4 refract_lanes(do_refract[0], do_refract[1], do_refract[2], do_refract[3]);
        if (refract_lanes.any()) {
          counters.refraction += uint64_t(count_lanes(refract_lanes));
          const Rgb4 c = trace4_impl<kEffects>(refracted.packet(), refract_lanes, depth + 1,
                                                float4::load(refract_path), counters);
          for (int i = 0; i < 4; ++i)
            if (do_refract[i]) {
              out[0][i] += refract_weight[i].r * c.r[i];
              out[1][i] += refract_weight[i].g * c.g[i];
              out[2][i] += refract_weight[i].b * c.b[i];
            }
        }
      }
    }
  }

  // Beer-Lambert: a ray that hits a surface from inside crossed the volume behind it.
  if constexpr ((kEffects & kRefraction) != 0) {
    if (effects_.absorption) {
      for (int i = 0; i < 4; ++i) {
        if (!shaded[i] || sp[i].front) continue;
        const glm::vec3 sigma = sp[i].material->absorption;
        for (int c = 0; c < 3; ++c) out[c][i] *= std::exp(-sigma[c] * sp[i].distance);
      }
    }
  }

  Rgb4 result{float4::load(out[0]), float4::load(out[1]), float4::load(out[2])};
  // NaN (e.g. from a degenerate normal) never leaves the shader; +Inf is capped.
  auto sanitize = [&](float4 x) {
    return select(isnan(x) | !active, float4(0.0f), min(max(x, float4(0.0f)), float4(kRadianceMax)));
  };
  return {sanitize(result.r), sanitize(result.g), sanitize(result.b)};
}

}  // namespace zz
