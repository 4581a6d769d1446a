// Arbitrary output variables as viewable 8-bit images:
//   rays    rays traced per pixel, 1..25 on a perceptual ramp, with a legend band below
//           the image (25 swatches, a tick every 5 rays)
//   level   AA level reached: 1 grey; 2 blue (horizontal) / cyan (vertical);
//           3 red (horizontal) / yellow (vertical)
//   geo     the visibility map: white = geometric discontinuity
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/geo_map.h"
#include "core/film.h"
#include "render/aov_layers.h"

namespace zz {

struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

Rgb8Image rays_heatmap(const Film& film);
Rgb8Image level_map(const Film& film);
Rgb8Image geo_image(const GeoMap& geo);

// Colour of n rays on the heatmap ramp (n clamped to 1..25).
void ray_count_colour(int n, uint8_t rgb[3]);

// Colour of an AA level byte (1..3, +4 when vertical; 0 = not rendered: black).
void level_colour(int level, uint8_t rgb[3]);

// The heatmap image of rays, level or geo (has_heatmap). Throws zz::Error for another
// AOV or a missing geo map.
void write_aov(Aov aov, const std::filesystem::path& path, const Film& film, const GeoMap& geo,
               OutputSet* set = nullptr);

}  // namespace zz
