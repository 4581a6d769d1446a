#include "gpu/visibility.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <limits>
#include <mutex>

#include "core/error.h"

namespace zz {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Once per process: a camera's planes cut into the scene and the device cannot clip.
void warn_cannot_clip() {
  static std::once_flag once;
  std::call_once(once, [] {
    std::fprintf(stderr,
                 "zigzag: warning: the Vulkan device cannot clip (no shaderClipDistance): the visibility map "
                 "also draws what the camera's znear/zfar cut away, so it sends rays to those edges too; the "
                 "image is clipped all the same\n");
  });
}

}  // namespace

// Everything one run() needs besides the tiles' own offsets.
struct VisibilityPass::Frame {
  int width = 0, height = 0, s = 4;
  // Pinhole: q = t * (dir00 + px du + py dv)  ->  (t px, t py, t);
  // orthographic: q = px ou + py ov + t dir00  ->  (px, py, t).
  glm::dmat3 view_from_ray;
  glm::vec3 origin{0.0f};
  bool orthographic = false;
  double znear = 1e-6;       // pinhole, in units of t (the forward component: t = depth)
  double zfar = 0.0;         // orthographic: the depth range [0, zfar] holds the scene
  CameraClip clip;           // the camera's planes, where they cut into the scene; else none
  gpu::FlagPush flag{};
  std::vector<Tile> tiles;
  uint32_t image_w = 0, image_h = 0;  // largest tile image, ring included
};

// The pixels a run flags (the region clamped to the frame, or the whole frame) and the
// flag buffer's rectangle: those pixels widened to whole flag words (the extra pixels are
// flagged exactly too). The buffer holds these rows only, so a region of a frame too big
// for one storage buffer still fits (a farm's 16384^2 frame: 256 MiB of flags).
struct FlagArea {
  TileRect want, buffer;
  int words_per_row() const { return buffer.width() / ZZ_PIXELS_PER_WORD + (buffer.width() % ZZ_PIXELS_PER_WORD != 0); }
  VkDeviceSize bytes() const { return VkDeviceSize(words_per_row()) * VkDeviceSize(buffer.height()) * sizeof(uint32_t); }
};

// The compute passes bind one vec4 per triangle (at least one) as a storage buffer each.
VkDeviceSize triangle_record_bytes(size_t triangles) {
  return VkDeviceSize(std::max<size_t>(triangles, 1)) * sizeof(glm::vec4);
}

constexpr const char* kTooManyTriangles = "render with --edges off";
constexpr const char* kTooManyFlags = "render a smaller frame, in regions (--region), or with --edges off";

// Throws zz::Error naming `what` and `remedy` when `bytes` exceed one storage-buffer
// binding (maxStorageBufferRange).
void check_storage_range(const VulkanContext& context, VkDeviceSize bytes, const std::string& what,
                         const char* remedy) {
  const VkDeviceSize range = context.properties().limits.maxStorageBufferRange;
  if (bytes > range)
    throw Error("visibility map: " + what + " need a storage buffer of " + std::to_string(bytes >> 20) +
                " MiB, the Vulkan device binds at most " + std::to_string(range >> 20) + " MiB; " + remedy);
}

FlagArea flag_area(int width, int height, const std::optional<TileRect>& region) {
  FlagArea a;
  a.want = {0, 0, width, height};
  if (region) {
    a.want = {std::clamp(region->x0, 0, width), std::clamp(region->y0, 0, height), std::clamp(region->x1, 0, width),
              std::clamp(region->y1, 0, height)};
    if (a.want.width() <= 0 || a.want.height() <= 0) return {};  // empty: nothing to flag
  }
  a.buffer = {a.want.x0 / ZZ_PIXELS_PER_WORD * ZZ_PIXELS_PER_WORD, a.want.y0,
              std::min(width, (a.want.x1 + ZZ_PIXELS_PER_WORD - 1) / ZZ_PIXELS_PER_WORD * ZZ_PIXELS_PER_WORD), a.want.y1};
  return a;
}

float material_tag(const Scene& scene, size_t triangle) {
  const uint32_t m = triangle < scene.material_of.size() ? scene.material_of[triangle] : 0u;
  return float(m % (1u << 24));  // exact in a float; materials 2^24 apart share a tag
}

