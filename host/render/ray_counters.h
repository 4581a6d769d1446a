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

  uint64_t total() const { return primary + shadow + reflection + refraction; }
  RayCounters& operator+=(const RayCounters& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    return *this;
  }
};

}  // namespace zz
