#include "render/shader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <utility>

#include "aa/signature.h"  // kLightSlots
#include "render/normal_map.h"
#include "render/see_through.h"
#include "render/surface_material.h"

namespace zz {

namespace {

// Weighs lane `lane`'s records at `node` and below it in the path tree by the light the ray
// to `node` keeps: the probes' specular and the footprint probes' weight (the footprinted
// nodes are probed ones, so one walk over the probed subtree reaches both).
void scale_path(const PathSignature4& signature, int node, int lane, glm::vec3 weight) {
  if (!probed(node)) return;
  if (signature.probes) signature.probes.at(node, lane).specular *= weight;
  if (signature.footprint && footprinted(node)) signature.footprint.at(node, lane).weight *= weight;
  scale_path(signature, reflected_node(node), lane, weight);
  scale_path(signature, refracted_node(node), lane, weight);
}

constexpr float kInvPi = 0.318309886f;
// A camera packet's signature holds what its reflection's reflection hit where the path
// to that hit keeps at least this share of the light: chrome seen in chrome (the car's
// bumper: display error 1.109x -> 1.049x the lattice's for +0.008 rays/px at 1024²). A
// dim reflection's reflection cannot show its edges; signing it anyway cost glass +0.06
// rays/px for 1 %.
constexpr float kSignedMirrorPath = 0.5f;
constexpr float kRadianceMax = 1e30f;  // keeps sums finite however bright the lights

// A signature part for a hit and what the ray leaving it hit next (0 = nothing).
uint32_t hit_then(uint32_t first, uint32_t next) { return (first * 0x9E3779B1u) ^ next; }

int count_lanes(mask4 m) { return std::popcount(unsigned(m.bits())); }

// The signature a camera packet's child ray, at path-tree node to_child(parent->node),
// fills: made where the parent records one and the child is signed (`sign`), probed or
// footprinted, with the parent's probes and footprints where the tree follows that node.
std::optional<PathSignature4> child_signature(const PathSignature4* parent, int (*to_child)(int), bool sign) {
  if (!parent) return std::nullopt;
  const int node = to_child(parent->node);
  const bool probe = parent->probes && probed(node), footprint = parent->footprint && footprinted(node);
  if (!sign && !probe && !footprint) return std::nullopt;
  std::optional<PathSignature4> child(std::in_place);
  child->node = node;
  if (probe) child->probes = parent->probes;
  if (footprint) child->footprint = parent->footprint;
  return child;
}

// out += weight * c on the lanes `on` (out in SoA, one row per channel).
void add_weighted(float out[3][4], const bool on[4], const glm::vec3 weight[4], const Rgb4& c) {
  for (int i = 0; i < 4; ++i)
    if (on[i]) {
      out[0][i] += weight[i].r * c.r[i];
      out[1][i] += weight[i].g * c.g[i];
      out[2][i] += weight[i].b * c.b[i];
    }
}

// What the shader needs at one lane's hit point.
struct SurfacePoint {
  SurfacePosition hit; // hit point from barycentrics + its rounding-error bound
  glm::vec3 ng;        // geometric normal facing the incoming ray
  glm::vec3 ns;        // shading normal facing the incoming ray, same hemisphere as ng
  glm::vec3 wo;        // unit direction back towards the ray origin
  glm::vec3 shadow_origin;  // hit.p lifted to the smooth surface, then offset: where shadow rays start
  bool lifted = false;      // the lift moved the point (smooth shading bends the surface outward here)
  glm::vec3 albedo;    // diffuse reflectance (texture applied)
  glm::vec3 dir;       // the ray's direction as traced (not normalised)
  bool front = true;   // the ray hit the side the triangle's winding normal points to
  float distance = 0;  // length of the ray segment to the hit
  float alpha = 1;     // coverage: 1 opaque, 0 cut out, between = BLEND weight
  const WhittedMaterial* material = nullptr;
  WhittedMaterial local;  // the material at this point when its inputs vary per hit
};

// The tangent-space normal map's normal, in world space (glTF: n = 2 * texel - 1, x and y
// scaled by normalTexture.scale; +X along the tangent, +Y along w * cross(N, T)).
glm::vec3 mapped_normal(const Scene& scene, const Material& m, size_t t3, float u, float v, const Texcoords& tc,
                        glm::vec3 n) {
  glm::vec3 frame[3];
  if (!normal_map_frame(scene, t3, u, v, n, frame)) return n;  // no frame (no UVs): unmapped
  return mapped_in_frame(frame, glm::vec3(tc.sample(scene, m.normal_texture)), m.normal_scale, n);
}

// The geometry of lane i's hit (position, facing geometric normal, direction back,
// distance from the ray origin including `skipped`); returns the interpolated vertex
// normal (the geometric one where it degenerates), not yet turned towards the viewer.
glm::vec3 surface_geometry(const Scene& scene, glm::vec3 dir, const LaneHits& hits, int i, float skipped,
                           SurfacePoint& s) {
  const float u = hits.u[i], v = hits.v[i];
  const size_t t3 = size_t(hits.prim[i]) * 3;
  const glm::vec3 &p0 = scene.positions[t3], &p1 = scene.positions[t3 + 1], &p2 = scene.positions[t3 + 2];
  s.hit = interpolate_hit(p0, p1, p2, u, v);
  s.dir = dir;
  const glm::vec3 ng = triangle_normal(p0, p1, p2);
  const float dir_len = glm::length(dir);
  s.wo = -dir / dir_len;
  s.distance = skipped + hits.t[i] * dir_len;
  s.front = glm::dot(ng, s.wo) >= 0.0f;
  s.ng = s.front ? ng : -ng;
  return interpolated_normal(scene, t3, u, v, ng);
}

// The shading normal `ns` (normal map applied) on the side the ray came from.
glm::vec3 facing_shading_normal(const SurfacePoint& s, glm::vec3 ns) {
  if (!s.front) ns = -ns;
  // A shading normal pointing away from the viewer would shade a lit side black.
  return glm::dot(ns, s.wo) > 0.0f ? ns : s.ng;
}

// The shadow terminator: a coarse mesh with interpolated normals is shaded as the smooth
// surface its vertex normals describe, but shadow rays leave the flat triangle, which lies
// inside that surface, so near the terminator they are blocked by the triangle itself or
// its neighbours and lit regions turn black facet by facet. Hanika, "Hacking the Shadow
// Terminator" (Ray Tracing Gems II, 2021): start them from the point projected onto the
// tangent plane of each vertex (normal n_i, the side the ray came from), interpolated with
// the barycentrics, p' = sum b_i (p - min(0, (p - p_i).n_i) n_i): only outward moves,
// so concave regions, where the planes lie below the triangle, keep p. Exact on flat
// meshes (every n_i = ng gives p' = p).
glm::vec3 lift_to_smooth_surface(glm::vec3 p, const glm::vec3* vertices, const glm::vec3* normals, float u, float v,
                                 bool flip) {
  const float b[3] = {1.0f - u - v, u, v};
  glm::vec3 lifted = p;
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 n = flip ? -normals[i] : normals[i];
    const float height = glm::dot(p - vertices[i], n);  // signed, above the vertex's plane
    if (height < 0.0f) lifted -= (b[i] * height) * n;
  }
  return lifted;
}

// The lanes' hit points as the per-light loop needs them, SoA; lanes not shaded hold zeros
// (cos_s = 0: never lit).
struct LitLanes {
  vec3x4 p, ns, ng, wo, albedo, specular, origin;
  float4 shininess;
  mask4 shaded, lifted;
  LitLanes(const SurfacePoint sp[4], const bool shaded_lanes[4]) {
    alignas(16) float a[7][3][4] = {};
    alignas(16) float shin[4] = {};
    for (int i = 0; i < 4; ++i) {
      if (!shaded_lanes[i]) continue;
      const SurfacePoint& s = sp[i];
      const glm::vec3* v[7] = {&s.hit.p, &s.ns, &s.ng, &s.wo, &s.albedo, &s.material->specular, &s.shadow_origin};
      for (int k = 0; k < 7; ++k)
        for (int c = 0; c < 3; ++c) a[k][c][i] = (*v[k])[c];
      shin[i] = s.material->shininess;
    }
    vec3x4* dst[7] = {&p, &ns, &ng, &wo, &albedo, &specular, &origin};
    for (int k = 0; k < 7; ++k) *dst[k] = {float4::load(a[k][0]), float4::load(a[k][1]), float4::load(a[k][2])};
    shininess = float4::load(shin);
    shaded = mask4(shaded_lanes[0], shaded_lanes[1], shaded_lanes[2], shaded_lanes[3]);
    lifted = mask4(sp[0].lifted && shaded_lanes[0], sp[1].lifted && shaded_lanes[1], sp[2].lifted && shaded_lanes[2],
                   sp[3].lifted && shaded_lanes[3]);
  }
};

// cos_r^shininess on the lanes of `lanes` (others 0): std::pow, skipped where cos_r = 0
// (the power is then 0 for the shininess >= 1 materials.cpp gives, as std::pow says).
float4 phong_pow4(float4 cos_r, float4 shininess, mask4 lanes) {
  const int todo = (lanes & ((cos_r > float4(0.0f)) | (shininess <= float4(0.0f)))).bits();
  if (todo == 0) return float4(0.0f);
  alignas(16) float c[4], n[4], out[4] = {};
  cos_r.store(c), shininess.store(n);
  for (int i = 0; i < 4; ++i)
    if ((todo >> i) & 1) out[i] = std::pow(c[i], n[i]);
  return float4::load(out);
}

}  // namespace

