// Small sample sources shared by the aa tests.
#pragma once

#include <cstdint>
#include <cstring>

#include "aa/adaptive_frame.h"

namespace zz::test {

// Two colours split by an axis-aligned line: x < pos (vertical line) or y < pos.
struct AxisEdgeSource {
  bool vertical_line = true;
  float pos = 0.5f;
  float a = 0.0f, b = 1.0f;
  Rgb4 sample4(float4 px, float4 py) const {
    const mask4 before = (vertical_line ? px : py) < float4(pos);
    const float4 v = select(before, float4(a), float4(b));
    return {v, v, v};
  }
};

struct ConstantSource {
  float r = 0.25f, g = 0.5f, b = 0.75f;
  Rgb4 sample4(float4, float4) const { return {float4(r), float4(g), float4(b)}; }
};

// Lane-independent pseudo-random HDR values from the point's bits.
struct HdrNoiseSource {
  Rgb4 sample4(float4 px, float4 py) const {
    alignas(16) float x[4], y[4], out[3][4];
    px.store(x);
    py.store(y);
    const float values[4] = {0.0f, 1e9f, 1e-3f, 5e8f};
    for (int i = 0; i < 4; ++i) {
      uint32_t ux, uy;
      std::memcpy(&ux, &x[i], 4);
      std::memcpy(&uy, &y[i], 4);
      uint32_t h = ux * 0x9E3779B1u ^ (uy + 0x7F4A7C15u) * 0x85EBCA77u;
      h ^= h >> 15;
      for (int c = 0; c < 3; ++c) out[c][i] = values[(h >> (2 * c)) & 3];
    }
    return {float4::load(out[0]), float4::load(out[1]), float4::load(out[2])};
  }
};

// corner_field: level 1 for the whole frame at once (aa/corner_field.h), else per tile.
template <class S>
Film render(const S& source, int w, int h, const AdaptiveSettings& s, int tile = kTileSize, int threads = 1,
            const GeoMap& geo = {}, AaStats* stats = nullptr, bool corner_field = true) {
  Film f(w, h);
  AaStats st = render_frame_adaptive(source, f, geo, s, tile, threads, corner_field);
  if (stats) *stats = st;
  return f;
}

}  // namespace zz::test
