#include "render/texture_detail.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "aa/lattice.h"

#include "render/lighting.h"
#include "render/lighting4.h"
#include "render/normal_map.h"
#include "render/surface_material.h"
#include "scene/materials.h"
#include "scene/scene.h"

namespace zz {

TexturePyramid::TexturePyramid(const Texture& base) {
  if (base.width <= 0 || base.height <= 0 || base.texel_count() < size_t(base.width) * size_t(base.height)) return;
  levels.emplace_back();  // level 0 is `base`
  int w = base.width, h = base.height;
  std::vector<float> parent_count;  // base texels under each texel of the level above (none: 1 each)
  while (w > 1 || h > 1) {
    const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    const Texture* parent = levels.size() == 1 ? &base : &levels.back();
    Texture level;
    level.width = nw;
    level.height = nh;
    level.wrap_s = base.wrap_s;
    level.wrap_t = base.wrap_t;
    level.filter = TextureFilter::Linear;
    // The mean of the base texels under each texel: the 2x2 block of the level above, an
    // odd last row or column joining the block beside it (2x3, 3x2 or 3x3), each weighed
    // by the base texels it holds, so every texel counts once at every level.
    level.texels.assign(size_t(nw) * size_t(nh), glm::vec4(0.0f));
    std::vector<float> count(size_t(nw) * size_t(nh), 0.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t from = size_t(y) * size_t(w) + size_t(x);
        const size_t i = size_t(std::min(y / 2, nh - 1)) * size_t(nw) + size_t(std::min(x / 2, nw - 1));
        const float n = parent_count.empty() ? 1.0f : parent_count[from];
        level.texels[i] += n * parent->texel(from);
        count[i] += n;
      }
    for (size_t i = 0; i < level.texels.size(); ++i) level.texels[i] /= count[i];
    parent_count = std::move(count);
    levels.push_back(std::move(level));
    w = nw;
    h = nh;
  }
}

glm::vec3 TexturePyramid::box_mean(const Texture& base, glm::vec2 lo, glm::vec2 hi) const {
  const glm::vec2 centre = 0.5f * (lo + hi);
  const float texels = std::max((hi.x - lo.x) * float(base.width), (hi.y - lo.y) * float(base.height));
  const float level = std::clamp(std::log2(std::max(texels, 1.0f)), 0.0f, float(levels.size()) - 1.0f);
  const int l0 = int(level), l1 = std::min(l0 + 1, int(levels.size()) - 1);
  auto at = [&](int l) { return glm::vec3(l == 0 ? base.sample(centre) : levels[size_t(l)].sample(centre)); };
  const float t = level - float(l0);
  return t > 0.0f ? (1.0f - t) * at(l0) + t * at(l1) : at(l0);
}

namespace {

// The textures that colour light directly (base colour, emissive): those with a pyramid.
std::vector<bool> pyramid_textures(const Scene& scene) {
  std::vector<bool> wanted(scene.textures.size(), false);
  for (const Material& m : scene.materials)
    for (const TextureRef* ref : {&m.base_color_texture, &m.emissive_texture})
      if (ref->used() && size_t(ref->index) < wanted.size()) wanted[size_t(ref->index)] = true;
  return wanted;
}

}  // namespace

uint64_t texture_pyramid_bytes(const Scene& scene) {
  const std::vector<bool> wanted = pyramid_textures(scene);
  uint64_t bytes = 0, largest_level = 0;
  for (size_t i = 0; i < wanted.size(); ++i) {
    if (!wanted[i]) continue;
    uint64_t w = uint64_t(std::max(scene.textures[i].width, 0)), h = uint64_t(std::max(scene.textures[i].height, 0));
    while (w > 1 || h > 1) {
      w = std::max<uint64_t>(1, w / 2), h = std::max<uint64_t>(1, h / 2);
      bytes += w * h * sizeof(glm::vec4);
      largest_level = std::max(largest_level, w * h);
    }
  }
  return bytes + 2 * largest_level * sizeof(float);  // the counts of one level and of the one above
}

std::vector<TexturePyramid> texture_pyramids(const Scene& scene) {
  const std::vector<bool> wanted = pyramid_textures(scene);
  std::vector<TexturePyramid> pyramids(scene.textures.size());
  for (size_t i = 0; i < pyramids.size(); ++i)
    if (wanted[i]) pyramids[i] = TexturePyramid(scene.textures[i]);
  return pyramids;
}

namespace {

struct Footprint {
  glm::vec3 corners{0.0f};  // the mean of the four corners' samples
  glm::vec3 box{0.0f};      // the texture's mean over their box
  bool ok = false;
};

Footprint footprint(const Scene& scene, const std::vector<TexturePyramid>& pyramids, const TextureRef& ref,
                    const SurfaceProbe c[4]) {
  Footprint f;
  const size_t index = size_t(ref.index);
  if (index >= pyramids.size() || pyramids[index].levels.empty()) return f;
  const Texture& texture = scene.textures[index];
  glm::vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (int k = 0; k < 4; ++k) {
    const glm::vec2 st = ref.at(c[k].uv0, c[k].uv1);
    f.corners += 0.25f * glm::vec3(texture.sample(st));
    lo = glm::min(lo, st);
    hi = glm::max(hi, st);
  }
  // Half the texture or more between neighbouring corners is a seam or a tiling jump.
  if (!(hi.x - lo.x < 0.5f && hi.y - lo.y < 0.5f)) return f;
  f.box = pyramids[index].box_mean(texture, lo, hi);
  f.ok = true;
  return f;
}

}  // namespace

glm::vec3 hidden_texture_detail(const Scene& scene, const std::vector<TexturePyramid>& pyramids,
                                const SurfaceProbe c[4], glm::vec3 corner_mean) {
  const uint32_t m = c[0].material;
  if (m >= scene.materials.size()) return glm::vec3(0.0f);
  for (int k = 1; k < 4; ++k)
    if (c[k].material != m) return glm::vec3(0.0f);
  const Material& material = scene.materials[m];
  glm::vec3 hidden(0.0f);
  const glm::vec3 emission = scene.whitted[m].emission;
  if (material.emissive_texture.used() && emission != glm::vec3(0.0f)) {
    const Footprint f = footprint(scene, pyramids, material.emissive_texture, c);
    if (f.ok) hidden += emission * glm::abs(f.box - f.corners);
  }
  if (material.base_color_texture.used()) {
    const Footprint f = footprint(scene, pyramids, material.base_color_texture, c);
    if (f.ok) {
      // Lit as its corners are: radiance per unit albedo times the albedo it misses.
      const glm::vec3 albedo = material.base_color * f.corners;
      const glm::vec3 per_albedo = corner_mean / glm::max(albedo, glm::vec3(0.02f));
      hidden += per_albedo * material.base_color * glm::abs(f.box - f.corners);
    }
  }
  return hidden;
}

namespace {

// The diffuse albedo the shader gives material `m` at these texture coordinates.
glm::vec3 diffuse_albedo(const Scene& scene, uint32_t m, const Texcoords& tc) {
  WhittedMaterial local;
  glm::vec3 albedo;
  textured_material(scene, m, tc, local, albedo);
  return albedo;
}

bool valid_ref(const Scene& scene, const TextureRef& ref) {
  return ref.used() && size_t(ref.index) < scene.textures.size();
}

// What the material asks of the footprint correction.
struct FootprintUse {
  bool bump_map = false;  // a normal map with the tangents and normals it needs
  bool diffuse = false;   // a texture varies the diffuse albedo or the normal
  bool emissive = false;  // an emissive texture with a non-zero factor
};

FootprintUse footprint_use(const Scene& scene, uint32_t m) {
  const Material& material = scene.materials[m];
  FootprintUse use;
  use.bump_map = valid_ref(scene, material.normal_texture) && !scene.tangents.empty() && !scene.normals.empty();
  use.diffuse = valid_ref(scene, material.base_color_texture) ||
                valid_ref(scene, material.metallic_roughness_texture) ||
                valid_ref(scene, material.transmission_texture) || use.bump_map;
  use.emissive = valid_ref(scene, material.emissive_texture) && scene.whitted[m].emission != glm::vec3(0.0f);
  return use;
}

// Direct light at a point lit light by light (Lambert and the Phong highlight, as the
// shader lights a hit).
glm::vec3 direct_light(int lights, glm::vec3 albedo, glm::vec3 specular, float shininess, glm::vec3 n, glm::vec3 wo,
                       const glm::vec3* light_strength, const glm::vec3* light_direction) {
  glm::vec3 sum(0.0f);
  for (int l = 0; l < lights; ++l) {
    const float cos_s = glm::dot(n, light_direction[l]);
    if (!(cos_s > 0.0f)) continue;
    const glm::vec3 r = 2.0f * cos_s * n - light_direction[l];
    const float cos_r = std::max(glm::dot(r, wo), 0.0f);
    const float lobe = shininess == 1.0f ? cos_r : std::pow(cos_r, shininess);
    const float phong = (shininess + 2.0f) * 0.5f * lobe;  // pi x normalised Phong
    sum += light_strength[l] * cos_s * (albedo + specular * phong);
  }
  return sum;
}

// The normal map's frame at barycentrics (u, v) of the triangle at t3, as the shader builds
// it, on the side a ray hit (`side` +1 where the winding's normal faces the ray, -1 else).
// False where there is none.
bool facing_frame(const Scene& scene, size_t t3, float u, float v, float side, glm::vec3 frame[3]) {
  const glm::vec3 &p0 = scene.positions[t3], &p1 = scene.positions[t3 + 1], &p2 = scene.positions[t3 + 2];
  const glm::vec3 ng = triangle_normal(p0, p1, p2);
  if (!normal_map_frame(scene, t3, u, v, interpolated_normal(scene, t3, u, v, ng), frame)) return false;
  for (int axis = 0; axis < 3; ++axis) frame[axis] *= side;
  return true;
}

// The footprint's first estimate's 2 x 2 points (s, t): TL corner at (0, 0), BR at (1, 1).
constexpr std::array<LatticePoint, 4> kFootprintCoarse = {
    LatticePoint{0.25f, 0.25f}, LatticePoint{0.75f, 0.25f}, LatticePoint{0.25f, 0.75f}, LatticePoint{0.75f, 0.75f}};


// The bilinear weights of the corners (TL, TR, BL, BR) at four points (s, t) of the pixel.
struct Bilerp4 {
  float4 w[4];
  Bilerp4(float4 s, float4 t) {
    const float4 one(1.0f);
    w[0] = (one - t) * (one - s);
    w[1] = (one - t) * s;
    w[2] = t * (one - s);
    w[3] = t * s;
  }
  float4 at(float a, float b, float c, float d) const { return w[0] * a + w[1] * b + w[2] * c + w[3] * d; }
  vec3x4 at(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) const {
    return {at(a.x, b.x, c.x, d.x), at(a.y, b.y, c.y, d.y), at(a.z, b.z, c.z, d.z)};
  }
  glm::vec3 lane3(int i, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) const {
    return w[0][i] * a + w[1][i] * b + w[2][i] * c + w[3][i] * d;
  }
};

// What four samples of the pixel hit where their camera rays meet one of the corners'
// triangles: that triangle's texture coordinates and shading frame at the hit, exact where
// the corners' bilinear interpolation is not (a pixel over two or more triangles of a
// curved, smooth-shaded mesh, whose normals and texture coordinates are linear per
// triangle, not over the pixel). Lanes bit i: lane i has its own.
struct SampleSurface4 {
  int lanes = 0;
  Texcoords tc[4];
  glm::vec3 frame[3][4];  // with a normal map: tangent, bitangent, normal (the shader's)
};

// The corners' distinct triangles, each as the ray test needs it; none without `f` (no
// camera to cast the samples' rays from).
class CornerTriangles {
 public:
  CornerTriangles(const Scene& scene, const FootprintProbe* const* f, bool frames) : scene_(scene), frames_(frames) {
    for (int i = 0; f && i < 4; ++i) {
      const int32_t prim = f[i]->prim;
      if (prim < 0 || size_t(prim) * 3 + 2 >= scene.positions.size()) continue;
      bool seen = false;
      for (int j = 0; j < count_; ++j) seen |= prim_[j] == prim;
      if (seen) continue;
      const size_t t3 = size_t(prim) * 3;
      prim_[count_] = prim;
      p0_[count_] = scene.positions[t3];
      e1_[count_] = scene.positions[t3 + 1] - scene.positions[t3];
      e2_[count_] = scene.positions[t3 + 2] - scene.positions[t3];
      ++count_;
    }
  }
  int count() const { return count_; }

