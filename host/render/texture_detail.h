// The texture detail flag (ours, next to the highlight flag of specular_peak.h): how much
// a pixel's texture, averaged over the pixel, differs from the mean of what its four corner
// rays sampled. A thin bright stroke of an emissive or base-colour texture between the
// corners (a lamp's painted filament, a decal's line) leaves all four corners on the dark
// texels, equal, and the pixel finished at level 1 without it.
//
// The texture's mean over the pixel's footprint (the box of the corners' texture
// coordinates) comes from a pyramid of box-filtered levels, sampled trilinearly at the box's
// size, as a GPU's mip-mapped lookup would. It only decides where rays go: a flagged pixel
// is refined by tracing, never coloured from the pyramid (prefiltered texture colours
// measured worse against the box-filtered references, issue 10).
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "render/specular_peak.h"
#include "scene/texture.h"

namespace zz {

struct Scene;

// Box-filtered levels of one texture: levels[l] halves levels[l - 1] (levels[0] is empty:
// the texture itself serves), each with the texture's wrap modes and bilinear filtering.
struct TexturePyramid {
  std::vector<Texture> levels;

  TexturePyramid() = default;
  explicit TexturePyramid(const Texture& base);
  // The texture's mean over the box [lo, hi] of texture coordinates (one period: lo within
  // a wrap period of hi), as trilinear filtering at the box's size estimates it.
  glm::vec3 box_mean(const Texture& base, glm::vec2 lo, glm::vec2 hi) const;
};

// Pyramids of the scene's textures that colour light directly (base colour, emissive);
// the others stay empty.
std::vector<TexturePyramid> texture_pyramids(const Scene& scene);

// The radiance (linear RGB) by which the pixel with these corners (TL, TR, BL, BR) may differ
// from `corner_mean`, the mean of their radiance, because of texture detail between them:
// |mean over the footprint - mean at the corners| of the emissive texture times the
// emissive factor, plus that of the base-colour texture times the factor and the corners'
// radiance per unit albedo. Zero unless all four corners hit the same textured material,
// or where the footprint spans half the texture or more (a UV seam, not detail).
glm::vec3 hidden_texture_detail(const Scene& scene, const std::vector<TexturePyramid>& pyramids,
                                const SurfaceProbe corners[4], glm::vec3 corner_mean);

}  // namespace zz