bool seen_by_map(const Scene& scene, size_t triangle) {
  if (triangle >= scene.material_of.size()) return true;
  const uint32_t m = scene.material_of[triangle];
  if (m >= scene.materials.size()) return true;
  const Material& mat = scene.materials[m];
  // MASK below its cutoff everywhere (texels only lower the factor's alpha): no ray sees it.
  const bool never_covers = mat.alpha_mode == AlphaMode::Mask && mat.base_alpha < mat.alpha_cutoff;
  return mat.alpha_mode != AlphaMode::Blend && !never_covers;
}

std::vector<glm::vec4> geometric_normals(const Scene& scene) {
  size_t n = scene.positions.size() / 3;
  std::vector<glm::vec4> normals(n, glm::vec4(0.0f));
  for (size_t t = 0; t < n; ++t) {
    glm::dvec3 v0(scene.positions[3 * t]), v1(scene.positions[3 * t + 1]), v2(scene.positions[3 * t + 2]);
    glm::dvec3 c = glm::cross(v1 - v0, v2 - v0);
    double len = glm::length(c);
    // Degenerate triangles keep a zero normal: any pair with one flags (cos 0 < limit).
    if (len > 0.0) normals[t] = glm::vec4(glm::vec3(c / len), 0.0f);
    normals[t].w = material_tag(scene, t);
  }
  return normals;
}

gpu::FlagPush make_flag_push(const Camera& camera, int width, int height,
                             const VisibilitySettings& settings) {
  CameraRays rays(camera, width, height);
  float s = float(settings.supersample);
  gpu::FlagPush p{};
  // Supersample (gx, gy) sits at image point ((gx + 0.5)/S, (gy + 0.5)/S).
  if (rays.orthographic) {  // the origins step, the direction stays (limits.w)
    glm::vec3 ou = rays.ou / s, ov = rays.ov / s;
    p.origin = rays.origin + 0.5f * ou + 0.5f * ov;
    p.dir00 = rays.dir00;
    // The depth rule's scale (geo_flags.comp far_apart): the view's height, as a pinhole's
    // depth is its view's height there up to the field of view's tangent.
    p.du = glm::vec4(ou, glm::length(rays.ov) * float(height));
    p.dv = glm::vec4(ov, 0.0f);
  } else {
    glm::vec3 du = rays.du / s, dv = rays.dv / s;
    p.origin = rays.origin;
    p.dir00 = rays.dir00 + 0.5f * du + 0.5f * dv;
    p.du = glm::vec4(du, 0.0f);
    p.dv = glm::vec4(dv, 0.0f);
  }
  p.frame = glm::ivec4(width, height, settings.supersample,
                       (width + ZZ_PIXELS_PER_WORD - 1) / ZZ_PIXELS_PER_WORD);
  p.limits = glm::vec4(std::cos(double(settings.normal_angle_deg) * M_PI / 180.0), settings.depth_rel,
                       settings.material_edges ? 1.0f : 0.0f, rays.orthographic ? 1.0f : 0.0f);
  return p;
}

VisibilityPass::VisibilityPass(VulkanContext& context, const Scene& scene) : context_(context) {
  auto t0 = Clock::now();
  triangles_ = scene.positions.size() / 3;
  std::vector<glm::vec4> positions(std::max<size_t>(3 * triangles_, 1), glm::vec4(0.0f));
  std::vector<glm::vec4> normals = geometric_normals(scene);
  normals.resize(std::max<size_t>(triangles_, 1), glm::vec4(0.0f));
  check_storage_range(context_, triangle_record_bytes(triangles_), std::to_string(triangles_) + " triangles",
                      kTooManyTriangles);
  std::vector<glm::vec4> first_vertices(normals.size(), glm::vec4(0.0f));
  if (triangles_ > 0) bounds_min_ = bounds_max_ = scene.positions[0];
  for (size_t t = 0; t < triangles_; ++t) {
    // A triangle the map does not see is drawn as a point, which covers no sample; its id
    // stays reserved, so every other triangle keeps the id the ray tracer gives it.
    const bool seen = seen_by_map(scene, t);
    for (int k = 0; k < 3; ++k) {
      glm::vec3 p = scene.positions[3 * t + (seen ? k : 0)];
      positions[3 * t + k] = glm::vec4(p, 1.0f);
      bounds_min_ = glm::min(bounds_min_, p);
      bounds_max_ = glm::max(bounds_max_, p);
    }
    first_vertices[t] = positions[3 * t];
  }
  VkMemoryPropertyFlags local = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  positions_ = create_buffer(context_, positions.size() * sizeof(glm::vec4),
                             VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, 0, local);
  first_vertices_ = create_buffer(context_, first_vertices.size() * sizeof(glm::vec4),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, 0, local);
  normals_ = create_buffer(context_, normals.size() * sizeof(glm::vec4),
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, 0, local);
  upload(context_, positions_, positions.data(), positions.size() * sizeof(glm::vec4));
  upload(context_, first_vertices_, first_vertices.data(), first_vertices.size() * sizeof(glm::vec4));
  upload(context_, normals_, normals.data(), normals.size() * sizeof(glm::vec4));
  planes_ = create_buffer(context_, normals.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, local);
  try {
    create_pipelines();
  } catch (...) {
    destroy_objects();  // the destructor does not run for a constructor that throws
    throw;
  }
  upload_s_ = seconds_since(t0);
}

