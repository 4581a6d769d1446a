// Embree 3 over the same triangle soup, traced with the same RayPacket4s (the reference
// for the speed targets). Everything is a no-op without ZZ_BENCH_HAVE_EMBREE.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <vector>

#include "accel/ray.h"

namespace zz::bench {

class EmbreeTracer {
 public:
  explicit EmbreeTracer(const std::vector<glm::vec3>& positions);
  ~EmbreeTracer();
  static bool available();

  // Same contract as Bvh::intersect4 / occluded4 / intersect1 (prim ids, t).
  void intersect4(const RayPacket4& rays, int mask, HitPacket4& hits) const;
  int occluded4(const RayPacket4& rays, int mask) const;
  Hit intersect1(const Ray& ray) const;
  bool occluded1(const Ray& ray) const;
  double build_seconds() const { return build_seconds_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double build_seconds_ = 0.0;
};

}  // namespace zz::bench
