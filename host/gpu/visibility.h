// The visibility map (ALGORITHM.md §7): the scene rasterised at S x S supersamples per
// pixel into triangle ids, then a compute shader flags pixels whose samples (plus a
// one-sample ring) show a geometric discontinuity, and which way it runs. One byte per pixel
// in a GeoMap (core/geo_map.h).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geo_map.h"
#include "core/tile.h"
#include "gpu/device.h"
#include "gpu/shaders.h"
#include "gpu/resources.h"
#include "scene/camera.h"
#include "scene/scene.h"
#include "shaders/visibility_shared.h"

namespace zz {

struct VisibilitySettings {
  int supersample = 4;            // S per axis: 4 normal, 6 high quality
  float normal_angle_deg = 25.0f; // camera-facing geometric normals further apart flag
  float depth_rel = 0.02f;        // |t_a - t_b| > depth_rel * min(t_a, t_b) flags
  // Samples on different materials flag too (ours, beyond §7): material boundaries on
  // flat surfaces (a checker floor), whose sub-pixel tips no corner sees.
  bool material_edges = false;
  // Budget for one tile, in supersamples (8 bytes each: the id attachment, which the
  // compute pass reads directly, and depth); larger frames are split into bands / tiles.
  int64_t max_tile_samples = int64_t(32) << 20;
  // Frames above this many supersamples are split into about eight bands (kBandsPerFrame) even
  // within the budget: on a CPU device the targets are fresh memory whose first touch
  // (page faults) costs about as much as the raster, and a band's targets serve the next
  // band already mapped (room 1024^2: the map 0.29 -> 0.25 s). Each band is one more vertex
  // pass over the scene, hence a floor on the band (raised for large scenes: band_floor)
  // and a bound on their number.
  int64_t min_band_samples = int64_t(2) << 20;
  // Largest tile image side in supersamples, ring included; 0 = the device's limits.
  int max_tile_dim = 0;
  // Work groups (ZZ_PLANE_GROUP triangles each) per dispatch of the per-frame planes pass;
  // 0 = maxComputeWorkGroupCount[0] (65535 on lavapipe: 4.2 M triangles a dispatch).
  int max_plane_groups = 0;
};

struct VisibilityTimings {
  double upload_s = 0;    // one-off scene upload at construction
  double raster_s = 0;    // GPU time (timestamps) of all tiles' raster passes
  double compute_s = 0;   // GPU time of the per-frame triangle planes + all flag dispatches
  double readback_s = 0;  // host time to unpack the flags into the GeoMap
  double total_s = 0;     // host wall time of run()
  int tiles = 0;
};

// Whether the raster draws the triangle. Not where its material is alpha-BLEND: what a
// blended surface shows is mostly what lies behind it (vase's glass at alpha 0.3), and the
// ray tracer's continuation ray sees those edges, so the map must too; the blended
// surface's own outline differs in colour or object signature from what surrounds it, which
// level 1 compares (vase FLIP 1.587 -> 1.560x the lattice's for +0.04 rays/px at 1024^2).
// Nor where it is alpha-MASK with a factor below the cutoff: invisible to every ray. A
// textured MASK (foliage) is drawn whole: the map sees its quads' outlines, not the
// cut-outs' (known limit; no alpha test in the raster).
bool seen_by_map(const Scene& scene, size_t triangle);
// The triangle's material index as the flag rule compares it (w of geometric_normals).
float material_tag(const Scene& scene, size_t triangle);
// Unit geometric normals, one per triangle, exactly as uploaded (zero if degenerate), with
// the triangle's material_tag in w.
std::vector<glm::vec4> geometric_normals(const Scene& scene);

// The compute pass's per-frame constants (tile left zero): the sample rays and the
// thresholds exactly as the shader sees them. Public so tests can mirror the rule.
gpu::FlagPush make_flag_push(const Camera& camera, int width, int height,
                             const VisibilitySettings& settings);

class VisibilityPass {
 public:
  // Uploads the scene's triangles and their geometric planes once.
  VisibilityPass(VulkanContext& context, const Scene& scene);
  ~VisibilityPass();
  VisibilityPass(const VisibilityPass&) = delete;
  VisibilityPass& operator=(const VisibilityPass&) = delete;

