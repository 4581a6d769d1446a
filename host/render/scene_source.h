// The renderer's SampleSource: a camera packet through 4 image-plane points, traced and
// shaded. Each tile owns one (its ray counters are per tile, summed afterwards).
// With signature parts switched on (aa/signature.h) it also says what each lane saw, and
// for the hidden-detail flags (aa/hidden_detail.h) which surface it hit.
#pragma once

#include <algorithm>
#include <bit>
#include <limits>
#include <vector>

#include "aa/adaptive_settings.h"
#include "aa/hidden_detail.h"
#include "aa/sample_source.h"
#include "aa/signature.h"
#include "render/shader.h"
#include "render/texture_detail.h"
#include "render/texture_range.h"
#include "scene/camera.h"

namespace zz {

// The light signature's test (signature.h): a light shows where it moves the display by
// an 8-bit step. kBoundMargin: how far the tone map's table may stray from its slope.
inline constexpr float kDisplayStep = 1.0f / 255.0f;
inline constexpr float kBoundMargin = 1.1f;

// Per lane, bit `slot` of shows[lane] (set, never cleared): whether adding the slot's
// light to the sample's radiance without it (`colour`, less the light where it reached the
// sample) moves a displayed channel by an 8-bit step or more. The tone map T is concave,
// so with s = T'(colour) and d the radiance between the two ends, T moves by at least s d
// where the light reached (the other end is below: a bound that can say yes) and by at
// most s d where it was blocked (above: one that can say no). Those bounds decide most
// lanes, with kBoundMargin for the tone map's table chords (under 5 % off its slope). A
// slot with a lane left undecided tone-maps the other ends, four lanes at a time, and
// decides all four exactly. Slots from `slots` on hold no light (a scene with fewer lights
// than slots) and are not read.
inline void lights_shown(const ToneMap& tonemap, const Rgb4& colour, const glm::vec3 (*light)[4],
                         const uint32_t shadowed[4], uint32_t shows[4], int slots = kLightSlots) {
  const Rgb4 slope{tonemap.slope4(colour.r), tonemap.slope4(colour.g), tonemap.slope4(colour.b)};
  Rgb4 shown;
  bool tone_mapped = false;
  alignas(16) float cr[4], cg[4], cb[4];
  colour.r.store(cr), colour.g.store(cg), colour.b.store(cb);
  const float4 step(kDisplayStep), above(kDisplayStep * kBoundMargin), below(kDisplayStep / kBoundMargin);
  for (int slot = 0; slot < std::min(slots, kLightSlots); ++slot) {
    alignas(16) float r[4], g[4], b[4], dr[4], dg[4], db[4];
    bool blocked_lane[4], any = false;
    for (int i = 0; i < 4; ++i) {
      const glm::vec3 l = light[slot][i];
      const bool lit = l.r > 0.0f || l.g > 0.0f || l.b > 0.0f;
      const bool blocked = (shadowed[i] >> slot) & 1u;
      any |= lit;
      blocked_lane[i] = blocked;
      // No light: the other end is the colour itself, which never shows.
      const glm::vec3 c(cr[i], cg[i], cb[i]);
      const glm::vec3 other = !lit ? c : blocked ? c + l : glm::max(c - l, glm::vec3(0.0f));
      const glm::vec3 d = glm::abs(other - c);
      r[i] = other.r, g[i] = other.g, b[i] = other.b;
      dr[i] = d.r, dg[i] = d.g, db[i] = d.b;
    }
    if (!any) continue;
    const mask4 brighter =
        _mm_castsi128_ps(int4(-blocked_lane[0], -blocked_lane[1], -blocked_lane[2], -blocked_lane[3]));
    const float4 bound_r = slope.r * float4::load(dr), bound_g = slope.g * float4::load(dg),
                 bound_b = slope.b * float4::load(db);
    const float4 largest = max(max(bound_r, bound_g), bound_b);
    const float4 apart = max(max(float4::load(dr), float4::load(dg)), float4::load(db));
    const mask4 surely = andnot(brighter, largest >= above);  // reached: T moves by at least the bound
    const mask4 never = (brighter & (largest < below)) | (apart <= float4(0.0f));  // blocked: by at most it
    int bits = surely.bits();
    if ((surely | never).bits() != 0xf) {
      if (!tone_mapped) shown = tonemap.apply4(colour), tone_mapped = true;
      const Rgb4 t = tonemap.apply4(Rgb4{float4::load(r), float4::load(g), float4::load(b)});
      // Where the light was blocked, the other end is the brighter one.
      const Rgb4 hi = select(brighter, t, shown), lo = select(brighter, shown, t);
      bits = ((hi.r - lo.r >= step) | (hi.g - lo.g >= step) | (hi.b - lo.b >= step)).bits();
    }
    for (int i = 0; i < 4; ++i) shows[i] |= uint32_t((bits >> i) & 1) << slot;
  }
}

// What the source looks for between a pixel's corners, made once per frame.
struct HiddenDetail {
  bool highlights = false;               // render/specular_peak.h
  bool textures = false;                 // render/texture_detail.h
  bool footprint = false;                // texture_footprint_delta (render/texture_detail.h)
  // Normal steps wider than this are the visibility map's (normal_interpolation_error).
  float step_limit = std::numeric_limits<float>::infinity();
  std::vector<TexturePyramid> pyramids;  // with textures: texture_pyramids(scene)
  std::vector<TextureSpread> normal_spreads;  // with highlights: normal_map_spreads(scene)

