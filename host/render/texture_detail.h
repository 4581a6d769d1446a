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

#include "render/footprint_probe.h"
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
// What texture_pyramids(scene) holds (float RGBA levels), and the largest level's texel
// counts it sums with on the way: for the memory check before a frame with --textures on.
uint64_t texture_pyramid_bytes(const Scene& scene);

// The radiance (linear RGB) by which the pixel with these corners (TL, TR, BL, BR) may differ
// from `corner_mean`, the mean of their radiance, because of texture detail between them:
// |mean over the footprint - mean at the corners| of the emissive texture times the
// emissive factor, plus that of the base-colour texture times the factor and the corners'
// radiance per unit albedo. Zero unless all four corners hit the same textured material,
// or where the footprint spans half the texture or more (a UV seam, not detail).
glm::vec3 hidden_texture_detail(const Scene& scene, const std::vector<TexturePyramid>& pyramids,
                                const SurfaceProbe corners[4], glm::vec3 corner_mean);

// The texture footprint correction (ours): what a pixel finished at level 1 lacks because
// the mean of its four corner samples is not the mean of the texture over the pixel. With
// the corners (TL, TR, BL, BR) on one material, the pixel's texture coordinates are their
// bilinear interpolation (with a FootprintView, a sample whose camera ray meets one of the
// corners' triangles takes that triangle's coordinates and normal-map frame instead); the base-colour (diffuse albedo) and emissive textures are
// averaged over it at 2 x 2 points, or the 25-point lattice's where those disagree (the box
// filter the lattice and the reference apply, without rays), and
//   delta = mean_s(A_s E_s) - mean_k(A_k E_k) + emission * (mean_s(T_s) - mean_k(T_k)),
// over samples s and corners k, with A the diffuse albedo, T the emissive texture and E the
// direct light per unit albedo (FootprintProbe::irradiance): at a sample, the corners' mean,
// moved to first order (FootprintProbe::gradient) by the normal map's normal there. Exact
// where light and visibility are even over the pixel, which is where its corners agree.
// Does not apply to other pixels (a miss, two materials, a UV seam or atlas jump, no texture).
// The 2 x 2 first estimate settles a pixel where it moves the display by less than this
// many 8-bit steps and its samples agree within that. Half a step let the rounding of the
// 8-bit image flip where the estimate's own error added to it: a quarter took car's FLIP
// 1.193 -> 1.177x the lattice's (the fabric floor 2.01 -> 1.73x), lamp 1.116 -> 1.115, for
// +3.5 % car render time (2.03 -> 2.10 s, 3 interleaved runs; an eighth: 1.175).
inline constexpr float kFootprintSettledSteps = 0.25f;
// The largest texture span along a pixel side that the samples resolve.
inline constexpr float kFootprintMaxTexels = 16.0f;
struct FootprintDelta {
  glm::vec3 delta{0.0f};
  bool applies = false;  // the pixel is one patch of a textured material (delta may still be 0)
};
// What the correction needs of one corner beyond its probes, the same for each of the
// four pixels that share it (footprint_corner makes it once per corner): with the normal
// map and few lights, the map's frame and each light's strength and direction, recomputed
// from the hit and checked against the irradiance the shader found; the corner's diffuse
// light both ways (light by light, and albedo x irradiance); its emissive texel.
struct FootprintCorner {
  bool valid = false;      // a hit on a material whose textures the correction follows
  bool per_light = false;  // frame, strength and to_light hold, and add up to the shader's light
  glm::vec3 frame[3]{};
  glm::vec3 strength[kFootprintLights]{}, to_light[kFootprintLights]{};
  glm::vec3 lit{0.0f};         // light by light at the corner's normal (with per_light)
  glm::vec3 albedo_lit{0.0f};  // albedo x FootprintProbe::irradiance
  glm::vec3 emissive_texel{0.0f};
};
FootprintCorner footprint_corner(const Scene& scene, const SurfaceProbe& corner, const FootprintProbe& footprint);

// The camera (origin, unit forward axis; a pinhole, or an orthographic camera's plane
// through origin): with it, a sample whose camera ray meets one of the corners' triangles
// takes that triangle's texture coordinates and shading frame, not the corners'
// interpolation. Only for the primary hit (node 0).
struct FootprintView {
  glm::vec3 origin{0.0f}, forward{0.0f, 0.0f, -1.0f};
  bool orthographic = false;
};

// `settled`: per channel, kFootprintSettledSteps of a display step: the 2 x 2 first
// estimate is kept when its delta stays below it and no two of its four samples differ by
// more, in every channel; otherwise the model at the 25-point lattice (aa/lattice.h: 24
// inner points, four at a time in SSE lanes, and the corners).
// `prepared`: footprint_corner of each corner.
FootprintDelta texture_footprint_delta(const Scene& scene, const SurfaceProbe corners[4],
                                       const FootprintProbe* const footprint[4],
                                       const FootprintCorner* const prepared[4], glm::vec3 settled,
                                       const FootprintView* view = nullptr);
// The same, preparing the four corners itself.
FootprintDelta texture_footprint_delta(const Scene& scene, const SurfaceProbe corners[4],
                                       const FootprintProbe* const footprint[4], glm::vec3 settled,
                                       const FootprintView* view = nullptr);

}  // namespace zz