  // The frame's map. With `region` (pixels, clamped to the frame) only those pixels are
  // flagged, the rest of the map is 0: the same tiles, projection and viewport as the
  // whole frame, the raster limited by the scissor, so the flags inside are bit for bit
  // those of the full map. A caller rendering a sub-rectangle passes the pixels its
  // sampler reads (adaptive_geo_reads in aa/adaptive_sampler.h). With `cancel` (the
  // viewer), each band is its own submission and a cancel seen at a band's start returns an
  // empty map; without, the map is one submission.
  GeoMap run(const Camera& camera, int width, int height, const VisibilitySettings& settings = {},
             VisibilityTimings* timings = nullptr, const std::optional<TileRect>& region = std::nullopt,
             const std::atomic<bool>* cancel = nullptr);

  // Allocates (and on a CPU device touches) what run() needs for a frame of this size,
  // these settings and this region: the tile targets, the flag buffer (the region's rows
  // only) and the flag pipeline. Optional: run() does it itself when needed; calling it
  // ahead keeps that one-off work (allocation, first-touch page faults, pipeline creation)
  // out of run()'s time. Invalid settings are left for run() to report.
  void prepare(int width, int height, const VisibilitySettings& settings = {},
               const std::optional<TileRect>& region = std::nullopt, bool orthographic = false);

  // The raw supersampled id image with its one-sample ring, (width*S + 2) x (height*S + 2)
  // row-major: entry [(gy + 1) * (width*S + 2) + gx + 1] is the triangle index + 1
  // (0 = background) seen at image point ((gx + 0.5)/S, (gy + 0.5)/S), gx in [-1, width*S].
  // Supersample (i, j) of pixel (x, y) is gx = x*S + i, gy = y*S + j. For tests.
  std::vector<uint32_t> render_ids(const Camera& camera, int width, int height,
                                   const VisibilitySettings& settings = {});

  double upload_seconds() const { return upload_s_; }

  // Memory the constructor takes for a scene of this many triangles, at its peak: the
  // device buffers (positions, first vertices, normals, planes: 96 bytes per triangle;
  // on lavapipe host memory) with, while they upload, the host copies (80) and the
  // largest staging buffer (48).
  static uint64_t scene_bytes(size_t triangles) { return uint64_t(96 + 80 + 48) * std::max<size_t>(triangles, 1); }

  // Device memory run() allocates for a frame (on lavapipe: host memory): the tile's id
  // and depth attachments (8 bytes per supersample, the tile plan of run()) plus the flag
  // buffer the map is read back from (one 32-bit word per 4 pixels of the region). Known
  // before any device exists: the tile plan without the device's image limits, whose
  // narrower tiles are taller and hold as many samples within a row of the budget.
  static uint64_t frame_bytes(int width, int height, const VisibilitySettings& settings, size_t triangles,
                              const std::optional<TileRect>& region = std::nullopt);

  // Throws the zz::Error a frame's map would throw part-way through it (a scene of more
  // triangles, or a region of more flags, than one storage binding of `context` holds),
  // before any of the frame's work: a 12000^2 frame was refused after 3.5 s and 2.4 GB.
  static void check_fits(const VulkanContext& context, size_t triangles, int width, int height,
                         const std::optional<TileRect>& region = std::nullopt);

  // The fewest supersamples a band of a frame holds for a scene of this many triangles:
  // min_band_samples, or more where a band's vertex pass would cost more than its targets'
  // first touch saves (lavapipe, 2 cores: ~28 ns a triangle a pass against ~2.7 ns a
  // sample: 16 samples a triangle leaves a margin; ToyCar's 109 k stay at 2 M).
  static int64_t band_floor(const VisibilitySettings& settings, size_t triangles) {
    return std::max<int64_t>(settings.min_band_samples, int64_t(16) * int64_t(std::min<size_t>(triangles, size_t(1) << 40)));
  }