  // Lane i's ray: from `origin` (a pinhole's, or lane i's on an orthographic camera's
  // plane) along d[i]. A lane that meets none of the triangles keeps the interpolation.
  template <class Origin>
  SampleSurface4 hit4(const Origin& origin, const glm::vec3 d[4]) const {
    constexpr bool kPinhole = std::is_same_v<Origin, glm::vec3>;
    SampleSurface4 out;
    alignas(16) float x[4], y[4], z[4];
    for (int lane = 0; lane < 4; ++lane) x[lane] = d[lane].x, y[lane] = d[lane].y, z[lane] = d[lane].z;
    const vec3x4 dir{float4::load(x), float4::load(y), float4::load(z)};
    float4 best(std::numeric_limits<float>::infinity()), best_u(0.0f), best_v(0.0f);
    int4 best_j(-1);
    for (int j = 0; j < count_; ++j) {
      // Moller & Trumbore 1997, the four rays in lanes (the same operations as glm's, in the
      // same order), with a little slack at the edges: a sample on the triangles' shared edge
      // may fall in either. s and q do not depend on the ray.
      const vec3x4 p = cross(dir, broadcast(e2_[j]));
      const float4 det = dot(broadcast(e1_[j]), p);
      const float4 inv = float4(1.0f) / det;
      float4 u, v, t;
      if constexpr (kPinhole) {
        const glm::vec3 s = origin - p0_[j];
        u = dot(broadcast(s), p) * inv;
        const glm::vec3 q = glm::cross(s, e1_[j]);
        v = dot(dir, broadcast(q)) * inv;
        t = float4(glm::dot(e2_[j], q)) * inv;
      } else {
        const vec3x4 s = origin - broadcast(p0_[j]);
        u = dot(s, p) * inv;
        const vec3x4 q = cross(s, broadcast(e1_[j]));
        v = dot(dir, q) * inv;
        t = dot(broadcast(e2_[j]), q) * inv;
      }
      constexpr float kSlack = 1e-4f;
      const mask4 take = (abs(det) > float4(0.0f)) & (u >= float4(-kSlack)) & (v >= float4(-kSlack)) &
                         (u + v <= float4(1.0f + kSlack)) & (t > float4(0.0f)) & (t < best);
      best = select(take, t, best);
      best_u = select(take, u, best_u);
      best_v = select(take, v, best_v);
      best_j = select(take, int4(j), best_j);
    }
    alignas(16) float us[4], vs[4];
    alignas(16) int32_t js[4];
    best_u.store(us);
    best_v.store(vs);
    best_j.store(js);
    for (int lane = 0; lane < 4; ++lane) {
      const int which = js[lane];
      const float bu = us[lane], bv = vs[lane];
      if (which < 0) continue;
      const size_t t3 = size_t(prim_[which]) * 3;
      const float u = std::clamp(bu, 0.0f, 1.0f), v = std::clamp(bv, 0.0f, 1.0f - u);
      out.tc[lane] = Texcoords(scene_, t3, u, v);
      if (frames_) {
        const float side = glm::dot(glm::cross(e1_[which], e2_[which]), d[lane]) < 0.0f ? 1.0f : -1.0f;
        glm::vec3 frame[3];
        if (!facing_frame(scene_, t3, u, v, side, frame)) continue;
        for (int axis = 0; axis < 3; ++axis) out.frame[axis][lane] = frame[axis];
      }
      out.lanes |= 1 << lane;
    }
    return out;
  }

