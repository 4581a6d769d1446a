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

#include <limits>
#include <vector>

#include "accel/bvh.h"
#include "core/color.h"
#include "render/footprint_probe.h"
#include "render/lighting4.h"
#include "render/ray_counters.h"
#include "render/specular_peak.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace zz {

// What four camera rays see first: the data of the depth, normal and albedo AOVs
// (render/primary_hits.h). The same surface the shader lights: alpha cut-outs are passed
// through, a BLEND surface with coverage > 0 counts as hit.
struct PrimaryHit4 {
  float depth[4];       // distance from the ray origin to the hit (directions are unit); +inf on a miss
  glm::vec3 normal[4];  // shading normal (normal map applied), world space, turned to the ray; 0 on a miss
  glm::vec3 albedo[4];  // base colour: glTF baseColorFactor x baseColorTexture (linear); 0 on a miss
};

// The path tree of a camera ray, as far as the highlight flag follows it: node 0 is the
// primary hit, and the reflection ray of node k hits node 2k + 1, its refraction ray node
// 2k + 2 (depth d holds nodes 2^d - 1 .. 2^(d+1) - 2). The flag probes the primary hit,
// what it reflects and refracts, what its reflection reflects and refracts (a highlight on
// a glass seen in a mirror, on chrome seen in the car's paint), and the whole refraction
// subtree to depth 3: a highlight on the far side of a thick glass, seen through both of
// its walls, is three or four surfaces from the camera. At 1024² (display RMSE x the
// lattice's): nodes 3-4 took glass 1.224 -> 1.192 and car 1.154 -> 1.137 for +0.004 and
// +0.003 rays/px; node 5 took vase 1.674 -> 1.567 for +0.007; the refraction's depth-2
// and depth-3 nodes (6, 11-14) took vase 1.500 -> 1.129 for +0.098 rays/px (car +0.041,
// glass +0.0004), and no node alone gave more than a fifth of that. The reflection's
// depth-3 nodes (7-10) added rays and removed nothing, and are left out.
inline constexpr int kPathTreeNodes = 15;  // to depth 3
inline constexpr int kProbeNodes = 11;     // the nodes probed, each in a slot of its own
constexpr int reflected_node(int k) { return 2 * k + 1; }
constexpr int refracted_node(int k) { return 2 * k + 2; }
// The slot of tree node k in a lane's probes; -1 where the flag does not follow the path.
constexpr int probe_slot(int node) {
  constexpr int slot[kPathTreeNodes] = {0, 1, 2, 3, 4, 5, 6, -1, -1, -1, -1, 7, 8, 9, 10};
  return node >= 0 && node < kPathTreeNodes ? slot[node] : -1;
}
constexpr bool probed(int node) { return probe_slot(node) >= 0; }

// Where a camera packet's path-tree probes go: probed node k of lane i is at(k, i), in
// slot probe_slot(k) of lane i's probes, contiguous from lane[i] (the caller's per-corner
// records, written in place).
struct ProbeTree {
  SurfaceProbe* lane[4] = {};
  SurfaceProbe& at(int node, int i) const { return lane[i][probe_slot(node)]; }
  explicit operator bool() const { return lane[0] != nullptr; }
};

// The path-tree nodes whose textures the footprint correction (render/texture_detail.h)
// integrates over the pixel: the primary hit, what its reflection and refraction rays hit,
// and what the refraction's refraction hits and the one after it (what a glass shows
// through its two walls, and a thick glass through four).
inline constexpr int kFootprintNodes = 5;
inline constexpr int kFootprintNode[kFootprintNodes] = {0, 1, 2, 6, 14};
// The slot of tree node k in a lane's footprint probes; -1 where the correction does not follow.
constexpr int footprint_slot(int node) {
  for (int slot = 0; slot < kFootprintNodes; ++slot)
    if (kFootprintNode[slot] == node) return slot;
  return -1;
}
constexpr bool footprinted(int node) { return footprint_slot(node) >= 0; }
// The shader reaches a footprinted node by walking the probed subtree (and reads the
// node's surface probe): each must be probed.
static_assert([] {
  for (int node : kFootprintNode)
    if (!probed(node)) return false;
  return true;
}());

