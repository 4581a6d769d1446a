// The renderer's SampleSource: a camera packet through 4 image-plane points, traced and
// shaded. Each tile owns one (its ray counters are per tile, summed afterwards).
// With signature parts switched on (aa/signature.h) it also says what each lane saw, and
// for the hidden-detail flags (aa/hidden_detail.h) which surface it hit.
#pragma once

#include <limits>
#include <vector>

#include "aa/adaptive_settings.h"
#include "aa/hidden_detail.h"
#include "aa/sample_source.h"
#include "aa/signature.h"
#include "render/shader.h"
#include "render/texture_detail.h"
#include "scene/camera.h"

namespace zz {

// What the source looks for between a pixel's corners, made once per frame.
struct HiddenDetail {
  bool highlights = false;               // render/specular_peak.h
  bool textures = false;                 // render/texture_detail.h
  bool footprint = false;                // texture_footprint_delta (render/texture_detail.h)
  // Normal steps wider than this are the visibility map's (normal_interpolation_error).
  float step_limit = std::numeric_limits<float>::infinity();
  std::vector<TexturePyramid> pyramids;  // with textures: texture_pyramids(scene)

  HiddenDetail() = default;
  HiddenDetail(const Scene& scene, const AdaptiveSettings& s)
      : highlights(s.highlights), textures(s.textures), footprint(s.footprint) {
    if (s.map_crease > 0.0f) step_limit = s.map_crease;
    if (textures) pyramids = texture_pyramids(scene);
  }
};

class SceneSource {
 public:
  // `tonemap`: the display's, which decides where a light could show (signature.h).
  SceneSource(const Shader& shader, const CameraRays& camera, unsigned signature_parts = kSignatureNone,
              const HiddenDetail* detail = nullptr, ToneMap tonemap = {})
      : shader_(shader), camera_(camera), parts_(signature_parts & kSignatureAll), detail_(detail),
        tonemap_(tonemap) {}

  Rgb4 sample4(float4 px, float4 py) { return shader_.trace4(camera_rays(px, py), mask4(true), 0, counters); }

  // The signature hashes the enabled parts of what the lane saw; 0 with none enabled.
  Rgb4 sample4(float4 px, float4 py, int4& signature) {
    if (parts_ == kSignatureNone) {
      signature = int4(0);
      return sample4(px, py);
    }
    PathSignature4 seen;
    glm::vec3 light_radiance[kLightSlots][4] = {};
    if (parts_ & kSignatureLights) seen.light_radiance = light_radiance;
    const Rgb4 c = shader_.trace4(camera_rays(px, py), mask4(true), 0, counters, &seen);
    signature = hash(seen, c);
    return c;
  }

  // With the surfaces the lanes' paths hit, for the hidden-detail flags (aa/hidden_detail.h):
  // the primary hit's, those seen in it by reflection and refraction, and those seen by
  // reflection and refraction in what it reflects (render/shader.h's path tree).
  struct Probe {
    SurfaceProbe node[kProbeNodes];
    FootprintProbe footprint;  // filled only when the footprint correction is on
    const SurfaceProbe& surface() const { return node[0]; }
  };
  Rgb4 sample4(float4 px, float4 py, int4& signature, Probe probes[4]) {
    SurfaceProbe tree[kProbeNodes][4];
    FootprintProbe footprint[4];
    PathSignature4 seen;
    seen.probes = tree;
    if (detail_ && detail_->footprint) seen.footprint = footprint;
    glm::vec3 light_radiance[kLightSlots][4] = {};
    if (parts_ & kSignatureLights) seen.light_radiance = light_radiance;
    const Rgb4 c = shader_.trace4(camera_rays(px, py), mask4(true), 0, counters, &seen);
    signature = parts_ == kSignatureNone ? int4(0) : hash(seen, c);
    for (int i = 0; i < 4; ++i) {
      for (int k = 0; k < kProbeNodes; ++k) probes[i].node[k] = tree[k][i];
      probes[i].footprint = footprint[i];
    }
    return c;
  }