  HiddenDetail() = default;
  HiddenDetail(const Scene& scene, const AdaptiveSettings& s)
      : highlights(s.highlights), textures(s.textures), footprint(footprint_applies(s)) {
    if (s.map_crease > 0.0f) step_limit = s.map_crease;
    if (textures) pyramids = texture_pyramids(scene);
    if (highlights) normal_spreads = normal_map_spreads(scene);
  }
};

class SceneSource {
 public:
  // `tonemap`: the display's, which decides where a light could show (signature.h).
  SceneSource(const Shader& shader, const CameraRays& camera, unsigned signature_parts = kSignatureNone,
              const HiddenDetail* detail = nullptr, ToneMap tonemap = {})
      : shader_(shader), camera_(camera), parts_(signature_parts & kSignatureAll), detail_(detail),
        tonemap_(tonemap),
        light_slots_(int(std::min(shader.scene().lights.size(), size_t(kLightSlots)))),
        clip_(shader.clip_in_scene(camera.clip)) {
    view_.origin = camera.origin;
    view_.orthographic = camera.orthographic;
    if (camera.orthographic) {
      view_.forward = camera.dir00;
    } else {
      const glm::vec3 forward = glm::normalize(glm::cross(camera.du, camera.dv));
      view_.forward = glm::dot(forward, camera.dir00) < 0.0f ? -forward : forward;
    }
  }

  Rgb4 sample4(float4 px, float4 py) { return shader_.trace4(camera_rays(px, py), mask4(true), 0, counters, nullptr, clip_); }

  // The signature hashes the enabled parts of what the lane saw; 0 with none enabled.
  Rgb4 sample4(float4 px, float4 py, int4& signature) {
    if (parts_ == kSignatureNone) {
      signature = int4(0);
      return sample4(px, py);
    }
    PathSignature4 seen;
    glm::vec3 light_radiance[kLightSlots][4] = {};
    if (parts_ & kSignatureLights) seen.light_radiance = light_radiance;
    const Rgb4 c = shader_.trace4(camera_rays(px, py), mask4(true), 0, counters, &seen, clip_);
    signature = hash(seen, c);
    return c;
  }

  // With the surfaces the lanes' paths hit, for the hidden-detail flags (aa/hidden_detail.h):
  // the primary hit's and those its reflection and refraction rays see, node[probe_slot(k)]
  // for path-tree node k (render/shader.h).
  struct Probe {
    SurfaceProbe node[kProbeNodes];
    // Node kFootprintNode[k]'s in footprint[k] (render/shader.h); filled only when the
    // footprint correction is on.
    FootprintProbe footprint[kFootprintNodes];
    // Bit k: node[k] has a highlight (has_highlight), set after the sample; the highlight
    // flag reads this one word per corner instead of a line of every node's record.
    uint32_t highlit = 0;
    static_assert(kProbeNodes <= 32);
    const SurfaceProbe& surface() const { return node[0]; }
    // Before a sample: what a node's readers see of a node the path lacks. The primary hit's
    // is read whole (a miss); the others are read only where has_highlight, and a node the
    // shader writes is written whole, so only their highlight needs clearing (the 800-byte
    // record, cleared whole per corner, cost car 3 % of its frame).
    void reset() {
      node[0] = SurfaceProbe{};
      for (int k = 1; k < kProbeNodes; ++k) node[k].specular = glm::vec3(0.0f);
      for (FootprintProbe& f : footprint) f = FootprintProbe{};
    }
  };
  // The shader writes the probes in place; nodes a lane's path lacks keep their defaults.
  Rgb4 sample4(float4 px, float4 py, int4& signature, ProbeLanes<Probe> probes) {
    PathSignature4 seen;
    const bool footprint = detail_ && detail_->footprint;
    for (int i = 0; i < 4; ++i) {
      probes[i].reset();
      seen.probes.lane[i] = probes[i].node;
      if (footprint) seen.footprint.lane[i] = probes[i].footprint;
    }
    glm::vec3 light_radiance[kLightSlots][4] = {};
    if (parts_ & kSignatureLights) seen.light_radiance = light_radiance;
    const Rgb4 c = shader_.trace4(camera_rays(px, py), mask4(true), 0, counters, &seen, clip_);
    signature = parts_ == kSignatureNone ? int4(0) : hash(seen, c);
    for (int i = 0; i < 4; ++i) {
      uint32_t highlit = 0;
      for (int k = 0; k < kProbeNodes; ++k) highlit |= uint32_t(has_highlight(probes[i].node[k])) << k;
      probes[i].highlit = highlit;
    }
    return c;
  }