VisibilityPass::~VisibilityPass() {
  context_.wait_idle_noexcept();
  destroy_objects();
}

void VisibilityPass::destroy_objects() noexcept {
  VkDevice d = context_.device();
  if (queries_) vkDestroyQueryPool(d, queries_, nullptr);
  if (descriptor_pool_) vkDestroyDescriptorPool(d, descriptor_pool_, nullptr);
  for (auto& [s, pipeline] : flag_pipelines_) vkDestroyPipeline(d, pipeline, nullptr);
  if (plane_pipeline_) vkDestroyPipeline(d, plane_pipeline_, nullptr);
  if (flag_module_) vkDestroyShaderModule(d, flag_module_, nullptr);
  if (flag_layout_) vkDestroyPipelineLayout(d, flag_layout_, nullptr);
  if (flag_set_layout_) vkDestroyDescriptorSetLayout(d, flag_set_layout_, nullptr);
  if (raster_pipeline_) vkDestroyPipeline(d, raster_pipeline_, nullptr);
  if (raster_clip_pipeline_) vkDestroyPipeline(d, raster_clip_pipeline_, nullptr);
  if (raster_layout_) vkDestroyPipelineLayout(d, raster_layout_, nullptr);
}

VisibilityPass::Frame VisibilityPass::plan(const Camera& camera, int width, int height,
                                           const VisibilitySettings& settings) const {
  if (width <= 0 || height <= 0) throw Error("visibility map: empty frame size");
  if (settings.supersample < 1 || settings.supersample > ZZ_MAX_SUPERSAMPLE)
    throw Error("visibility map: supersampling must be 1..16, got " + std::to_string(settings.supersample));
  Frame f;
  f.width = width;
  f.height = height;
  f.s = settings.supersample;
  CameraRays rays(camera, width, height);
  f.origin = rays.origin;
  f.orthographic = rays.orthographic;
  // Columns du, dv, dir00: a point q = M (t px, t py, t); its inverse projects exactly
  // like CameraRays, even for a slightly non-orthonormal camera basis. Orthographic:
  // columns ou, ov, dir00 and q = M (px, py, t).
  glm::dmat3 m(glm::dvec3(rays.orthographic ? rays.ou : rays.du), glm::dvec3(rays.orthographic ? rays.ov : rays.dv),
               glm::dvec3(rays.dir00));
  f.view_from_ray = glm::inverse(m);
  // Reverse-Z with an infinite far plane: depth = znear / t has float's relative
  // precision at every t, so znear only decides what is clipped. 1e-15 of the farthest
  // scene point keeps geometry at 1e-4 visible in a 1e7-sized scene, and znear / t stays
  // far above the denormal range.
  // An orthographic depth is linear instead: from the camera's plane (what lies behind it
  // is out of view, as for its rays) to beyond the farthest corner of the scene's bounds.
  double dmax = 0.0;
  for (int c = 0; c < 8; ++c) {
    glm::dvec3 corner((c & 1) ? bounds_max_.x : bounds_min_.x, (c & 2) ? bounds_max_.y : bounds_min_.y,
                      (c & 4) ? bounds_max_.z : bounds_min_.z);
    dmax = std::max(dmax, glm::length(corner - glm::dvec3(f.origin)));
    f.zfar = std::max(f.zfar, 1.01 * (f.view_from_ray * (corner - glm::dvec3(f.origin))).z);
  }
  f.znear = std::max(dmax * 1e-15, 1e-30);
  if (!(f.zfar > 0.0 && std::isfinite(f.zfar))) f.zfar = 1.0;  // all behind the camera: any range
  // The camera's own planes, only where they cut into the scene: the raster that clips is
  // another pipeline, and a scene between them keeps the plain one's bits.
  // A device that cannot clip draws everything: the map then flags the edges of what the
  // planes cut away too (more rays there), and the tracer still clips the image.
  if (rays.clip.cuts_into(bounds_min_, bounds_max_)) {
    if (context_.clip_distance()) f.clip = rays.clip;
    else warn_cannot_clip();
  }
  f.flag = make_flag_push(camera, width, height, settings);

  // Tiles: full rows when they fit, else bands / columns. Widths are multiples of 4
  // pixels (one flag word each), the image holds the tile plus a one-sample ring.
  const auto [tile_w, tile_h] = tile_size(width, height, settings);
  for (int y = 0; y < height; y += tile_h)
    for (int x = 0; x < width; x += tile_w)
      f.tiles.push_back({x, y, std::min(tile_w, width - x), std::min(tile_h, height - y)});
  f.image_w = target_width(tile_w, f.s);
  f.image_h = uint32_t(tile_h * f.s + 2);
  return f;
}

