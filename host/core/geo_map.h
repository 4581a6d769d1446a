// The per-pixel geometric discontinuity flags (ALGORITHM.md §7), produced by the
// Vulkan visibility pass and read by the adaptive sampler. Empty = no map (--edges off).
#pragma once

#include <cstdint>
#include <vector>

namespace zz {

struct GeoMap {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> flags;  // 1 byte per pixel, row-major, nonzero = geo

  bool empty() const { return flags.empty(); }
  bool at(int x, int y) const { return !empty() && flags[size_t(y) * width + x] != 0; }
};

}  // namespace zz