 private:
  const Scene& scene_;
  bool frames_ = false;
  int count_ = 0;
  int32_t prim_[4] = {};
  glm::vec3 p0_[4], e1_[4], e2_[4];
};

// A texture the footprint's samples read, with its coordinates at the four corners: a
// sample's are theirs interpolated (affine in the corners' uv, so the texture transform
// commutes with the interpolation).
struct CornerTexture {
  const Texture* texture = nullptr;
  const TextureRef* ref = nullptr;
  glm::vec2 st[4];
  CornerTexture() = default;
  CornerTexture(const Scene& scene, const TextureRef& r, const SurfaceProbe c[4]) {
    if (!valid_ref(scene, r)) return;
    texture = &scene.textures[size_t(r.index)];
    ref = &r;
    for (int i = 0; i < 4; ++i) st[i] = r.at(c[i].uv0, c[i].uv1);
  }
  // At the interpolated coordinates, except in the lanes `exact` has its own for.
  void sample4(const Bilerp4& w, const SampleSurface4& exact, float4 rgba[4]) const {
    alignas(16) float s[4], t[4];
    w.at(st[0].x, st[1].x, st[2].x, st[3].x).store(s);
    w.at(st[0].y, st[1].y, st[2].y, st[3].y).store(t);
    for (int lane = 0; lane < 4; ++lane)
      if ((exact.lanes >> lane) & 1) {
        const glm::vec2 at = ref->at(exact.tc[lane].uv0, exact.tc[lane].uv1);
        s[lane] = at.x;
        t[lane] = at.y;
      }
    texture->sample4(float4::load(s), float4::load(t), rgba);
  }
};

// std::clamp(v, 0, 1) lane by lane, as whitted_surface clamps: NaN stays NaN and -0 stays
// -0, where lighting4.h's clamp01 (min and max) gives 0 and +0.
float4 std_clamp01(float4 v) {
  const float4 zero(0.0f), one(1.0f);
  return select(v < zero, zero, select(one < v, one, v));
}

// The diffuse albedo that textured_material gives a metallic- or transmission-textured
// material (whitted_surface's base x (1 - metallic) x (1 - transmission)) at four points of
// the pixel, with the same float operations in the same order: the same floats, lane by lane.
vec3x4 pbr_albedo4(const Material& material, const CornerTexture& base_map, const CornerTexture& metallic_map,
                   const CornerTexture& transmission_map, const Bilerp4& w, const SampleSurface4& own) {
  vec3x4 base = broadcast(material.base_color);
  float4 rgba[4];
  if (base_map.texture) {
    base_map.sample4(w, own, rgba);
    base = base * vec3x4{rgba[0], rgba[1], rgba[2]};
  }
  float4 metallic(material.metallic), transmission(material.transmission);
  if (metallic_map.texture) {  // glTF: B = metallic
    metallic_map.sample4(w, own, rgba);
    metallic = metallic * rgba[2];
  }
  if (transmission_map.texture) {
    transmission_map.sample4(w, own, rgba);
    transmission = transmission * rgba[0];
  }
  const float4 one(1.0f);
  metallic = std_clamp01(metallic);
  transmission = std_clamp01(transmission) * (one - metallic);
  const vec3x4 clamped{std_clamp01(base.x), std_clamp01(base.y), std_clamp01(base.z)};
  return clamped * (one - metallic) * (one - transmission);
}

// One lane's vector from `bilinear`, except in the lanes `exact` has its own for.
vec3x4 patch_lanes(const vec3x4& bilinear, const SampleSurface4& exact, const glm::vec3 (&own)[4]) {
  if (exact.lanes == 0) return bilinear;
  alignas(16) float x[4], y[4], z[4];
  bilinear.x.store(x), bilinear.y.store(y), bilinear.z.store(z);
  for (int lane = 0; lane < 4; ++lane)
    if ((exact.lanes >> lane) & 1) x[lane] = own[lane].x, y[lane] = own[lane].y, z[lane] = own[lane].z;
  return {float4::load(x), float4::load(y), float4::load(z)};
}

}  // namespace

FootprintCorner footprint_corner(const Scene& scene, const SurfaceProbe& c, const FootprintProbe& f) {
  FootprintCorner k;
  const uint32_t m = c.material;
  if (m >= scene.materials.size() || f.prim < 0 || size_t(f.prim) * 3 >= scene.positions.size()) return k;
  const FootprintUse use = footprint_use(scene, m);
  if (!use.diffuse && !use.emissive) return k;
  k.valid = true;
  const Material& material = scene.materials[m];
  // With the normal map and few lights, the corner's lights are recomputed from its hit
  // and shadow bits; they must add up to the irradiance the shader found (no partial
  // shadow, no light lost below the flat triangle).
  const int lights = int(scene.lights.size());
  bool per_light = use.bump_map && lights <= kFootprintLights;
  if (per_light) {
    per_light = facing_frame(scene, size_t(f.prim) * 3, f.u, f.v, f.side, k.frame);
    if (per_light) {
      // The shader's normal at the corner: the map's, unless it faced away (then ng).
      const glm::vec3 rgb(Texcoords(c.uv0, c.uv1).sample(scene, material.normal_texture));
      per_light = glm::length(mapped_in_frame(k.frame, rgb, material.normal_scale, k.frame[2]) - c.normal) < 1e-4f;
    }
    glm::vec3 irradiance(0.0f);
    for (int l = 0; l < lights && per_light; ++l) {
      float tmax;
      glm::vec3 scale;
      k.strength[l] = glm::vec3(0.0f);
      k.to_light[l] = glm::vec3(0.0f);
      if (!light_towards(scene.lights[size_t(l)], c.position, k.to_light[l], tmax, scale)) continue;
      const float cos_s = glm::dot(c.normal, k.to_light[l]);
      if (!(cos_s > 0.0f) || ((c.blocked >> (l % 32)) & 1u)) continue;
      k.strength[l] = scale * 0.318309886f;  // 1 / pi, as the shader
      irradiance += k.strength[l] * cos_s;
    }
    const glm::vec3 miss = glm::abs(irradiance - f.irradiance);
    per_light = per_light && glm::all(glm::lessThanEqual(miss, 0.02f * f.irradiance + 1e-6f));
  }
  k.per_light = per_light;
  if (use.diffuse) {
    const glm::vec3 albedo = diffuse_albedo(scene, m, Texcoords(c.uv0, c.uv1));
    k.albedo_lit = albedo * f.irradiance;
    if (per_light)
      k.lit = direct_light(lights, albedo, c.specular, c.shininess, c.normal, c.view, k.strength, k.to_light);
  }
  if (use.emissive) k.emissive_texel = glm::vec3(Texcoords(c.uv0, c.uv1).sample(scene, material.emissive_texture));
  return k;
}

FootprintDelta texture_footprint_delta(const Scene& scene, const SurfaceProbe c[4], const FootprintProbe* const f[4],
                                       glm::vec3 settled, const FootprintView* view) {
  const FootprintCorner k[4] = {footprint_corner(scene, c[0], *f[0]), footprint_corner(scene, c[1], *f[1]),
                                footprint_corner(scene, c[2], *f[2]), footprint_corner(scene, c[3], *f[3])};
  const FootprintCorner* const corners[4] = {&k[0], &k[1], &k[2], &k[3]};
  return texture_footprint_delta(scene, c, f, corners, settled, view);
}

FootprintDelta texture_footprint_delta(const Scene& scene, const SurfaceProbe c[4], const FootprintProbe* const f[4],
                                       const FootprintCorner* const k[4], glm::vec3 settled,
                                       const FootprintView* view) {
  const uint32_t m = c[0].material;
  if (m >= scene.materials.size()) return {};
  for (int i = 0; i < 4; ++i)
    if (c[i].material != m || !k[i]->valid) return {};
  const Material& material = scene.materials[m];
  const FootprintUse use = footprint_use(scene, m);
  const bool diffuse = use.diffuse, emissive = use.emissive;
  const glm::vec3 emission = scene.whitted[m].emission;
  // The corners' texture coordinates must span the pixel as one smooth patch does: close
  // to a parallelogram, and over few texels (a UV seam or an atlas jump between corners
  // fails one or the other; so does a texture minified beyond what the samples resolve).
  for (const TextureRef* ref : material.texture_slots()) {
    if (!valid_ref(scene, *ref)) continue;
    glm::vec2 st[4];
    for (int i = 0; i < 4; ++i) st[i] = ref->at(c[i].uv0, c[i].uv1);
    const Texture& texture = scene.textures[size_t(ref->index)];
    const glm::vec2 size(float(texture.width), float(texture.height));
    const glm::vec2 e1 = (st[1] - st[0]) * size, e2 = (st[2] - st[0]) * size;
    const glm::vec2 twist = (st[0] + st[3] - st[1] - st[2]) * size;
    const float edge = std::max(glm::length(e1), glm::length(e2));
    if (!(edge <= kFootprintMaxTexels && glm::length(twist) <= 0.5f * edge + 1e-3f)) return {};
  }

  // With the normal map and few lights, each sample is lit light by light at its own normal,
  // the lights' directions and strengths and the map's frame interpolated between the
  // corners' (footprint_corner); otherwise only the albedo varies.
  const int lights = int(scene.lights.size());
  const bool per_light = k[0]->per_light && k[1]->per_light && k[2]->per_light && k[3]->per_light;
  glm::vec3 light(0.0f), at_corners(0.0f);
  for (int i = 0; i < 4; ++i) {
    light += 0.25f * f[i]->irradiance;
    if (diffuse) at_corners += 0.25f * (per_light ? k[i]->lit : k[i]->albedo_lit);
    if (emissive) at_corners += 0.25f * emission * k[i]->emissive_texel;
  }
  const bool lit = diffuse && light != glm::vec3(0.0f);
  const WhittedMaterial& whitted = scene.whitted[m];
  const bool plain_albedo = !material.varies_per_hit();  // albedo = diffuse x base texture
  const vec3x4 zero = broadcast(glm::vec3(0.0f));
  const CornerTexture emissive_map(scene, material.emissive_texture, c), base_map(scene, material.base_color_texture, c);
  const CornerTexture metallic_map = plain_albedo ? CornerTexture() : CornerTexture(scene, material.metallic_roughness_texture, c);
  const CornerTexture transmission_map = plain_albedo ? CornerTexture() : CornerTexture(scene, material.transmission_texture, c);
  const CornerTexture normal_map = per_light ? CornerTexture(scene, material.normal_texture, c) : CornerTexture();
  // With the camera, each sample's own triangle among the corners' (SampleSurface4). The
  // rays' directions on the image plane are affine in (s, t), so the corners' directions
  // scaled to unit depth interpolate to them exactly.
  const CornerTriangles triangles(scene, view ? f : nullptr, per_light);
  const bool exact = view && triangles.count() > 1;
  // An orthographic view's rays are parallel: their origins on its plane interpolate.
  glm::vec3 image[4];
  if (exact)
    for (int i = 0; i < 4; ++i) {
      const glm::vec3 d = c[i].position - view->origin;
      image[i] = view->orthographic ? d - glm::dot(d, view->forward) * view->forward : d / glm::dot(d, view->forward);
    }

  // The model's radiance at four points (s, t) of the pixel at once (corner TL at 0, 0; BR
  // at 1, 1), every quantity interpolated between the corners with the same four weights.
  auto model4 = [&](float4 s, float4 t) {
    const Bilerp4 w(s, t);
    SampleSurface4 own;
    if (exact) {
      glm::vec3 d[4];
      for (int lane = 0; lane < 4; ++lane) d[lane] = w.lane3(lane, image[0], image[1], image[2], image[3]);
      if (view->orthographic) {
        alignas(16) float x[4], y[4], z[4];
        for (int lane = 0; lane < 4; ++lane) {
          const glm::vec3 o = view->origin + d[lane];
          x[lane] = o.x, y[lane] = o.y, z[lane] = o.z;
          d[lane] = view->forward;
        }
        own = triangles.hit4(vec3x4{float4::load(x), float4::load(y), float4::load(z)}, d);
      } else {
        own = triangles.hit4(view->origin, d);
      }
    }
    vec3x4 sum = zero;
    if (emissive) {
      float4 rgba[4];
      emissive_map.sample4(w, own, rgba);
      sum = vec3x4{rgba[0], rgba[1], rgba[2]} * broadcast(emission);
    }
    if (!lit) return sum;
    vec3x4 albedo;
    if (plain_albedo) {
      albedo = broadcast(whitted.diffuse);
      if (base_map.texture) {
        float4 rgba[4];
        base_map.sample4(w, own, rgba);
        albedo = albedo * vec3x4{rgba[0], rgba[1], rgba[2]};
      }
    } else {  // metallic or transmission textured: whitted_surface's diffuse term, four lanes at once
      albedo = pbr_albedo4(material, base_map, metallic_map, transmission_map, w, own);
    }
    if (!per_light) return sum + albedo * broadcast(light);
    // The normal map at the samples, in the corners' frames interpolated (mapped_in_frame).
    float4 rgb[4];
    normal_map.sample4(w, own, rgb);
    const float4 scale(material.normal_scale);
    auto axis = [&](int a) {
      return patch_lanes(w.at(k[0]->frame[a], k[1]->frame[a], k[2]->frame[a], k[3]->frame[a]), own, own.frame[a]);
    };
    const vec3x4 mapped = axis(0) * ((rgb[0] * 2.0f - 1.0f) * scale) + axis(1) * ((rgb[1] * 2.0f - 1.0f) * scale) +
                          axis(2) * (rgb[2] * 2.0f - 1.0f);
    const float4 mapped_len = sqrt(dot(mapped, mapped));
    const vec3x4 normal = select((mapped_len > float4(1e-12f)) & isfinite(mapped_len),
                                 mapped * rcp_exact(mapped_len), broadcast(c[0].normal));
    const vec3x4 view = w.at(c[0].view, c[1].view, c[2].view, c[3].view);
    const vec3x4 wo = view * rcp_exact(sqrt(dot(view, view)));
    const vec3x4 specular = w.at(c[0].specular, c[1].specular, c[2].specular, c[3].specular);
    const float4 shininess = w.at(c[0].shininess, c[1].shininess, c[2].shininess, c[3].shininess);
    const bool phong_linear = (shininess != float4(1.0f)).none();
    for (int l = 0; l < lights; ++l) {
      const vec3x4 to = w.at(k[0]->to_light[l], k[1]->to_light[l], k[2]->to_light[l], k[3]->to_light[l]);
      const float4 to_len = sqrt(dot(to, to));
      const vec3x4 direction = select(to_len > float4(1e-12f), to * rcp_exact(to_len), zero);
      // direct_light's Lambert and Phong terms.
      const float4 cos_s = dot(normal, direction);
      const vec3x4 r = normal * (float4(2.0f) * cos_s) - direction;
      const float4 cos_r = max(dot(r, wo), float4(0.0f));
      float4 lobe = cos_r;
      if (!phong_linear) {
        alignas(16) float x[4], e[4];
        cos_r.store(x);
        shininess.store(e);
        for (int lane = 0; lane < 4; ++lane) x[lane] = e[lane] == 1.0f ? x[lane] : std::pow(x[lane], e[lane]);
        lobe = float4::load(x);
      }
      const float4 phong = (shininess + 2.0f) * float4(0.5f) * lobe;
      const vec3x4 strength = w.at(k[0]->strength[l], k[1]->strength[l], k[2]->strength[l], k[3]->strength[l]);
      const vec3x4 term = strength * cos_s * (albedo + specular * phong);
      sum = sum + select(cos_s > float4(0.0f), term, zero);
    }
    return sum;
  };
  // The model's mean over `count` points of the pixel (a multiple of four), four at a time;
  // `spread`: per channel, the largest difference between two of them.
  auto model_mean = [&](const LatticePoint* points, int count, glm::vec3& spread) {
    vec3x4 sum = zero;
    const glm::vec3 inf(std::numeric_limits<float>::infinity());
    vec3x4 lo = broadcast(inf), hi = broadcast(-inf);
    for (int first = 0; first < count; first += 4) {
      alignas(16) float ss[4], ts[4];
      for (int lane = 0; lane < 4; ++lane) {
        ss[lane] = points[first + lane].u;
        ts[lane] = points[first + lane].v;
      }
      const vec3x4 v = model4(float4::load(ss), float4::load(ts));
      sum = sum + v;
      lo = {min(lo.x, v.x), min(lo.y, v.y), min(lo.z, v.z)};
      hi = {max(hi.x, v.x), max(hi.y, v.y), max(hi.z, v.z)};
    }
    spread = glm::vec3(hmax(hi.x) - hmin(lo.x), hmax(hi.y) - hmin(lo.y), hmax(hi.z) - hmin(lo.z));
    return glm::vec3(hsum(sum.x), hsum(sum.y), hsum(sum.z)) / float(count);
  };
  // 2 x 2 samples first. They settle the pixel where what they add could not show and no
  // two of them differ by more (`settled`, kFootprintSettledSteps of a display step). On
  // the car's fabric floor, 2 x 2 means whose samples disagree were a display step off the
  // pixel's on 26 000 pixels, which FLIP counts (1.44x the lattice's error without the
  // agreement test).
  glm::vec3 spread;
  const glm::vec3 coarse = model_mean(kFootprintCoarse.data(), int(kFootprintCoarse.size()), spread) - at_corners;
  if (glm::all(glm::lessThan(glm::abs(coarse), settled)) && glm::all(glm::lessThan(spread, settled)))
    return {coarse, true};
  // Otherwise the 25-point lattice's mean (aa/lattice.h): its 24 inner points, six groups of
  // four, and its four corners at 1/4 each, which are at_corners. A rank-1 lattice has one
  // point in every row and column of step 1/25, so texture stripes along the pixel's axes
  // do not alias as on a regular grid, whose points share rows and columns: car FLIP 1.290
  // -> 1.239x the lattice's (1024^2) against 4 x 4 here; 8 x 8, 64 reads, gave 1.233. The
  // lattice's level-2 points as the first estimate instead of 2 x 2 settled worse (1.253).
  const glm::vec3 inner = model_mean(kLattice.data() + 1, kLatticePoints - 1, spread);
  return {(inner - at_corners) * (float(kLatticePoints - 1) / float(kLatticePoints)), true};
}

}  // namespace zz