std::pair<int, int> VisibilityPass::tile_size(int width, int height, const VisibilitySettings& settings) const {
  const VkPhysicalDeviceLimits& limits = context_.properties().limits;
  // The target is an image, a framebuffer and a viewport: the least of their limits.
  return tile_size(width, height, settings,
                   int(std::min({limits.maxImageDimension2D, limits.maxFramebufferWidth, limits.maxFramebufferHeight,
                                 limits.maxViewportDimensions[0], limits.maxViewportDimensions[1],
                                 uint32_t(std::numeric_limits<int>::max())})),
                   triangles_);
}

std::pair<int, int> VisibilityPass::tile_size(int width, int height, const VisibilitySettings& settings, int max_dim,
                                              size_t triangles) {
  const int s = settings.supersample;
  if (settings.max_tile_dim > 0) max_dim = settings.max_tile_dim;
  int max_px = (max_dim - 2) / s;
  int tile_w = std::min(width, max_px / ZZ_PIXELS_PER_WORD * ZZ_PIXELS_PER_WORD);
  if (tile_w < 1) throw Error("visibility map: tile limit too small for the supersampling");
  int64_t row_samples = int64_t(tile_w) * s + 2;
  constexpr int64_t kBandsPerFrame = 8;
  const int64_t frame_samples = (int64_t(width) * s + 2) * (int64_t(height) * s + 2);
  const int64_t budget =
      std::min(settings.max_tile_samples, std::max(band_floor(settings, triangles), frame_samples / kBandsPerFrame));
  int64_t max_rows = budget / row_samples;  // image rows incl. ring
  int tile_h = int(std::min<int64_t>({int64_t(height), int64_t(max_px), (max_rows - 2) / s}));
  if (tile_h < 1) throw Error("visibility map: tile memory budget too small");
  return {tile_w, tile_h};
}

uint64_t VisibilityPass::frame_bytes(int width, int height, const VisibilitySettings& settings, size_t triangles,
                                     const std::optional<TileRect>& region) {
  const auto [tile_w, tile_h] = tile_size(width, height, settings, std::numeric_limits<int>::max(), triangles);
  const uint64_t samples = uint64_t(target_width(tile_w, settings.supersample)) * uint64_t(tile_h * settings.supersample + 2);
  return samples * 8 + flag_area(width, height, region).bytes();
}

void VisibilityPass::check_fits(const VulkanContext& context, size_t triangles, int width, int height,
                                const std::optional<TileRect>& region) {
  check_storage_range(context, triangle_record_bytes(triangles), std::to_string(triangles) + " triangles",
                      kTooManyTriangles);
  if (width > 0 && height > 0)
    check_storage_range(context, flag_area(width, height, region).bytes(), "the frame's flags", kTooManyFlags);
}

