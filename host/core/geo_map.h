// The per-pixel geometric discontinuity flags (ALGORITHM.md §7), produced by the
// Vulkan visibility pass and read by the adaptive sampler. Empty = no map (--edges off).
#pragma once

#include <cstdint>
#include <vector>

#include "core/tile.h"

namespace zz {

// A pixel's flag byte (shaders/visibility_shared.h: ZZ_GEO_EDGE, ZZ_GEO_ALONG_X).
inline constexpr uint8_t kGeoEdge = 1;    // the pixel is geo
inline constexpr uint8_t kGeoAlongX = 2;  // more of its differing sample pairs are vertical
                                          // neighbours than horizontal ones: the edge runs along x

struct GeoMap {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> flags;  // 1 byte per pixel, row-major, nonzero = geo

  bool empty() const { return flags.empty(); }
  bool at(int x, int y) const { return !empty() && flags[size_t(y) * width + x] != 0; }
  // Whether a geo pixel's edge runs along x (false where the map has no pixel or no edge).
  bool along_x(int x, int y) const { return !empty() && (flags[size_t(y) * width + x] & kGeoAlongX) != 0; }
};

// The flags of `rect` (inside the map) as a map of its own; empty stays empty.
inline GeoMap crop(const GeoMap& geo, const TileRect& rect) {
  if (geo.empty()) return {};
  GeoMap out{rect.width(), rect.height(), std::vector<uint8_t>(size_t(rect.width()) * rect.height())};
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) out.flags[size_t(y - rect.y0) * out.width + (x - rect.x0)] = geo.flags[size_t(y) * geo.width + x];
  return out;
}

}  // namespace zz