// Where a camera packet's footprint probes go: node k of lane i is at(k, i), in slot
// footprint_slot(k) of lane i's probes, contiguous from lane[i].
struct FootprintLanes {
  FootprintProbe* lane[4] = {};
  FootprintProbe& at(int node, int i) const { return lane[i][footprint_slot(node)]; }
  explicit operator bool() const { return lane[0] != nullptr; }
};

// What each lane of a camera packet saw, for the sample signatures (aa/signature.h):
// indices + 1 of the materials hit (0 = nothing: background, or no such ray).
struct PathSignature4 {
  uint32_t object[4] = {};     // the primary hit
  uint32_t shadowed[4] = {};   // bit l % 32: light l's shadow ray was blocked or attenuated
  uint32_t blocked[4] = {};    // bit l % 32: light l's shadow ray passed nothing
  // Where the caller wants it (a camera packet only): [l % kLightSlots][lane], the largest
  // unshadowed contribution (linear RGB, per channel) of the lights in that slot.
  glm::vec3 (*light_radiance)[4] = nullptr;
  // The first hit of the primary hit's reflection ray, combined with what that hit's own
  // reflection ray hits where that path keeps at least half the light (a mirror in a mirror).
  uint32_t reflected[4] = {};
  uint32_t refracted[4] = {};  // the first two hits along its refraction rays, combined
  // Where the caller wants them (a camera packet only): probes.at(k, lane), the surface of node
  // k of each lane's path tree (probe_nodes below) for the highlight flag, its specular
  // scaled by the path's weight from the camera and by Beer's absorption along it: the
  // highlight radiance it may send to the camera. Left as they were where the lane's path
  // has no such node; specular 0 where the node's ray hits nothing.
  ProbeTree probes;
  int node = 0;  // this packet's node of the tree
  // Where the caller wants them (a camera packet only): per lane, the data of the footprinted
  // nodes of its path tree for the texture footprint correction (render/texture_detail.h),
  // each with the weight of the path that reached it. Left as they were where the lane's
  // path has no such node.
  FootprintLanes footprint;
};

class Shader {
 public:
  Shader(const Scene& scene, const Bvh& bvh);

  // Radiance arriving along the active lanes' rays (inactive lanes return 0).
  // `depth` counts the bounces already taken: 0 for camera rays.
  // `signature`, if given (zero-initialised), receives what the lanes saw: integer
  // bookkeeping only, the same rays are traced either way.
  // `clip` (clip_in_scene), for camera rays (depth 0), applies the camera's clipping planes.
  Rgb4 trace4(const RayPacket4& rays, mask4 active, int depth, RayCounters& counters,
              PathSignature4* signature = nullptr, const CameraClip* clip = nullptr) const {
    return (this->*kernel_)(rays, active, depth, 0, float4(1.0f), Media{}, counters, signature,
                            depth == 0 ? clip : nullptr);
  }

  // Throughput cutoff: a reflected or refracted ray is spawned only while the path's
  // throughput (the product of the mirror/Fresnel/transmission weights so far, largest
  // channel) stays at or above this. Fresnel splits at glass then form a tree whose
  // weights sum to at most 1 per bounce, so at most 1/kMinThroughput rays per bounce level
  // survive whatever the trace depth: --max-depth 16 on glass stays bounded instead of
  // 2^16 rays per pixel. Contributions below 1/1024 of the radiance are far below one
  // 8-bit display step for the scenes' own depths (the reference-image tests hold them).
  static constexpr float kMinThroughput = 1.0f / 1024.0f;

  // The first surface along each ray of a full packet, without shading it: no light,
  // shadow or secondary rays (only cut-out continuations, counted in `counters`).
  void primary4(const RayPacket4& rays, PrimaryHit4& out, RayCounters& counters, const CameraClip* clip = nullptr) const {
    (this->*primary_kernel_)(rays, out, counters, clip);
  }