void VisibilityPass::ensure_flags(VkDeviceSize bytes) {
  if (flags_.size >= bytes) return;
  check_storage_range(context_, bytes, "the frame's flags", kTooManyFlags);
  flags_.reset();
  flags_ = create_buffer(context_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                         VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
}

void VisibilityPass::prepare(int width, int height, const VisibilitySettings& settings,
                             const std::optional<TileRect>& region, bool orthographic) {
  if (width <= 0 || height <= 0 || settings.supersample < 1 || settings.supersample > ZZ_MAX_SUPERSAMPLE) return;
  const FlagArea flagged = flag_area(width, height, region);
  if (flagged.want.width() <= 0 || flagged.want.height() <= 0) return;
  const auto [tile_w, tile_h] = tile_size(width, height, settings);
  ensure_targets(target_width(tile_w, settings.supersample), uint32_t(tile_h * settings.supersample + 2));
  ensure_flags(flagged.bytes());
  flag_pipeline(settings.supersample, orthographic);
}

void VisibilityPass::ensure_targets(uint32_t width, uint32_t height) {
  if (ids_.image && depth_.image && ids_.width >= width && ids_.height >= height) return;
  context_.wait_idle();
  // The size this frame needs, not the largest of each side ever asked: a wide frame then a
  // tall one would otherwise keep a target that is both, past the tile memory budget.
  depth_.reset();
  ids_.reset();
  // The compute pass reads the attachment itself (storage image); TRANSFER_SRC only for
  // render_ids. Both are made before either is kept, so a failed allocation leaves none.
  Image ids = create_image_2d(context_, width, height, kIdFormat,
                              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                  VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              VK_IMAGE_ASPECT_COLOR_BIT);
  Image depth = create_image_2d(context_, width, height, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                VK_IMAGE_ASPECT_DEPTH_BIT);
  ids_ = std::move(ids);
  depth_ = std::move(depth);
}

void VisibilityPass::record_raster(VkCommandBuffer cmd, const Frame& f, const Tile& tile, const Tile& area) {
  uint32_t iw = uint32_t(tile.w * f.s + 2), ih = uint32_t(tile.h * f.s + 2);
  // The area's samples with their ring, in image coordinates.
  VkRect2D scissor{{(area.x - tile.x) * f.s, (area.y - tile.y) * f.s},
                   {uint32_t(area.w * f.s + 2), uint32_t(area.h * f.s + 2)}};
  // Previous users of the targets (last tile's compute read, depth test) must finish;
  // UNDEFINED discards the old contents, which the clear replaces anyway.
  VkImageMemoryBarrier2 to_attach[2] = {{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2},
                                        {VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2}};
  to_attach[0].srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT;
  to_attach[0].dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
  to_attach[0].dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
  to_attach[0].oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  to_attach[0].newLayout = VK_IMAGE_LAYOUT_GENERAL;
  to_attach[0].srcQueueFamilyIndex = to_attach[0].dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_attach[0].image = ids_.image;
  to_attach[0].subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  to_attach[1].srcStageMask = VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  to_attach[1].srcAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  to_attach[1].dstStageMask =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  to_attach[1].dstAccessMask =
      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  to_attach[1].oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  to_attach[1].newLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  to_attach[1].srcQueueFamilyIndex = to_attach[1].dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_attach[1].image = depth_.image;
  to_attach[1].subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 2;
  dep.pImageMemoryBarriers = to_attach;
  vkCmdPipelineBarrier2(cmd, &dep);

  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = ids_.view;
  color.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  color.clearValue.color.uint32[0] = 0;  // background
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = depth_.view;
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.clearValue.depthStencil.depth = 0.0f;  // reverse-Z: 0 is infinitely far
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = scissor;  // the clears too
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = 1;
  rendering.pColorAttachments = &color;
  rendering.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &rendering);
  if (triangles_ > 0) {
    // Image sample (u, v) has its centre at frame supersample gx = u + ox, i.e. image
    // point px = (u + 0.5 + ox)/S. With (a, b, c) = view_from_ray q (c = t):
    // fb_x = S a/c - ox, ndc_x = 2 fb_x / iw - 1, clip = ndc * c, z = znear (reverse-Z).
    // Orthographic, (a, b, c) = view_from_ray q with c = t: fb_x = S a - ox, clip = ndc
    // (w = 1), z = 1 - c / zfar (reverse-Z, linear: the camera's plane at 1).
    double ox = double(tile.x) * f.s - 1.0, oy = double(tile.y) * f.s - 1.0;
    glm::dmat3 r = glm::transpose(f.view_from_ray);  // r[k] = row k of view_from_ray
    gpu::RasterPush push{};
    if (f.orthographic) {
      glm::dvec3 row_x = (2.0 * f.s / iw) * r[0], row_y = (2.0 * f.s / ih) * r[1], row_z = -r[2] / f.zfar;
      for (int k = 0; k < 3; ++k)
        push.clip_from_view[k] = glm::vec4(float(row_x[k]), float(row_y[k]), float(row_z[k]), 0.0f);
      push.clip_from_view[3] = glm::vec4(float(-(2.0 * ox / iw + 1.0)), float(-(2.0 * oy / ih + 1.0)), 1.0f, 1.0f);
    } else {
      glm::dvec3 row_x = (2.0 * f.s / iw) * r[0] - (2.0 * ox / iw + 1.0) * r[2];
      glm::dvec3 row_y = (2.0 * f.s / ih) * r[1] - (2.0 * oy / ih + 1.0) * r[2];
      glm::dvec3 row_w = r[2];
      for (int k = 0; k < 3; ++k) {  // glm is column-major: m[column][row]
        push.clip_from_view[k][0] = float(row_x[k]);
        push.clip_from_view[k][1] = float(row_y[k]);
        push.clip_from_view[k][2] = 0.0f;
        push.clip_from_view[k][3] = float(row_w[k]);
      }
      push.clip_from_view[3] = glm::vec4(0.0f, 0.0f, float(f.znear), 0.0f);
    }
    push.origin = glm::vec4(f.origin, 0.0f);
    // An infinite far plane as the largest float: inf - depth would be NaN-free, but the
    // clipper interpolates the distances.
    push.clip_forward = glm::vec4(f.clip.forward, 0.0f);
    push.clip_planes = glm::vec4(f.clip.znear, std::min(f.clip.zfar, std::numeric_limits<float>::max()), 0.0f, 0.0f);
    VkViewport viewport{0.0f, 0.0f, float(iw), float(ih), 0.0f, 1.0f};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f.clip.clips() ? raster_clip_pipeline() : raster_pipeline_);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdPushConstants(cmd, raster_layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &positions_.buffer, &offset);
    vkCmdDraw(cmd, uint32_t(3 * triangles_), 1, 0, 0);
  }
  vkCmdEndRendering(cmd);
}

