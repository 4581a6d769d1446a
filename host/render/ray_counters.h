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
  // Not rays: the traced lanes whose radiance came out NaN and was set to 0 before leaving
  // the shader (a shading bug: 0 in a healthy render; what tests of finiteness read, since
  // the image itself cannot show it).
  uint64_t nan_radiance = 0;
  // Not rays: lanes cut short at a see-through limit (render/see_through.h:
  // kMaxSeeThroughLayers cut-outs or shadow layers, kMaxBlendLayers BLEND surfaces), where
  // what lies further behind is left out. 0 unless a scene stacks them.
  uint64_t layer_limit = 0;
  // Not rays: traced lanes whose radiance exceeded the shader's cap (1e30, +Inf included)
  // and left it capped: 0 unless a light sits nearly on a surface (its 1/d^2 overflows);
  // the image cannot show it, since the cap is far above what any display or EXR reader
  // tells apart.
  uint64_t capped_radiance = 0;

  uint64_t total() const { return primary + shadow + reflection + refraction + continuation; }
  RayCounters& operator+=(const RayCounters& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    continuation += o.continuation;
    nan_radiance += o.nan_radiance;
    layer_limit += o.layer_limit;
    capped_radiance += o.capped_radiance;
    return *this;
  }
};

}  // namespace zz