  // Radiance by which the pixel with corners tl[0], tl[1], tl[stride], tl[stride + 1]
  // (TL, TR, BL, BR, in a grid with a ring around them; `mean` the mean of their radiance)
  // may differ unseen; `visible`: per channel, the smallest increment that could show.
  MissedDetail hidden_radiance(const Probe* tl, ptrdiff_t stride, float4 mean, float4 visible) const {
    if (!detail_) return {};
    const glm::vec3 shown(visible[0], visible[1], visible[2]);
    glm::vec3 h(0.0f), darker(0.0f);
    uint32_t points = 0;
    if (detail_->highlights)
      // Only the nodes with a highlight at all four corners: most have none at some corner.
      for (uint32_t nodes = tl[0].highlit & tl[1].highlit & tl[stride].highlit & tl[stride + 1].highlit; nodes != 0;
           nodes &= nodes - 1) {
        const int k = std::countr_zero(nodes);
        const SurfaceProbe c[4] = {tl[0].node[k], tl[1].node[k], tl[stride].node[k], tl[stride + 1].node[k]};
        const ProbeStencil stencil(&tl->node[k], sizeof(Probe), stride * ptrdiff_t(sizeof(Probe)));
        h += hidden_highlight(shader_.scene(), c, shown, &stencil, detail_->step_limit, &detail_->normal_spreads,
                              &points);
      }
    if (detail_->textures) {
      const SurfaceProbe corners[4] = {tl[0].surface(), tl[1].surface(), tl[stride].surface(), tl[stride + 1].surface()};
      const glm::vec3 t =
          hidden_texture_detail(shader_.scene(), detail_->pyramids, corners, glm::vec3(mean[0], mean[1], mean[2]));
      if (t.r > 0.0f || t.g > 0.0f || t.b > 0.0f) points = kAllLatticePoints;  // anywhere between the corners
      h += t;
      darker = t;
    }
    return {float4(h.r, h.g, h.b, 0.0f), points, float4(darker.r, darker.g, darker.b, 0.0f)};
  }

  // Whether all four corners' primary hits show mostly a reflected or refracted image, or
  // what lies behind a BLEND surface (shows_an_image, scene/materials.h).
  bool specular_corners(const Probe* tl, ptrdiff_t stride) const {
    const Scene& scene = shader_.scene();
    for (const Probe* c : {tl, tl + 1, tl + stride, tl + stride + 1}) {
      const uint32_t m = c->surface().material;
      if (m >= scene.whitted.size() || m >= scene.materials.size() ||
          !shows_an_image(scene.materials[m], scene.whitted[m]))
        return false;
    }
    return true;
  }

