// Rays traced, by type: makes "simulate only what the scene calls for" checkable.
#pragma once

#include <cstdint>

namespace zz {

enum class RayType { Primary, Shadow, Reflection, Refraction };

struct RayCounters {
  uint64_t primary = 0;
  uint64_t shadow = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;
  // Rays that continue a camera, mirror or refraction ray past an alpha-masked or blended
  // surface (shadow rays continuing through see-through surfaces count as shadow rays).
  uint64_t continuation = 0;

  uint64_t total() const { return primary + shadow + reflection + refraction + continuation; }
  RayCounters& operator+=(const RayCounters& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    continuation += o.continuation;
    return *this;
  }
};

}  // namespace zz
