#include "render/aov.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "render/image_io.h"

namespace zz {

void ray_count_colour(int n, uint8_t rgb[3]) {
  // A dark-blue -> magenta -> orange -> pale-yellow ramp (inferno-like), piecewise linear.
  static const float stops[5][3] = {{0.05f, 0.03f, 0.20f}, {0.45f, 0.07f, 0.45f}, {0.85f, 0.25f, 0.25f},
                                    {0.98f, 0.60f, 0.10f}, {0.99f, 0.98f, 0.65f}};
  const float t = float(std::clamp(n, 1, 25) - 1) / 24.0f * 4.0f;
  const int i = std::min(int(t), 3);
  const float f = t - float(i);
  for (int c = 0; c < 3; ++c)
    rgb[c] = uint8_t(std::lround(255.0f * (stops[i][c] * (1.0f - f) + stops[i + 1][c] * f)));
}

Rgb8Image rays_heatmap(const Film& film) {
  constexpr int kLegend = 24;
  Rgb8Image img{film.width, film.height + kLegend, {}};
  img.rgb.assign(size_t(img.width) * img.height * 3, 0);
  for (size_t i = 0; i < film.rays.size(); ++i) ray_count_colour(film.rays[i], &img.rgb[i * 3]);
  // Legend: 25 swatches across the width; white ticks at 1, 5, 10, 15, 20, 25.
  for (int y = film.height; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const int n = 1 + std::min(24, x * 25 / std::max(1, img.width));
      uint8_t* p = &img.rgb[(size_t(y) * img.width + x) * 3];
      ray_count_colour(n, p);
      const bool tick_row = y < film.height + 6;
      const bool tick = (n == 1 || n % 5 == 0) && (x * 25 / std::max(1, img.width)) != ((x + 1) * 25 / std::max(1, img.width));
      if (tick_row && tick) p[0] = p[1] = p[2] = 255;
    }
  return img;
}

void level_colour(int level, uint8_t rgb[3]) {
  static const uint8_t colours[8][3] = {{0, 0, 0}, {70, 70, 70}, {40, 90, 230},  {230, 50, 40},
                                        {0, 0, 0}, {70, 70, 70}, {40, 210, 230}, {240, 220, 40}};
  std::copy_n(colours[level & 7], 3, rgb);
}

Rgb8Image level_map(const Film& film) {
  Rgb8Image img{film.width, film.height, std::vector<uint8_t>(size_t(film.width) * film.height * 3)};
  for (size_t i = 0; i < film.level.size(); ++i) level_colour(film.level[i], &img.rgb[i * 3]);
  return img;
}

Rgb8Image geo_image(const GeoMap& geo) {
  Rgb8Image img{geo.width, geo.height, std::vector<uint8_t>(size_t(geo.width) * geo.height * 3)};
  for (size_t i = 0; i < geo.flags.size(); ++i) std::fill_n(&img.rgb[i * 3], 3, geo.flags[i] ? 255 : 0);
  return img;
}

void write_aov(Aov aov, const std::filesystem::path& path, const Film& film, const GeoMap& geo, OutputSet* set) {
  Rgb8Image img;
  switch (aov) {
    case Aov::Rays:
      img = rays_heatmap(film);
      break;
    case Aov::Level:
      img = level_map(film);
      break;
    case Aov::Geo:
      if (geo.empty()) throw Error("--aov geo needs the visibility map (--edges vulkan)");
      img = geo_image(geo);
      break;
    default:
      throw Error(std::string("--aov ") + aov_name(aov) + " has no image of its own (only channels of an .exr)");
  }
  write_rgb8(path, img.width, img.height, img.rgb, set);
}

}  // namespace zz
