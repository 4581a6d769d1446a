// Packet colours: linear RGB radiance for 4 lanes (SoA).
#pragma once

#include "core/simd.h"

namespace zz {

struct alignas(16) Rgb4 {
  float4 r, g, b;
};

inline Rgb4 operator+(const Rgb4& a, const Rgb4& b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline Rgb4 operator*(const Rgb4& a, float4 s) { return {a.r * s, a.g * s, a.b * s}; }
inline Rgb4 select(mask4 m, const Rgb4& a, const Rgb4& b) {
  return {select(m, a.r, b.r), select(m, a.g, b.g), select(m, a.b, b.b)};
}

}  // namespace zz