  // `clip` if its planes can cut anything in the scene (its bounds' depths), else null: the
  // `clip` to pass to trace4 and primary4, so a camera whose planes enclose the scene costs
  // nothing per ray.
  const CameraClip* clip_in_scene(const CameraClip& clip) const {
    return clip.cuts_into(scene_bounds_.lo, scene_bounds_.hi) ? &clip : nullptr;
  }

  const EffectSet& effects() const { return effects_; }
  const Scene& scene() const { return scene_; }

  // Bits of the kernel specialisation.
  enum : unsigned { kShadows = 1, kReflection = 2, kRefraction = 4, kTextures = 8, kAlpha = 16, kAllEffects = 31 };

 private:
  // What each lane's ray travels through: the material of the volume it is inside (-1:
  // none, air) and of the volume around that one. Refraction enters and leaves volumes by
  // it: the index ratio at an interface is that of the two media, and Beer-Lambert takes
  // the medium a segment crossed, also where it ends on an object inside a volume.
  struct Media {
    int inside[4] = {-1, -1, -1, -1};
    int outside[4] = {-1, -1, -1, -1};
  };

  // `blend_layers` counts the BLEND surfaces already seen through along this ray.
  template <unsigned kEffects>
  Rgb4 trace4_impl(const RayPacket4& rays, mask4 active, int depth, int blend_layers, float4 throughput,
                   const Media& media, RayCounters& counters, PathSignature4* signature,
                   const CameraClip* clip = nullptr) const;

  // The kernel's stages, in the order trace4_impl runs them on one packet's hits (Hits4).
  struct Hits4;
  template <unsigned kEffects>
  void shade_surfaces(const RayPacket4& rays, int active_bits, const Media& media, PathSignature4* signature,
                      Hits4& h) const;
  template <unsigned kEffects>
  void add_direct_light(Hits4& h, RayCounters& counters, PathSignature4* signature) const;
  template <unsigned kEffects>
  int add_reflection_and_refraction(Hits4& h, int depth, int blend_layers, float4 throughput, RayCounters& counters,
                                    PathSignature4* signature) const;
  void absorb_along_segment(Hits4& h, PathSignature4* signature) const;
  template <unsigned kEffects>
  void blend_over_behind(Hits4& h, int refracted_lanes, int depth, int blend_layers, float4 throughput,
                         RayCounters& counters, PathSignature4* signature, const CameraClip* clip) const;

  using Kernel = Rgb4 (Shader::*)(const RayPacket4&, mask4, int, int, float4, const Media&, RayCounters&,
                                  PathSignature4*, const CameraClip*) const;
  template <unsigned... kE>
  static Kernel pick_kernel(unsigned effects, std::integer_sequence<unsigned, kE...>);

  template <bool kTextured, bool kSeeThrough>
  void primary4_impl(const RayPacket4& rays, PrimaryHit4& out, RayCounters& counters, const CameraClip* clip) const;
  using PrimaryKernel = void (Shader::*)(const RayPacket4&, PrimaryHit4&, RayCounters&, const CameraClip*) const;

  const Scene& scene_;
  const Bvh& bvh_;
  EffectSet effects_;
  Scene::Bounds scene_bounds_;  // the triangles' box, for clip_in_scene
  std::vector<LightConstants> light_constants_;  // per scene light, made once for the SoA light loop
  // Per material, the bounds of its triangles (widened by their rounding), for volumes
  // only: a ray "inside" a volume whose hit lies outside its bounds went through an open
  // surface (a pane modelled as one sheet) and is in air again.
  struct VolumeBounds {
    glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
    bool contains(const glm::vec3& p) const {
      return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
    }
  };
  std::vector<VolumeBounds> volume_bounds_;
  Kernel kernel_;
  PrimaryKernel primary_kernel_;
};

// Exact unpolarised Fresnel reflectance of a dielectric interface for cos_i >= 0 and
// relative index eta = n_incident / n_transmitted; 1 on total internal reflection.
float fresnel_dielectric(float cos_i, float eta);
// cos of the refracted angle by Snell's law (eta = n_incident / n_transmitted), or -1 for
// total internal reflection, which eta <= 1 never gives.
float cos_transmitted(float cos_i, float eta);

}  // namespace zz
