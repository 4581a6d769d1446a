// The per-pixel geometric discontinuity flags (ALGORITHM.md §7), produced by the
// Vulkan visibility pass and read by the adaptive sampler. Empty = no map (--edges off).
#pragma once

#include <cstdint>
#include <vector>

#include "core/tile.h"

namespace zz {

// A pixel's flag byte (shaders/visibility_shared.h: ZZ_GEO_EDGE, ZZ_GEO_ALONG_X,
// ZZ_GEO_ZONE_SHIFT).
inline constexpr uint8_t kGeoEdge = 1;    // the pixel is geo
inline constexpr uint8_t kGeoAlongX = 2;  // more of its differing sample pairs are vertical
                                          // neighbours than horizontal ones: the edge runs along x
inline constexpr int kGeoZoneShift = 2;   // then 5 bits: the zones the edge meets, in the frame
                                          // kGeoAlongX names (vertical when set)

// The zone bit (ALGORITHM.md §3: zone k spans canonical u in [0.2 k, 0.2 k + 0.2]) of
// canonical u given in units of 1 / (10 S) of a pixel, both neighbours on a boundary: as
// zone_at in shaders/geo_flags.comp.
constexpr int map_zone_at(int u, int s) {
  const int k = u / (2 * s);
  int z = 1 << (k < 4 ? k : 4);
  if (u % (2 * s) == 0 && k > 0 && k < 5) z |= 1 << (k - 1);
  return z;
}

// The flag byte of a pixel from its differing horizontal (`across`) and vertical (`along`)
// sample pairs and the zones they meet in the horizontal and the vertical frame.
constexpr uint8_t geo_flag_byte(int across, int along, int zones_h, int zones_v) {
  if (across + along == 0) return 0;
  return uint8_t(kGeoEdge | (along > across ? kGeoAlongX | zones_v << kGeoZoneShift : zones_h << kGeoZoneShift));
}

// A pixel's differing sample pairs, counted as the compute pass counts them, in pixel-local
// sample indices (-1 and s are the ring), with the zones each meets in both frames
// (canonical u = x in the horizontal frame, 1 - y in the vertical one).
struct GeoPairs {
  int s;  // samples per pixel axis
  int across = 0, along = 0, zones_h = 0, zones_v = 0;
  // Samples i and i + 1 of row j: the pair's midpoint at x = (i + 1) / s, the row at y = (j + 0.5) / s.
  constexpr void horizontal(int i, int j) {
    ++across;
    zones_h |= map_zone_at(10 * (i + 1), s);
    zones_v |= map_zone_at(10 * s - (10 * j + 5), s);
  }
  // Rows j and j + 1 of column i: the column at x = (i + 0.5) / s, the midpoint at y = (j + 1) / s.
  constexpr void vertical(int i, int j) {
    ++along;
    zones_h |= map_zone_at(10 * i + 5, s);
    zones_v |= map_zone_at(10 * s - 10 * (j + 1), s);
  }
  constexpr uint8_t byte() const { return geo_flag_byte(across, along, zones_h, zones_v); }
};

struct GeoMap {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> flags;  // 1 byte per pixel, row-major, nonzero = geo

  bool empty() const { return flags.empty(); }
  bool at(int x, int y) const { return !empty() && flags[size_t(y) * width + x] != 0; }
  // Whether a geo pixel's edge runs along x (false where the map has no pixel or no edge).
  bool along_x(int x, int y) const { return !empty() && (flags[size_t(y) * width + x] & kGeoAlongX) != 0; }
  // The zones a geo pixel's edge meets, in the frame along_x names (0 where no edge).
  int zones(int x, int y) const { return empty() ? 0 : (flags[size_t(y) * width + x] >> kGeoZoneShift) & 0x1F; }
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