 private:
  // Tile width and height in pixels for a frame: the raster's memory budget, and the
  // device's image, framebuffer and viewport limits (max_dim; settings.max_tile_dim first).
  static std::pair<int, int> tile_size(int width, int height, const VisibilitySettings& settings, int max_dim,
                                       size_t triangles);
  std::pair<int, int> tile_size(int width, int height, const VisibilitySettings& settings) const;
  // The id target's width for tiles `tile_w` pixels wide: their samples and ring, padded to
  // whole flag words, since the flag shader loads every sample row of a word's 4 pixels
  // (those beyond the tile only feed pixels it does not flag, but stay inside the image).
  static uint32_t target_width(int tile_w, int s) {
    return uint32_t((tile_w + ZZ_PIXELS_PER_WORD - 1) / ZZ_PIXELS_PER_WORD * ZZ_PIXELS_PER_WORD * s + 2);
  }
  static constexpr VkFormat kIdFormat = VK_FORMAT_R32_UINT;
  static constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;  // reverse-Z
  struct Tile {
    int x, y, w, h;  // pixels
  };
  struct Frame;
  Frame plan(const Camera& camera, int width, int height, const VisibilitySettings& settings) const;
  void ensure_targets(uint32_t width, uint32_t height);
  void ensure_flags(VkDeviceSize bytes);
  void create_pipelines();  // visibility_pipelines.cpp
  // The id raster with `vertex_shader` (ids.vert, with or without the clip planes).
  VkPipeline make_raster_pipeline(ShaderCode vertex_shader);  // visibility_pipelines.cpp
  // The raster that clips at the camera's planes, made on first use.
  VkPipeline raster_clip_pipeline();  // visibility_pipelines.cpp
  void destroy_objects() noexcept;  // the pipelines, layouts, descriptors and queries made so far
  // The flag pipeline specialised for S, made on first use.
  VkPipeline flag_pipeline(int s, bool orthographic);  // visibility_pipelines.cpp
  // Rasterises `tile` with its own projection; only `area` (pixels inside the tile) and
  // its one-sample ring are cleared and drawn (scissor), the viewport stays the tile's.
  void record_raster(VkCommandBuffer cmd, const Frame& frame, const Tile& tile, const Tile& area);
  // Copies the tile's id image (ring included, rows tightly packed) into `dst`.
  void record_id_copy(VkCommandBuffer cmd, const Tile& tile, VkBuffer dst);
  void bind_descriptors();

  VulkanContext& context_;
  size_t triangles_ = 0;
  glm::vec3 bounds_min_{0.0f}, bounds_max_{0.0f};
  double upload_s_ = 0;
  Buffer positions_;       // vec4 per vertex: the raster's vertex input
  Buffer first_vertices_;  // vec4 per triangle: its first vertex, for the planes pass
  Buffer normals_;    // vec4 per triangle: unit geometric normal
  Buffer planes_;     // vec4 per triangle: normal, n.(v0 - camera), rewritten per frame
  Buffer flags_;      // packed flag words of the last frame (host-visible)
  Buffer id_readback_;  // render_ids' host copy
  int frame_s_ = 4;
  Image ids_;         // R32_UINT colour target and storage image, reused by all tiles and frames
  Image depth_;       // D32_SFLOAT, reverse-Z
  VkPipelineLayout raster_layout_ = VK_NULL_HANDLE;
  VkPipeline raster_pipeline_ = VK_NULL_HANDLE;
  VkPipeline raster_clip_pipeline_ = VK_NULL_HANDLE;
  VkShaderModule flag_module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout flag_set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout flag_layout_ = VK_NULL_HANDLE;  // both compute passes
  VkPipeline plane_pipeline_ = VK_NULL_HANDLE;
  std::map<std::pair<int, bool>, VkPipeline> flag_pipelines_;  // by S and camera type
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkDescriptorSet flag_set_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  uint32_t query_capacity_ = 0;
};

}  // namespace zz