  // What the corners' mean lacks of the texture's mean over the pixel (texture_detail.h),
  // on the primary hit and on what the pixel sees in a mirror or through a glass (each
  // footprinted node of the path tree whose four corners reach one textured patch, times
  // the corners' mean weight of the path to it); lane 3 is 1 where the correction applies
  // to some node, 0 elsewhere. `prepared`: footprint_corner of the four corners.
  // `mean`: the corners' mean radiance; a first estimate is kept where it moves the display
  // by less than kFootprintSettledSteps and its samples agree within that (texture_detail.h).
  struct FootprintCorner {
    zz::FootprintCorner node[kFootprintNodes];
  };
  FootprintCorner footprint_corner(const Probe& corner) const {
    FootprintCorner k;
    if (!detail_ || !detail_->footprint) return k;
    for (int n = 0; n < kFootprintNodes; ++n) {
      const FootprintProbe& f = corner.footprint[n];
      if (f.prim < 0) continue;
      k.node[n] = zz::footprint_corner(shader_.scene(), unweighted(corner, n), f);
    }
    return k;
  }
  float4 footprint_delta(const Probe* tl, ptrdiff_t stride, const FootprintCorner* const prepared[4],
                         float4 mean) const {
    if (!detail_ || !detail_->footprint) return float4(0.0f);
    const Probe* const four[4] = {tl, tl + 1, tl + stride, tl + stride + 1};
    const float4 settled = float4(kFootprintSettledSteps / 255.0f) / tonemap_.slope4(mean);
    glm::vec3 delta(0.0f);
    bool applies = false;
    for (int n = 0; n < kFootprintNodes; ++n) {
      const FootprintProbe* const light[4] = {&four[0]->footprint[n], &four[1]->footprint[n],
                                              &four[2]->footprint[n], &four[3]->footprint[n]};
      if (light[0]->prim < 0 || light[1]->prim < 0 || light[2]->prim < 0 || light[3]->prim < 0) continue;
      // Beyond the primary hit, the weight of the path to the node, even over the pixel (to
      // within a quarter): the node's delta is weighed by the corners' mean.
      glm::vec3 weight(1.0f);
      if (n > 0) {
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(0.0f);
        weight = glm::vec3(0.0f);
        for (const FootprintProbe* f : light) {
          weight += 0.25f * f->weight;
          lo = glm::min(lo, f->weight);
          hi = glm::max(hi, f->weight);
        }
        if (!glm::all(glm::lessThanEqual(hi - lo, 0.25f * hi))) continue;
        if (!(std::max(weight.r, std::max(weight.g, weight.b)) > 0.0f)) continue;
      }
      const SurfaceProbe corners[4] = {unweighted(*four[0], n), unweighted(*four[1], n), unweighted(*four[2], n),
                                       unweighted(*four[3], n)};
      const zz::FootprintCorner* const made[4] = {&prepared[0]->node[n], &prepared[1]->node[n],
                                                  &prepared[2]->node[n], &prepared[3]->node[n]};
      // A display step at the camera is a step over the weight at the node.
      const glm::vec3 at_node = glm::vec3(settled[0], settled[1], settled[2]) / glm::max(weight, glm::vec3(1e-30f));
      const FootprintDelta d =
          texture_footprint_delta(shader_.scene(), corners, light, made, at_node, n == 0 ? &view_ : nullptr);
      if (!d.applies) continue;
      applies = true;
      delta += weight * d.delta;
    }
    return float4(delta.r, delta.g, delta.b, applies ? 1.0f : 0.0f);
  }

  RayCounters counters;

 private:
  RayPacket4 camera_rays(float4 px, float4 py) {
    RayPacket4 rays;
    camera_.origins4(px, py, rays.ox, rays.oy, rays.oz);
    camera_.directions4(px, py, rays.dx, rays.dy, rays.dz);
    rays.tmax = float4(kInfinity);
    counters.primary += 4;
    return rays;
  }

  // Footprinted node n's surface probe as its own shading sees it: the probes' specular
  // carries the path's weight (for the highlight flag), the footprint's model does not.
  static SurfaceProbe unweighted(const Probe& corner, int n) {
    SurfaceProbe c = corner.node[probe_slot(kFootprintNode[n])];
    if (n == 0) return c;
    const glm::vec3 w = corner.footprint[n].weight;
    for (int i = 0; i < 3; ++i) c.specular[i] = w[i] > 0.0f ? c.specular[i] / w[i] : 0.0f;
    return c;
  }

  int4 hash(const PathSignature4& seen, const Rgb4& colour) const {
    alignas(16) int32_t s[4];
    uint32_t shadowed[4] = {}, shows[4] = {};
    if (parts_ & kSignatureLights) {
      for (int i = 0; i < 4; ++i) shadowed[i] = fold_to_slots(seen.shadowed[i]);
      lights_shown(tonemap_, colour, seen.light_radiance, shadowed, shows, light_slots_);
    }
    for (int i = 0; i < 4; ++i) {
      uint32_t h = 0;
      if (parts_ & kSignatureObject) h = signature_mix(h, seen.object[i]);
      if (parts_ & kSignatureSecondary) h = signature_mix(signature_mix(h ^ 0x53454344u, seen.reflected[i]), seen.refracted[i]);
      s[i] = make_signature(h >> (32 - kWhatBits), shows[i], shadowed[i]);
    }
    return int4(s[0], s[1], s[2], s[3]);
  }


  const Shader& shader_;
  const CameraRays& camera_;
  unsigned parts_;
  const HiddenDetail* detail_;
  ToneMap tonemap_;
  int light_slots_;  // the slots the scene's lights fold onto (fold_to_slots)
  const CameraClip* clip_;  // the camera's planes where they cut into the scene, else null
  FootprintView view_;  // the camera, for the footprint's samples on the primary hit
};

static_assert(SignedSampleSource<SceneSource>);
static_assert(HiddenDetailSource<SceneSource>);
static_assert(FootprintSource<SceneSource>);

}  // namespace zz
