#include "render/texture_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene/scene.h"

namespace zz {

TexturePyramid::TexturePyramid(const Texture& base) {
  if (base.width <= 0 || base.height <= 0 || base.texel_count() < size_t(base.width) * size_t(base.height)) return;
  levels.emplace_back();  // level 0 is `base`
  int w = base.width, h = base.height;
  while (w > 1 || h > 1) {
    const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    const Texture* parent = levels.size() == 1 ? &base : &levels.back();
    Texture level;
    level.width = nw;
    level.height = nh;
    level.wrap_s = base.wrap_s;
    level.wrap_t = base.wrap_t;
    level.filter = TextureFilter::Linear;
    level.texels.resize(size_t(nw) * size_t(nh));
    for (int y = 0; y < nh; ++y)
      for (int x = 0; x < nw; ++x) {
        // The 2x2 block under the texel (an odd last row or column joins its neighbour).
        const int x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
        const int y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
        level.texels[size_t(y) * nw + x] =
            0.25f * (parent->texel(size_t(y0) * w + x0) + parent->texel(size_t(y0) * w + x1) +
                     parent->texel(size_t(y1) * w + x0) + parent->texel(size_t(y1) * w + x1));
      }
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

std::vector<TexturePyramid> texture_pyramids(const Scene& scene) {
  std::vector<bool> wanted(scene.textures.size(), false);
  for (const Material& m : scene.materials)
    for (const TextureRef* ref : {&m.base_color_texture, &m.emissive_texture})
      if (ref->used() && size_t(ref->index) < wanted.size()) wanted[size_t(ref->index)] = true;
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
    const glm::vec2 st = ref.apply(ref.texcoord == 1 ? c[k].uv1 : c[k].uv0);
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

}  // namespace zz