float cos_transmitted(float cos_i, float eta) {
  // cos^2_t = 1 - eta^2 (1 - cos^2_i), summed as (1 - eta^2) + eta^2 cos^2_i: exact at
  // eta 1, where the first form lost cos_i near grazing to rounding (ior 1 reflected 1 %
  // at cos_i 2e-4, and everything below 2.4e-4).
  const float cos2_t = (1.0f - eta * eta) + eta * eta * (cos_i * cos_i);
  if (eta > 1.0f && cos2_t <= 0.0f) return -1.0f;  // total internal reflection
  return std::sqrt(std::max(0.0f, cos2_t));
}

float fresnel_dielectric(float cos_i, float eta) {
  if (eta == 1.0f) return 0.0f;  // no interface; at cos_i = 0 the terms below are 0 / 0
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const float cos_t = cos_transmitted(cos_i, eta);
  if (cos_t < 0.0f) return 1.0f;  // total internal reflection
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

Shader::Shader(const Scene& scene, const Bvh& bvh)
    : scene_(scene), bvh_(bvh), effects_(scene.effects()), scene_bounds_(scene.bounds()) {
  light_constants_.reserve(scene.lights.size());
  for (const Light& light : scene.lights) light_constants_.emplace_back(light);
  unsigned bits = 0;
  if (effects_.shadows) bits |= kShadows;
  if (effects_.reflection) bits |= kReflection;
  if (effects_.refraction) bits |= kRefraction;
  if (effects_.textures) bits |= kTextures;
  if (effects_.alpha_mask || effects_.alpha_blend) bits |= kAlpha;
  kernel_ = pick_kernel(bits, std::make_integer_sequence<unsigned, kAllEffects + 1>{});
  volume_bounds_.resize(scene.whitted.size());
  for (size_t t = 0; t < scene.material_of.size(); ++t) {
    const uint32_t m = scene.material_of[t];
    if (m >= scene.whitted.size() || !scene.whitted[m].transmits() || scene.whitted[m].thin_walled) continue;
    for (int k = 0; k < 3; ++k) {
      volume_bounds_[m].lo = glm::min(volume_bounds_[m].lo, scene.positions[3 * t + size_t(k)]);
      volume_bounds_[m].hi = glm::max(volume_bounds_[m].hi, scene.positions[3 * t + size_t(k)]);
    }
  }
  for (VolumeBounds& b : volume_bounds_) {
    if (!(b.lo.x <= b.hi.x)) continue;
    const glm::vec3 margin = 1e-5f * (glm::abs(b.lo) + glm::abs(b.hi)) + 1e-30f;  // hits on the surface count as inside
    b.lo -= margin;
    b.hi += margin;
  }
  const bool textured = (bits & kTextures) != 0, see_through = (bits & kAlpha) != 0;
  primary_kernel_ = textured ? (see_through ? &Shader::primary4_impl<true, true> : &Shader::primary4_impl<true, false>)
                             : (see_through ? &Shader::primary4_impl<false, true> : &Shader::primary4_impl<false, false>);
}

template <bool kTextured, bool kSeeThrough>
void Shader::primary4_impl(const RayPacket4& rays, PrimaryHit4& out, RayCounters& counters,
                           const CameraClip* clip) const {
  HitPacket4 packet_hits;
  bvh_.intersect4(rays, mask4(true), packet_hits);
  LaneHits hits(packet_hits);
  float skipped[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  if (clip) clip_near(scene_, bvh_, rays, 0xF, hits, skipped, *clip, counters);
  if constexpr (kSeeThrough) pass_cutouts(scene_, bvh_, rays, 0xF, hits, skipped, counters);
  if (clip) clip_far(scene_, 0xF, hits, *clip);
  for (int i = 0; i < 4; ++i) {
    if (hits.prim[i] < 0) {
      out.depth[i] = kInfinity;
      out.normal[i] = out.albedo[i] = glm::vec3(0.0f);
      continue;
    }
    SurfacePoint s;
    glm::vec3 ns = surface_geometry(scene_, rays.direction(i), hits, i, skipped[i], s);
    const uint32_t mat_index = scene_.material_of[size_t(hits.prim[i])];
    const Material& m = scene_.materials[mat_index];
    glm::vec3 base = m.base_color;
    if constexpr (kTextured) {
      const size_t t3 = size_t(hits.prim[i]) * 3;
      const Texcoords tc(scene_, t3, hits.u[i], hits.v[i]);
      if (m.base_color_texture.used()) base *= glm::vec3(tc.sample(scene_, m.base_color_texture));
      if (m.normal_texture.used() && !scene_.tangents.empty())
        ns = mapped_normal(scene_, m, t3, hits.u[i], hits.v[i], tc, ns);
    }
    out.depth[i] = s.distance;
    out.normal[i] = facing_shading_normal(s, ns);
    out.albedo[i] = base;
  }
}

template <unsigned... kE>
Shader::Kernel Shader::pick_kernel(unsigned effects, std::integer_sequence<unsigned, kE...>) {
  static constexpr Kernel kernels[] = {&Shader::trace4_impl<kE>...};
  return kernels[effects];
}

// One packet's hits as the shading stages pass them on: where each lane's ray hit, what
// it found there and the radiance gathered so far.
struct Shader::Hits4 {
  Hits4(const HitPacket4& packet, const Media& media) : hits(packet), crossed(media) {}
  LaneHits hits;
  float skipped[4] = {0.0f, 0.0f, 0.0f, 0.0f};  // distance travelled through cut-outs
  alignas(16) float out[3][4] = {};            // radiance, SoA
  SurfacePoint sp[4];
  bool shaded[4] = {false, false, false, false};  // hit a surface (not inactive, not the background)
  // The volume each lane's segment crossed: the one the ray was in, unless the hit shows
  // the ray left it through an open surface (outside its bounds, or on a front face of it).
  Media crossed;
};

template <unsigned kEffects>
Rgb4 Shader::trace4_impl(const RayPacket4& rays, mask4 active, int depth, int blend_layers, float4 throughput,
                         const Media& media, RayCounters& counters, PathSignature4* signature,
                         const CameraClip* clip) const {
  if (active.none()) return Rgb4{float4(0.0f), float4(0.0f), float4(0.0f)};

  HitPacket4 packet_hits;
  bvh_.intersect4(rays, active, packet_hits);
  Hits4 h(packet_hits, media);
  const int active_bits = active.bits();
  if (clip) clip_near(scene_, bvh_, rays, active_bits, h.hits, h.skipped, *clip, counters);
  // Alpha: a ray that hits a cut-out texel (MASK below the cutoff, BLEND alpha 0)
  // continues behind it.
  if constexpr ((kEffects & kAlpha) != 0) pass_cutouts(scene_, bvh_, rays, active_bits, h.hits, h.skipped, counters);
  if (clip) clip_far(scene_, active_bits, h.hits, *clip);

  shade_surfaces<kEffects>(rays, active_bits, media, signature, h);
  if constexpr ((kEffects & kShadows) != 0) add_direct_light<kEffects>(h, counters, signature);
  int refracted_lanes = 0;  // lanes whose refraction ray took the path tree's refraction node
  if constexpr ((kEffects & (kReflection | kRefraction)) != 0)
    if (depth < scene_.max_depth)  // depth = bounces taken so far
      refracted_lanes = add_reflection_and_refraction<kEffects>(h, depth, blend_layers, throughput, counters, signature);
  if constexpr ((kEffects & kRefraction) != 0)
    if (effects_.absorption) absorb_along_segment(h, signature);
  if constexpr ((kEffects & kAlpha) != 0)
    blend_over_behind<kEffects>(h, refracted_lanes, depth, blend_layers, throughput, counters, signature, clip);

  if (signature && signature->probes)
    for (int i = 0; i < 4; ++i)
      if (h.shaded[i]) signature->probes.at(signature->node, i).blocked = signature->blocked[i];

  Rgb4 result{float4::load(h.out[0]), float4::load(h.out[1]), float4::load(h.out[2])};
  // NaN (e.g. from a degenerate normal) never leaves the shader, nor does radiance above the
  // cap (+Inf included); both are counted, as the image cannot show them.
  const float4 cap(kRadianceMax);
  counters.nan_radiance += uint64_t(count_lanes((isnan(result.r) | isnan(result.g) | isnan(result.b)) & active));
  counters.capped_radiance += uint64_t(count_lanes(((result.r > cap) | (result.g > cap) | (result.b > cap)) & active));
  auto sanitize = [&](float4 x) {
    return select(isnan(x) | !active, float4(0.0f), min(max(x, float4(0.0f)), cap));
  };
  return {sanitize(result.r), sanitize(result.g), sanitize(result.b)};
}

// Each hit's surface: geometry, material, textures, emission; the background for misses.
template <unsigned kEffects>
void Shader::shade_surfaces(const RayPacket4& rays, int active_bits, const Media& media, PathSignature4* signature,
                            Hits4& h) const {
  constexpr bool kTextured = (kEffects & kTextures) != 0;
  constexpr bool kSeeThrough = (kEffects & kAlpha) != 0;
  for (int i = 0; i < 4; ++i) {
    if (!((active_bits >> i) & 1)) continue;
    const int prim = h.hits.prim[i];
    if (prim < 0) {
      h.out[0][i] = scene_.background.r;
      h.out[1][i] = scene_.background.g;
      h.out[2][i] = scene_.background.b;
      continue;
    }
    const float u = h.hits.u[i], v = h.hits.v[i];
    const size_t t3 = size_t(prim) * 3;
    SurfacePoint& s = h.sp[i];
    glm::vec3 ns = surface_geometry(scene_, rays.direction(i), h.hits, i, h.skipped[i], s);
    const uint32_t mat_index = scene_.material_of[prim];
    if (signature) signature->object[i] = mat_index + 1;
    glm::vec3 emission = scene_.whitted[mat_index].emission;
    glm::vec2 uv0(0.0f), uv1(0.0f);  // the hit's texture coordinates, for the probe
    if constexpr (kTextured) {
      const Material& gltf = scene_.materials[mat_index];
      const Texcoords tc(scene_, t3, u, v);
      uv0 = tc.uv0;
      uv1 = tc.uv1;
      s.material = &material_at<true>(scene_, mat_index, &tc, s.local, s.albedo);
      if (gltf.emissive_texture.used() && emission != glm::vec3(0.0f))
        emission *= glm::vec3(tc.sample(scene_, gltf.emissive_texture));
      if (gltf.normal_texture.used() && !scene_.tangents.empty())
        ns = mapped_normal(scene_, gltf, t3, u, v, tc, ns);
      if constexpr (kSeeThrough) s.alpha = coverage(scene_, gltf, tc);
    } else {
      s.material = &material_at<false>(scene_, mat_index, nullptr, s.local, s.albedo);
      if constexpr (kSeeThrough) s.alpha = coverage(scene_, scene_.materials[mat_index], Texcoords(scene_, t3, u, v));
    }
    if constexpr ((kEffects & kShadows) != 0) {
      // Once per hit, not per light: every shadow ray of this hit leaves from the same point.
      const glm::vec3 shadow_p = lift_to_smooth_surface(s.hit.p, &scene_.positions[t3], &scene_.normals[t3], u, v,
                                                        !s.front);
      s.lifted = shadow_p != s.hit.p;
      // The lifted point's rounding error is that of the hit plus a few ULPs of the lift.
      const glm::vec3 lift = shadow_p - s.hit.p;
      s.shadow_origin = offset_ray_origin(SurfacePosition{shadow_p, s.hit.error + glm::abs(lift) * 4e-7f}, s.ng);
    }
    s.ns = facing_shading_normal(s, ns);
    if (signature && signature->footprint && footprinted(signature->node))
      signature->footprint.at(signature->node, i) = FootprintProbe{glm::vec3(0.0f), prim, u, v, s.front ? 1.0f : -1.0f};
    if (signature && signature->probes)
      signature->probes.at(signature->node, i) = {s.hit.p, s.ns, s.wo, s.material->specular, s.material->shininess,
                                               0u, mat_index, uv0, uv1};
    h.out[0][i] = emission.r;
    h.out[1][i] = emission.g;
    h.out[2][i] = emission.b;
    h.shaded[i] = true;
    if (const int here = media.inside[i];
        here >= 0 && (!volume_bounds_[size_t(here)].contains(s.hit.p) || (s.front && here == int(mat_index))))
      h.crossed.inside[i] = h.crossed.outside[i] = -1;
  }
}

// Direct light: one shadow packet per light, lanes that face it. The lanes are shaded
// together (SoA float4), each with the scalar code's operations in its order.
template <unsigned kEffects>
void Shader::add_direct_light(Hits4& h, RayCounters& counters, PathSignature4* signature) const {
  constexpr bool kTextured = (kEffects & kTextures) != 0;
  constexpr bool kSeeThrough = (kEffects & kAlpha) != 0;
  if (scene_.lights.empty()) return;
  const LitLanes lit(h.sp, h.shaded);
  float4 out_r = float4::load(h.out[0]), out_g = float4::load(h.out[1]), out_b = float4::load(h.out[2]);
  // The footprint's light terms (a camera packet that asks for them only).
  const bool footprint = signature && signature->footprint && footprinted(signature->node);
  vec3x4 irradiance{float4(0.0f), float4(0.0f), float4(0.0f)};
  auto add_light = [&](mask4 reached, const vec3x4& e) {
    irradiance.x = select(reached, irradiance.x + e.x, irradiance.x);
    irradiance.y = select(reached, irradiance.y + e.y, irradiance.y);
    irradiance.z = select(reached, irradiance.z + e.z, irradiance.z);
  };
  for (size_t light_index = 0; light_index < scene_.lights.size(); ++light_index) {
    const Light& light = scene_.lights[light_index];
    const uint32_t light_bit = 1u << (light_index % 32);
    const LightConstants& constants = light_constants_[light_index];
    const LightSample4 ls = light_towards4(light, constants, lit.p);
    const vec3x4& wi = ls.to_light;
    const float4 cos_s = dot(lit.ns, wi);
    // Below the flat triangle's plane the light is blocked by the triangle itself,
    // unless the shadow ray starts lifted off it (the shadow terminator, above).
    const mask4 facing = lit.shaded & ls.lit &
                         !((cos_s <= float4(0.0f)) | andnot(lit.lifted, dot(lit.ng, wi) <= float4(0.0f)));
    if (facing.none()) continue;
    // Normalised Phong: (n+2)/(2 pi) cos^n(R, wo), energy-conserving lobe.
    const vec3x4 r = lit.ns * (float4(2.0f) * cos_s) - wi;
    const float4 cos_r = max(dot(r, lit.wo), float4(0.0f));
    const float4 lobe = phong_pow4(cos_r, lit.shininess, facing);
    const float4 phong = (lit.shininess + float4(2.0f)) * float4(0.5f) * float4(kInvPi) * lobe;
    const vec3x4 f = lit.albedo * float4(kInvPi) + lit.specular * phong;
    const vec3x4 contribution = (f * ls.scale) * cos_s;
    const mask4 lanes = facing & ((contribution.x > float4(0.0f)) | (contribution.y > float4(0.0f)) |
                                  (contribution.z > float4(0.0f)));
    // A black corner traces no shadow ray, but its neighbours in the texture may be lit:
    // the footprint takes the light as reaching it.
    if (footprint) add_light(andnot(lanes, facing), (ls.scale * cos_s) * float4(kInvPi));
    if (lanes.none()) continue;
    if (signature && signature->light_radiance)
      for (int i = 0; i < 4; ++i)
        if (lanes[i]) {
          glm::vec3& slot = signature->light_radiance[light_index % kLightSlots][i];
          slot = glm::max(slot, glm::vec3(contribution.x[i], contribution.y[i], contribution.z[i]));
        }
    // Unused lanes as PacketBuilder leaves them: zero origin, +z direction, tmax 0.
    RayPacket4 shadow;
    shadow.ox = select(lanes, lit.origin.x, float4(0.0f));
    shadow.oy = select(lanes, lit.origin.y, float4(0.0f));
    shadow.oz = select(lanes, lit.origin.z, float4(0.0f));
    vec3x4 dir;
    float4 tmax;
    if (light.type == Light::Type::Directional) {
      dir = wi;
      tmax = float4(kInfinity);
    } else {
      dir = constants.position - lit.origin;  // t in (0, 1) reaches the light
      tmax = float4(1.0f - kShadowEpsilon);
    }
    shadow.dx = select(lanes, dir.x, float4(0.0f));
    shadow.dy = select(lanes, dir.y, float4(0.0f));
    shadow.dz = select(lanes, dir.z, float4(1.0f));
    shadow.tmax = select(lanes, tmax, float4(0.0f));
    if constexpr ((kEffects & (kAlpha | kRefraction)) != 0) {
      PacketBuilder builder;
      shadow.ox.store(builder.o[0]), shadow.oy.store(builder.o[1]), shadow.oz.store(builder.o[2]);
      shadow.dx.store(builder.d[0]), shadow.dy.store(builder.d[1]), shadow.dz.store(builder.d[2]);
      shadow.tmax.store(builder.tmax);
      glm::vec3 through[4];
      shadow_transmittance<kTextured, kSeeThrough, (kEffects & kRefraction) != 0>(scene_, bvh_, light, builder,
                                                                                  lanes.bits(), through, counters);
      alignas(16) float t[3][4];
      for (int i = 0; i < 4; ++i) {
        t[0][i] = through[i].r, t[1][i] = through[i].g, t[2][i] = through[i].b;
        if (signature && lanes[i] && !(through[i].r >= 1.0f && through[i].g >= 1.0f && through[i].b >= 1.0f))
          signature->shadowed[i] |= light_bit;
        if (signature && lanes[i] && !(through[i].r > 0.0f || through[i].g > 0.0f || through[i].b > 0.0f))
          signature->blocked[i] |= light_bit;
      }
      out_r = select(lanes, out_r + contribution.x * float4::load(t[0]), out_r);
      out_g = select(lanes, out_g + contribution.y * float4::load(t[1]), out_g);
      out_b = select(lanes, out_b + contribution.z * float4::load(t[2]), out_b);
      if (footprint)
        add_light(lanes, ((ls.scale * cos_s) * float4(kInvPi)) *
                             vec3x4{float4::load(t[0]), float4::load(t[1]), float4::load(t[2])});
    } else {
      counters.shadow += uint64_t(count_lanes(lanes));
      const mask4 blocked = bvh_.occluded4(shadow, lanes);
      if (signature) {
        const int shadowed = (lanes & blocked).bits();
        for (int i = 0; i < 4; ++i)
          if ((shadowed >> i) & 1) signature->shadowed[i] |= light_bit, signature->blocked[i] |= light_bit;
      }
      const mask4 reached = andnot(blocked, lanes);
      out_r = select(reached, out_r + contribution.x, out_r);
      out_g = select(reached, out_g + contribution.y, out_g);
      out_b = select(reached, out_b + contribution.z, out_b);
      if (footprint) add_light(reached, (ls.scale * cos_s) * float4(kInvPi));
    }
  }
  out_r.store(h.out[0]), out_g.store(h.out[1]), out_b.store(h.out[2]);
  if (footprint)
    for (int i = 0; i < 4; ++i) {
      if (!h.shaded[i]) continue;
      FootprintProbe& f = signature->footprint.at(signature->node, i);
      f.irradiance = glm::vec3(irradiance.x[i], irradiance.y[i], irradiance.z[i]);
    }
}

// Mirror reflection and refraction, each as one secondary packet; returns the lanes whose
// refraction ray took the path tree's refraction node.
template <unsigned kEffects>
int Shader::add_reflection_and_refraction(Hits4& h, int depth, int blend_layers, float4 throughput,
                                          RayCounters& counters, PathSignature4* signature) const {
  int refracted_lanes = 0;
  PacketBuilder reflected, refracted;
  Media refracted_media = h.crossed;  // reflected rays stay in the media of their parent
  glm::vec3 reflect_weight[4], refract_weight[4];
  alignas(16) float path[4], reflect_path[4] = {}, refract_path[4] = {};
  throughput.store(path);
  auto largest = [](const glm::vec3& w) { return std::max(w.r, std::max(w.g, w.b)); };
  bool do_reflect[4] = {false, false, false, false}, do_refract[4] = {false, false, false, false};
  for (int i = 0; i < 4; ++i) {
    if (!h.shaded[i]) continue;
    const SurfacePoint& s = h.sp[i];
    const WhittedMaterial& m = *s.material;
    const float cos_i = std::clamp(glm::dot(s.ns, s.wo), 0.0f, 1.0f);
    glm::vec3 kr = m.mirror;
    bool transmit = false;
    float eta = 1.0f;
    if constexpr ((kEffects & kRefraction) != 0) {
      if (m.transmits()) {
        // n_incident / n_transmitted; a thin wall has air on both sides of its sheet. A
        // ray enters this volume from the one it is in, or leaves it for the one around.
        const int here = h.crossed.inside[i], self = int(scene_.material_of[size_t(h.hits.prim[i])]);
        if (m.thin_walled) {
          eta = 1.0f / m.ior;
        } else if (s.front) {
          // Entering `self` from the medium the ray is in (air after an open surface).
          eta = (here >= 0 ? scene_.whitted[size_t(here)].ior : 1.0f) / m.ior;
          refracted_media.inside[i] = self;
          refracted_media.outside[i] = here;
        } else {
          // Leaving `self`; a ray not known to be inside it (it started there, or the mesh
          // is open) stays in the medium it is in.
          const int next = here == self ? h.crossed.outside[i] : here;
          eta = m.ior / (next >= 0 ? scene_.whitted[size_t(next)].ior : 1.0f);
          refracted_media.inside[i] = next;
          refracted_media.outside[i] = here == self ? -1 : h.crossed.outside[i];
        }
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
        const float cos_t = std::max(0.0f, cos_transmitted(cos_i, eta));
        // Snell, vector form; a thin wall's two faces bend the ray back: it goes on.
        const glm::vec3 t = m.thin_walled ? -s.wo : -eta * s.wo + (eta * cos_i - cos_t) * s.ns;
        if (glm::dot(t, s.ng) < 0.0f) {
          refracted.set(i, offset_ray_origin(s.hit, -s.ng), t, kInfinity);
          do_refract[i] = true;
        }
      }
    }
  }
  const mask4 reflect_lanes(do_reflect[0], do_reflect[1], do_reflect[2], do_reflect[3]);
  // The secondary rays' first hits, for a camera packet's signature and probes.
  if (reflect_lanes.any()) {
    counters.reflection += uint64_t(count_lanes(reflect_lanes));
    std::optional<PathSignature4> seen_reflected = child_signature(signature, reflected_node, depth <= 1);
    const Rgb4 c = trace4_impl<kEffects>(reflected.packet(), reflect_lanes, depth + 1, blend_layers,
                                         float4::load(reflect_path), h.crossed, counters,
                                         seen_reflected ? &*seen_reflected : nullptr);
    if (seen_reflected) {
      const PathSignature4& seen = *seen_reflected;
      for (int i = 0; i < 4; ++i)
        signature->reflected[i] = !do_reflect[i] ? 0u
                                  : depth == 0   ? hit_then(seen.object[i], seen.reflected[i])
                                  : reflect_path[i] >= kSignedMirrorPath ? seen.object[i]
                                                                         : 0u;
    }
    add_weighted(h.out, do_reflect, reflect_weight, c);
  }
  if constexpr ((kEffects & kRefraction) != 0) {
    const mask4 refract_lanes(do_refract[0], do_refract[1], do_refract[2], do_refract[3]);
    if (refract_lanes.any()) {
      counters.refraction += uint64_t(count_lanes(refract_lanes));
      refracted_lanes = refract_lanes.bits();
      // A refracted ray's first hit is mostly the far side of the same glass; what the
      // glass shows is the hit after that, so a camera packet's signature keeps both.
      std::optional<PathSignature4> seen_refracted = child_signature(signature, refracted_node, depth <= 1);
      const Rgb4 c = trace4_impl<kEffects>(refracted.packet(), refract_lanes, depth + 1, blend_layers,
                                           float4::load(refract_path), refracted_media, counters,
                                           seen_refracted ? &*seen_refracted : nullptr);
      if (seen_refracted) {
        const PathSignature4& seen = *seen_refracted;
        for (int i = 0; i < 4; ++i)
          signature->refracted[i] =
              !do_refract[i] ? 0u : depth == 0 ? hit_then(seen.object[i], seen.refracted[i]) : seen.object[i];
      }
      add_weighted(h.out, do_refract, refract_weight, c);
    }
  }
  // The children's probes carry the weight of the ray that reached them.
  if (signature && (signature->probes || signature->footprint))
    for (int i = 0; i < 4; ++i) {
      if (do_reflect[i]) scale_path(*signature, reflected_node(signature->node), i, reflect_weight[i]);
      if (do_refract[i]) scale_path(*signature, refracted_node(signature->node), i, refract_weight[i]);
    }
  return refracted_lanes;
}

// Beer-Lambert over the segment to each hit, by the medium it crossed: the volume the ray
// is in, whatever it hits there (an object inside a tinted glass too); for a ray not known
// to be inside one that hits a surface from inside, the volume behind that surface.
void Shader::absorb_along_segment(Hits4& h, PathSignature4* signature) const {
  for (int i = 0; i < 4; ++i) {
    if (!h.shaded[i]) continue;
    const int medium = h.crossed.inside[i];
    if (medium < 0 && h.sp[i].front) continue;
    const glm::vec3 sigma = medium >= 0 ? scene_.whitted[size_t(medium)].absorption : h.sp[i].material->absorption;
    if (!(sigma.r > 0.0f || sigma.g > 0.0f || sigma.b > 0.0f)) continue;
    glm::vec3 kept;
    for (int c = 0; c < 3; ++c) {
      kept[c] = std::exp(-sigma[c] * h.sp[i].distance);
      h.out[c][i] *= kept[c];
    }
    if (signature && (signature->probes || signature->footprint))
      scale_path(*signature, signature->node, i, kept);  // highlights and footprints too
  }
}

// BLEND: each surface's colour over what a continuation ray sees behind it,
// out = alpha * surface + (1 - alpha) * behind (glTF's "over" with straight alpha).
template <unsigned kEffects>
void Shader::blend_over_behind(Hits4& h, int refracted_lanes, int depth, int blend_layers, float4 throughput,
                               RayCounters& counters, PathSignature4* signature, const CameraClip* clip) const {
  PacketBuilder behind;
  int blend = 0;
  for (int i = 0; i < 4; ++i) {
    if (!h.shaded[i] || !(h.sp[i].alpha < 1.0f)) continue;
    if (blend_layers >= kMaxBlendLayers) {
      for (int c = 0; c < 3; ++c) h.out[c][i] *= h.sp[i].alpha;
      ++counters.layer_limit;
      continue;
    }
    behind.set(i, offset_ray_origin(h.sp[i].hit, -h.sp[i].ng), h.sp[i].dir, kInfinity);
    blend |= 1 << i;
  }
  if (blend == 0) return;
  counters.continuation += uint64_t(std::popcount(unsigned(blend)));
  // What a camera packet sees through a BLEND surface takes the refraction's node of the
  // path tree where the surface does not refract, as glass's image does: the highlight
  // flag probes the highlights behind the pane and the footprint its textures, which
  // the pane's own surface does not show (1024² vase FLIP 1.489 -> 1.473x the lattice's).
  // A lane that refracts here too (a BLEND glass) keeps the node for its refraction and
  // traces what is behind unprobed, in a packet of its own: whether a lane is probed must
  // not depend on the other lanes of its packet.
  std::optional<PathSignature4> seen_behind = child_signature(signature, refracted_node, false);
  const int probed_lanes = seen_behind ? blend & ~refracted_lanes : 0;
  Rgb4 c{float4(0.0f), float4(0.0f), float4(0.0f)};  // recursion bounded by kMaxBlendLayers
  if (probed_lanes != 0)
    c = trace4_impl<kEffects>(behind.packet(), mask4::from_bits(probed_lanes), depth, blend_layers + 1, throughput,
                              h.crossed, counters, &*seen_behind, clip);
  if (const int unprobed = blend & ~probed_lanes; unprobed != 0) {
    const Rgb4 u = trace4_impl<kEffects>(behind.packet(), mask4::from_bits(unprobed), depth, blend_layers + 1,
                                         throughput, h.crossed, counters, nullptr, clip);
    c = select(mask4::from_bits(unprobed), u, c);
  }
  for (int i = 0; i < 4; ++i) {
    if (!((blend >> i) & 1)) continue;
    const float a = h.sp[i].alpha;
    if ((probed_lanes >> i) & 1) scale_path(*signature, seen_behind->node, i, glm::vec3(1.0f - a));  // what the pane passes
    h.out[0][i] = a * h.out[0][i] + (1.0f - a) * c.r[i];
    h.out[1][i] = a * h.out[1][i] + (1.0f - a) * c.g[i];
    h.out[2][i] = a * h.out[2][i] + (1.0f - a) * c.b[i];
  }
}

}  // namespace zz
