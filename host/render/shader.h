// Whitted shading of 4-ray packets: Lambert + normalised Phong highlight per light with
// hard shadows (shadow rays in 4-ray packets), perfect mirror reflection, refraction
// with exact dielectric Fresnel and total internal reflection, Beer-Lambert absorption
// inside volumes, emission. Per hit: base colour, metallic/roughness, transmission,
// emissive and normal textures; alpha MASK surfaces are skipped where cut out and BLEND
// surfaces mix with a continuation ray behind them (deterministic, no randomness).
// Shadow rays pass alpha cut-outs and transmissive non-metal surfaces, attenuated by
// transmission x base colour at each crossing and by Beer's law inside volumes; they are
// not bent (the classic Whitted approximation: no caustics).
// The kernel is compiled once per EffectSet combination, so a scene without lights never
// builds a shadow packet, one without glass never runs refraction code and one without
// alpha never tests coverage (ALGORITHM-independent: the AA code only sees a SampleSource).
#pragma once

#include "accel/bvh.h"
#include "core/color.h"
#include "render/ray_counters.h"
#include "scene/scene.h"

namespace zz {

class Shader {
 public:
  Shader(const Scene& scene, const Bvh& bvh);

  // Radiance arriving along the active lanes' rays (inactive lanes return 0).
  // `depth` counts the bounces already taken: 0 for camera rays.
  Rgb4 trace4(const RayPacket4& rays, mask4 active, int depth, RayCounters& counters) const {
    return (this->*kernel_)(rays, active, depth, 0, counters);
  }

  const EffectSet& effects() const { return effects_; }

  // Bits of the kernel specialisation.
  enum : unsigned { kShadows = 1, kReflection = 2, kRefraction = 4, kTextures = 8, kAlpha = 16, kAllEffects = 31 };

 private:
  // `blend_layers` counts the BLEND surfaces already seen through along this ray.
  template <unsigned kEffects>
  Rgb4 trace4_impl(const RayPacket4& rays, mask4 active, int depth, int blend_layers, RayCounters& counters) const;

  using Kernel = Rgb4 (Shader::*)(const RayPacket4&, mask4, int, int, RayCounters&) const;
  template <unsigned... kE>
  static Kernel pick_kernel(unsigned effects, std::integer_sequence<unsigned, kE...>);

  const Scene& scene_;
  const Bvh& bvh_;
  EffectSet effects_;
  Kernel kernel_;
};

// Exact unpolarised Fresnel reflectance of a dielectric interface for cos_i >= 0 and
// relative index eta = n_incident / n_transmitted; 1 on total internal reflection.
float fresnel_dielectric(float cos_i, float eta);

}  // namespace zz