  // Radiance by which the pixel with corners tl[0], tl[1], tl[stride], tl[stride + 1]
  // (TL, TR, BL, BR, in a grid with a ring around them; `mean` the mean of their radiance)
  // may differ unseen; `visible`: per channel, the smallest increment that could show.
  float4 hidden_radiance(const Probe* tl, ptrdiff_t stride, float4 mean, float4 visible) const {
    if (!detail_) return float4(0.0f);
    const SurfaceProbe corners[4] = {tl[0].surface(), tl[1].surface(), tl[stride].surface(), tl[stride + 1].surface()};
    const glm::vec3 shown(visible[0], visible[1], visible[2]);
    glm::vec3 h(0.0f);
    if (detail_->highlights)
      for (int k = 0; k < kProbeNodes; ++k) {
        const SurfaceProbe c[4] = {tl[0].node[k], tl[1].node[k], tl[stride].node[k], tl[stride + 1].node[k]};
        if (!has_highlight(c[0]) || !has_highlight(c[1]) || !has_highlight(c[2]) || !has_highlight(c[3])) continue;
        const ProbeStencil stencil(&tl->node[k], sizeof(Probe), stride * ptrdiff_t(sizeof(Probe)));
        h += hidden_highlight(shader_.scene(), c, shown, &stencil, detail_->step_limit);
      }
    if (detail_->textures)
      h += hidden_texture_detail(shader_.scene(), detail_->pyramids, corners, glm::vec3(mean[0], mean[1], mean[2]));
    return float4(h.r, h.g, h.b, 0.0f);
  }

  // What the corners' mean lacks of the texture's mean over the pixel (texture_detail.h);
  // lane 3 is 1 where the correction applies, 0 elsewhere.
  // `mean`: the corners' mean radiance; a first estimate is kept where it moves the display
  // by less than half a step.
  float4 footprint_delta(const Probe* tl, ptrdiff_t stride, float4 mean) const {
    if (!detail_ || !detail_->footprint) return float4(0.0f);
    const SurfaceProbe corners[4] = {tl[0].surface(), tl[1].surface(), tl[stride].surface(), tl[stride + 1].surface()};
    const FootprintProbe* const light[4] = {&tl[0].footprint, &tl[1].footprint, &tl[stride].footprint,
                                            &tl[stride + 1].footprint};
    const float4 settled = float4(0.5f / 255.0f) / tonemap_.slope4(mean);
    const FootprintDelta d =
        texture_footprint_delta(shader_.scene(), corners, light, glm::vec3(settled[0], settled[1], settled[2]));
    return float4(d.delta.r, d.delta.g, d.delta.b, d.applies ? 1.0f : 0.0f);
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

  int4 hash(const PathSignature4& seen, const Rgb4& colour) const {
    alignas(16) int32_t s[4];
    for (int i = 0; i < 4; ++i) {
      uint32_t h = 0;
      if (parts_ & kSignatureObject) h = signature_mix(h, seen.object[i]);
      if (parts_ & kSignatureSecondary) h = signature_mix(signature_mix(h ^ 0x53454344u, seen.reflected[i]), seen.refracted[i]);
      uint32_t shadowed = 0, shows = 0;
      if (parts_ & kSignatureLights) {
        for (int l = 0; l < 32; ++l) shadowed |= ((seen.shadowed[i] >> l) & 1u) << (l % kLightSlots);
        const glm::vec3 c(colour.r[i], colour.g[i], colour.b[i]);
        for (int slot = 0; slot < kLightSlots; ++slot)
          shows |= uint32_t(light_shows(c, seen.light_radiance[slot][i], (shadowed >> slot) & 1u)) << slot;
      }
      s[i] = make_signature(h >> (32 - kWhatBits), shows, shadowed);
    }
    return int4(s[0], s[1], s[2], s[3]);
  }

  // Whether adding `light` to the sample's radiance without it (`colour`, less `light` where
  // the light reached it) moves a displayed channel by an 8-bit step or more.
  bool light_shows(glm::vec3 colour, glm::vec3 light, bool shadowed) const {
    if (!(light.r > 0.0f || light.g > 0.0f || light.b > 0.0f)) return false;
    const glm::vec3 without = shadowed ? colour : glm::max(colour - light, glm::vec3(0.0f));
    const float4 base(without.r, without.g, without.b, 0.0f), lit(without.r + light.r, without.g + light.g,
                                                                  without.b + light.b, 0.0f);
    return ((tonemap_.apply4(lit) - tonemap_.apply4(base) >= float4(kDisplayStep)).bits() & 0x7) != 0;
  }
  static constexpr float kDisplayStep = 1.0f / 255.0f;

  const Shader& shader_;
  const CameraRays& camera_;
  unsigned parts_;
  const HiddenDetail* detail_;
  ToneMap tonemap_;
};

static_assert(SignedSampleSource<SceneSource>);
static_assert(HiddenDetailSource<SceneSource>);

}  // namespace zz
