// How much a texture varies over a patch of texture coordinates, for the highlight flag
// (render/specular_peak.h): a normal map finer than the pixel (a metal's brushed or
// hammered grain, 10 texels between two corners on the lamp) turns the normal between the
// corners away from their bilinear interpolation, and the highlight of a shiny surface
// then peaks on a texel no corner saw. How far the map turns the normals there is
// estimated from the texels' RMS deviation over the corners' texture-coordinate box, from
// a pyramid of per-block sums of the texels and of their squares.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "render/specular_peak.h"
#include "scene/texture.h"

namespace zz {

struct Scene;

// Sums of a set of texels' RGB and of its squares.
struct TextureMoments {
  glm::vec3 sum{0.0f}, sum_sq{0.0f};
  float count = 0.0f;
  glm::vec3 deviation() const;  // per channel, the RMS distance from the mean
};

class TextureSpread {
 public:
  TextureSpread() = default;
  explicit TextureSpread(const Texture& base);
  bool empty() const { return levels_.empty(); }
  // The moments of the texels that nearest or bilinear filtering of `base` reads in the box
  // [lo, hi] of texture coordinates: those texels themselves where the box spans at most
  // 5 x 5 of them, otherwise the blocks of the finest level on which it spans at most 3 x 3
  // (a few texels around it then count too). `base` must be the texture this was built from.
  TextureMoments over(const Texture& base, glm::vec2 lo, glm::vec2 hi) const;
  // Bytes the pyramid of a width x height texture holds.
  static uint64_t bytes(int width, int height);

 private:
  // Level i's block (x, y) sums base texels [x B, (x + 1) B) x [y B, (y + 1) B) with
  // B = 4 << i; a level's last row and column also sum the base's remainder.
  struct Level {
    int width = 0, height = 0;
    std::vector<TextureMoments> blocks;
  };
  std::vector<Level> levels_;
};

// Spreads of the scene's normal maps (one per scene texture, empty unless a material uses
// it as its normal texture).
std::vector<TextureSpread> normal_map_spreads(const Scene& scene);
// What normal_map_spreads will hold, in bytes (about 1.9 per texel), for the frame's memory check.
uint64_t normal_map_spread_bytes(const Scene& scene);

// How far (a distance between unit normals) the normal map typically turns the normals
// inside the pixel whose corners are `corners` away from the bilinear interpolation of
// theirs: kSpreadDeviations times the RMS distance of its tangent-space normals over the
// corners' texture box from their mean. 0 unless all four corners hit one material with a
// normal map. A typical turn, not a bound: the range of an 8-bit map's texels (a bound)
// sent the lamp to 2.49 rays/px. Half the RMS distance is what the report's targets
// allow (1024²): lamp FLIP 1.189 -> 1.143x the lattice's for +0.10 rays/px, car +0.03;
// the whole RMS distance gave lamp 1.116 but car +0.064, past the mean-rays target.
inline constexpr float kSpreadDeviations = 0.5f;
float normal_map_spread(const Scene& scene, const std::vector<TextureSpread>& spreads, const SurfaceProbe corners[4]);

}  // namespace zz
