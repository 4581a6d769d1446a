// The renderer's SampleSource: a camera packet through 4 image-plane points, traced and
// shaded. Each tile owns one (its ray counters are per tile, summed afterwards).
// With signature parts switched on (aa/signature.h) it also says what each lane saw.
#pragma once

#include "aa/sample_source.h"
#include "aa/signature.h"
#include "render/shader.h"
#include "scene/camera.h"

namespace zz {

class SceneSource {
 public:
  SceneSource(const Shader& shader, const CameraRays& camera, unsigned signature_parts = kSignatureNone)
      : shader_(shader), camera_(camera), parts_(signature_parts & kSignatureAll) {}

  Rgb4 sample4(float4 px, float4 py) { return shader_.trace4(camera_rays(px, py), mask4(true), 0, counters); }

  // The signature hashes the enabled parts of what the lane saw; 0 with none enabled.
  Rgb4 sample4(float4 px, float4 py, int4& signature) {
    if (parts_ == kSignatureNone) {
      signature = int4(0);
      return sample4(px, py);
    }
    PathSignature4 seen;
    const Rgb4 c = shader_.trace4(camera_rays(px, py), mask4(true), 0, counters, &seen);
    alignas(16) int32_t s[4];
    for (int i = 0; i < 4; ++i) {
      uint32_t h = 0;
      if (parts_ & kSignatureObject) h = signature_mix(h, seen.object[i]);
      if (parts_ & kSignatureLights) h = signature_mix(h ^ 0x4C494748u, seen.shadowed[i]);
      if (parts_ & kSignatureSecondary) h = signature_mix(signature_mix(h ^ 0x53454344u, seen.reflected[i]), seen.refracted[i]);
      s[i] = int32_t(h);
    }
    signature = int4(s[0], s[1], s[2], s[3]);
    return c;
  }

  RayCounters counters;

 private:
  RayPacket4 camera_rays(float4 px, float4 py) {
    RayPacket4 rays;
    rays.ox = float4(camera_.origin.x);
    rays.oy = float4(camera_.origin.y);
    rays.oz = float4(camera_.origin.z);
    camera_.directions4(px, py, rays.dx, rays.dy, rays.dz);
    rays.tmax = float4(kInfinity);
    counters.primary += 4;
    return rays;
  }

  const Shader& shader_;
  const CameraRays& camera_;
  unsigned parts_;
};

static_assert(SignedSampleSource<SceneSource>);

}  // namespace zz
