// The renderer's SampleSource: a camera packet through 4 image-plane points, traced and
// shaded. Each tile owns one (its ray counters are per tile, summed afterwards).
#pragma once

#include "aa/sample_source.h"
#include "render/shader.h"
#include "scene/camera.h"

namespace zz {

class SceneSource {
 public:
  SceneSource(const Shader& shader, const CameraRays& camera) : shader_(shader), camera_(camera) {}

  Rgb4 sample4(float4 px, float4 py) {
    RayPacket4 rays;
    rays.ox = float4(camera_.origin.x);
    rays.oy = float4(camera_.origin.y);
    rays.oz = float4(camera_.origin.z);
    camera_.directions4(px, py, rays.dx, rays.dy, rays.dz);
    rays.tmax = float4(kInfinity);
    counters.primary += 4;
    return shader_.trace4(rays, mask4(true), 0, counters);
  }

  RayCounters counters;

 private:
  const Shader& shader_;
  const CameraRays& camera_;
};

static_assert(SampleSource<SceneSource>);

}  // namespace zz