void VisibilityPass::record_id_copy(VkCommandBuffer cmd, const Tile& tile, VkBuffer dst) {
  uint32_t iw = uint32_t(tile.w * frame_s_ + 2), ih = uint32_t(tile.h * frame_s_ + 2);
  VkImageMemoryBarrier2 ready{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  ready.srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
  ready.srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
  ready.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
  ready.dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT;
  ready.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
  ready.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  ready.srcQueueFamilyIndex = ready.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  ready.image = ids_.image;
  ready.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &ready;
  vkCmdPipelineBarrier2(cmd, &dep);
  VkBufferImageCopy region{};  // tightly packed rows of iw ids
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {iw, ih, 1};
  vkCmdCopyImageToBuffer(cmd, ids_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, 1, &region);
}

void VisibilityPass::bind_descriptors() {
  VkDescriptorImageInfo image_info{VK_NULL_HANDLE, ids_.view, VK_IMAGE_LAYOUT_GENERAL};
  VkDescriptorBufferInfo buffer_info[4] = {{first_vertices_.buffer, 0, VK_WHOLE_SIZE},
                                           {normals_.buffer, 0, VK_WHOLE_SIZE},
                                           {planes_.buffer, 0, VK_WHOLE_SIZE},
                                           {flags_.buffer, 0, VK_WHOLE_SIZE}};
  VkWriteDescriptorSet writes[2] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                    {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
  writes[0].dstSet = flag_set_;
  writes[0].dstBinding = ZZ_BIND_IDS;
  writes[0].descriptorCount = 1;
  writes[0].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  writes[0].pImageInfo = &image_info;
  static_assert(ZZ_BIND_NORMALS == ZZ_BIND_FIRST_VERTICES + 1 && ZZ_BIND_PLANES == ZZ_BIND_FIRST_VERTICES + 2 &&
                ZZ_BIND_FLAGS == ZZ_BIND_FIRST_VERTICES + 3);
  writes[1].dstSet = flag_set_;
  writes[1].dstBinding = ZZ_BIND_FIRST_VERTICES;
  writes[1].descriptorCount = 4;
  writes[1].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  writes[1].pBufferInfo = buffer_info;
  vkUpdateDescriptorSets(context_.device(), 2, writes, 0, nullptr);
}

GeoMap VisibilityPass::run(const Camera& camera, int width, int height, const VisibilitySettings& settings,
                           VisibilityTimings* timings, const std::optional<TileRect>& region,
                           const std::atomic<bool>* cancel) {
  auto t0 = Clock::now();
  Frame f = plan(camera, width, height, settings);
  const FlagArea flagged = flag_area(width, height, region);
  const TileRect& want = flagged.want;
  if (want.width() <= 0 || want.height() <= 0) throw Error("visibility map: empty region");
  const Tile area{flagged.buffer.x0, flagged.buffer.y0, flagged.buffer.width(), flagged.buffer.height()};
  f.flag.out_x0 = flagged.buffer.x0;
  f.flag.out_y0 = flagged.buffer.y0;
  f.flag.frame.w = flagged.words_per_row();
  ensure_targets(f.image_w, f.image_h);
  frame_s_ = f.s;
  VkDevice d = context_.device();
  const VkPipeline flags_pipeline = flag_pipeline(f.s, f.orthographic);

  ensure_flags(flagged.bytes());
  // The tiles' parts inside the area; tile edges are multiples of 4 pixels (but the last).
  std::vector<std::pair<Tile, Tile>> work;  // tile, area within it
  for (const Tile& tile : f.tiles) {
    int x0 = std::max(tile.x, area.x), x1 = std::min(tile.x + tile.w, area.x + area.w);
    int y0 = std::max(tile.y, area.y), y1 = std::min(tile.y + tile.h, area.y + area.h);
    if (x0 < x1 && y0 < y1) work.push_back({tile, Tile{x0, y0, x1 - x0, y1 - y0}});
  }
  uint32_t queries = uint32_t(3 * work.size() + 2);
  bool timed = context_.timestamps();
  if (timed && query_capacity_ < queries) {
    if (queries_) vkDestroyQueryPool(d, queries_, nullptr);
    queries_ = VK_NULL_HANDLE;
    query_capacity_ = 0;  // until the new pool exists
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = queries;
    vk_check(vkCreateQueryPool(d, &info, nullptr, &queries_), "vkCreateQueryPool");
    query_capacity_ = queries;
  }
  bind_descriptors();

  auto record_planes = [&](VkCommandBuffer cmd) {
    if (timed) {
      vkCmdResetQueryPool(cmd, queries_, 0, queries);
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
    }
    if (triangles_ > 0) {
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, flag_layout_, 0, 1, &flag_set_, 0, nullptr);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, plane_pipeline_);
      const size_t groups = (triangles_ + ZZ_PLANE_GROUP - 1) / ZZ_PLANE_GROUP;
      const size_t most = settings.max_plane_groups > 0 ? size_t(settings.max_plane_groups)
                                                        : context_.properties().limits.maxComputeWorkGroupCount[0];
      for (size_t first = 0; first < groups; first += most) {
        gpu::PlanePush planes{glm::vec4(f.flag.origin, 0.0f), glm::ivec4(int(triangles_), int(first * ZZ_PLANE_GROUP), 0, 0)};
        vkCmdPushConstants(cmd, flag_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(planes), &planes);
        vkCmdDispatch(cmd, uint32_t(std::min(most, groups - first)), 1, 1);
      }
      memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    }
    if (timed) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
  };
  auto record_band = [&](VkCommandBuffer cmd, size_t k) {
    const auto& [tile, part] = work[k];
    if (timed) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, uint32_t(3 * k + 2));
    record_raster(cmd, f, tile, part);
    if (timed) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, uint32_t(3 * k + 3));
    // The attachment stays in GENERAL: the flag pass reads it as a storage image.
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, flag_layout_, 0, 1, &flag_set_, 0, nullptr);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, flags_pipeline);
    gpu::FlagPush push = f.flag;
    push.tile = glm::ivec4(tile.x, tile.y, tile.w, tile.h);
    push.area = glm::ivec4(part.x, part.y, part.w, part.h);
    vkCmdPushConstants(cmd, flag_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    const uint32_t words = uint32_t((part.w + ZZ_PIXELS_PER_WORD - 1) / ZZ_PIXELS_PER_WORD);
    vkCmdDispatch(cmd, (words + ZZ_FLAG_GROUP_X - 1) / ZZ_FLAG_GROUP_X,
                  uint32_t(part.h + ZZ_FLAG_GROUP_Y - 1) / ZZ_FLAG_GROUP_Y, 1);
    if (timed) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, uint32_t(3 * k + 4));
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  };
  if (!cancel) {
    // One submission: each costs a queue hand-off and a fence wait (8 bands: +0.03 s).
    context_.run_commands([&](VkCommandBuffer cmd) {
      record_planes(cmd);
      for (size_t k = 0; k < work.size(); ++k) record_band(cmd, k);
    });
  } else {
    // The viewer's map: a submission per band, so a present on the shared queue waits for
    // a band at most, and a map its camera has left stops at the next band. Pipeline
    // barriers order the submissions as they ordered one command buffer's commands.
    context_.run_commands(record_planes);
    for (size_t k = 0; k < work.size(); ++k) {
      if (cancel->load(std::memory_order_relaxed)) return GeoMap{};
      context_.run_commands([&](VkCommandBuffer cmd) { record_band(cmd, k); });
    }
  }

  auto t_read = Clock::now();
  invalidate(flags_);
  GeoMap map;
  map.width = width;
  map.height = height;
  map.flags.assign(size_t(width) * height, 0);
  // Byte k of word w is pixel 4w + k (little-endian), so each row is a plain copy.
  static_assert(ZZ_GEO_EDGE == kGeoEdge && ZZ_GEO_ALONG_X == kGeoAlongX && ZZ_GEO_ZONE_SHIFT == kGeoZoneShift,
                "one flag byte layout");
  const auto* bytes = static_cast<const uint8_t*>(flags_.mapped);
  const size_t row_bytes = size_t(flagged.words_per_row()) * sizeof(uint32_t);
  for (int y = want.y0; y < want.y1; ++y)
    std::memcpy(&map.flags[size_t(y) * width + want.x0],
                bytes + size_t(y - flagged.buffer.y0) * row_bytes + size_t(want.x0 - flagged.buffer.x0),
                size_t(want.width()));

  if (timings) {
    *timings = VisibilityTimings{};
    timings->upload_s = upload_s_;
    timings->tiles = int(work.size());
    if (timed) {
      std::vector<uint64_t> ts(queries);
      vk_check(vkGetQueryPoolResults(d, queries_, 0, queries, ts.size() * sizeof(uint64_t), ts.data(),
                                     sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
               "vkGetQueryPoolResults");
      double period = context_.properties().limits.timestampPeriod * 1e-9;
      timings->compute_s += double(ts[1] - ts[0]) * period;
      for (size_t k = 0; k < work.size(); ++k) {
        timings->raster_s += double(ts[3 * k + 3] - ts[3 * k + 2]) * period;
        timings->compute_s += double(ts[3 * k + 4] - ts[3 * k + 3]) * period;
      }
    }
    timings->readback_s = seconds_since(t_read);
    timings->total_s = seconds_since(t0);
  }
  return map;
}

std::vector<uint32_t> VisibilityPass::render_ids(const Camera& camera, int width, int height,
                                                 const VisibilitySettings& settings) {
  Frame f = plan(camera, width, height, settings);
  ensure_targets(f.image_w, f.image_h);
  frame_s_ = f.s;
  size_t fw = size_t(width) * f.s + 2;
  std::vector<uint32_t> ids(fw * (size_t(height) * f.s + 2), 0u);
  VkDeviceSize bytes = VkDeviceSize(f.image_w) * f.image_h * sizeof(uint32_t);
  if (id_readback_.size < bytes) {
    id_readback_.reset();
    id_readback_ = create_buffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  }
  for (const Tile& tile : f.tiles) {
    // The whole tile image, ring included; neighbouring tiles' rings overlap and agree.
    uint32_t cw = uint32_t(tile.w * f.s + 2), ch = uint32_t(tile.h * f.s + 2);
    context_.run_commands([&](VkCommandBuffer cmd) {
      record_raster(cmd, f, tile, tile);
      record_id_copy(cmd, tile, id_readback_.buffer);
      memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    });
    invalidate(id_readback_);
    const auto* src = static_cast<const uint32_t*>(id_readback_.mapped);
    for (uint32_t v = 0; v < ch; ++v)
      std::memcpy(&ids[(size_t(tile.y) * f.s + v) * fw + size_t(tile.x) * f.s], src + size_t(v) * cw,
                  cw * sizeof(uint32_t));
  }
  return ids;
}

}  // namespace zz
