#include "render/renderer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>

#include "aa/corner_field.h"  // kCornerFieldBudget
#include "scene/loader.h"
#include "test_render.h"
#include "test_scenes.h"

namespace zz {
namespace {

// A floor with a box on it (shadow edges, silhouettes) and a mirror ball-ish box.
Scene box_scene() {
  Scene s = test::lit_floor(0.6f, 80.0f, 3.0f);
  s.lights[0].position = {1.5f, 1.0f, 3.0f};
  s.materials.push_back(test::mirror_material(glm::vec3(0.9f)));
  s.materials.push_back(test::glass_material(1.5f));
  test::add_box(s, {-0.8f, -0.6f, 0.0f}, {0.2f, 0.4f, 0.7f}, 1);
  // The glass box floats 1 mm above the floor: a ray refracted out at a bottom edge that
  // coincides with the floor would start within rounding distance of the floor, where the
  // packet and single-ray traversals can disagree on a hit at t ~ 1e-7 (no t > error-bound
  // test as pbrt-v4's; an accel issue). Shadows through glass made that visible.
  test::add_box(s, {0.4f, -0.9f, 0.001f}, {0.9f, -0.2f, 0.5f}, 2);
  s.cameras[0] = Camera::look_at({1.5f, -3.0f, 2.5f}, {0, 0, 0.3f}, {0, 0, 1}, 0.7f);
  s.finalize_materials();
  return s;
}

using test::render;

using test::bit_identical;

TEST(Renderer, OneRayPerPixelCountsExactly) {
  RenderSettings s;
  s.width = 70;
  s.height = 33;
  s.aa = AaMode::None;
  RenderStats stats;
  render(box_scene(), s, &stats);
  // 70*33 = 2310 points, streamed 4 at a time over 2 tiles (64 + 6 columns): each tile
  // pads its last packet.
  EXPECT_EQ(stats.samples, 2310u);
  EXPECT_EQ(stats.rays.primary, 4u * ((64 * 33 + 3) / 4 + (6 * 33 + 3) / 4));
  EXPECT_GT(stats.rays.shadow, 0u);
  EXPECT_GT(stats.rays.reflection, 0u);
  EXPECT_GT(stats.rays.refraction, 0u);
}

TEST(Renderer, BitIdenticalAcrossThreadsTileSizesAndOrder) {
  for (UniformPattern pattern : {UniformPattern::Center, UniformPattern::Stratified, UniformPattern::Lattice}) {
    RenderSettings s;
    s.width = 97;
    s.height = 70;
    s.aa = pattern == UniformPattern::Center ? AaMode::None : AaMode::Uniform;
    s.uniform = {pattern, pattern == UniformPattern::Stratified ? 9 : 25};
    s.threads = 1;
    const Film reference = render(box_scene(), s);
    s.threads = 2;
    EXPECT_TRUE(bit_identical(reference, render(box_scene(), s)));
    s.tile_size = 16;
    s.centre_out = true;
    EXPECT_TRUE(bit_identical(reference, render(box_scene(), s)));
    s.tile_size = 7;
    EXPECT_TRUE(bit_identical(reference, render(box_scene(), s)));
  }
}

TEST(Renderer, AdaptiveIsBitIdenticalAcrossThreadsTileSizesAndOrderWithAndWithoutSignatures) {
  const Scene scene = box_scene();
  for (unsigned sig : {kSignatureNone, kSignatureAll})
    for (Filter filter : {Filter::Box, Filter::Mitchell}) {
      // The hidden-detail flags and the curvature correction (the box filter's, with its ring
      // of corners) on in two of the four cases: box with signatures, Mitchell without.
      const bool extras = (sig != kSignatureNone) != (filter == Filter::Mitchell);
      SCOPED_TRACE(testing::Message() << "signature " << signature_name(sig) << " " << to_string(filter));
      RenderSettings s;
      s.width = 97;
      s.height = 70;
      s.adaptive.signature = sig;
      s.adaptive.filter = filter;
      s.adaptive.highlights = s.adaptive.textures = s.adaptive.curvature = extras;
      s.threads = 1;
      RenderStats first;
      const Film reference = render(scene, s, &first);
      s.threads = 2;
      EXPECT_TRUE(bit_identical(reference, render(scene, s)));
      s.tile_size = 16;
      s.centre_out = true;
      EXPECT_TRUE(bit_identical(reference, render(scene, s)));
      s.tile_size = 7;
      RenderStats last;
      EXPECT_TRUE(bit_identical(reference, render(scene, s, &last)));
      EXPECT_GT(first.aa.level2_pixels, 0u);
      // One definition of rays/px: the sampler's count is the camera rays traced.
      EXPECT_EQ(first.aa.total_rays(), first.rays.primary);
      EXPECT_EQ(last.aa.total_rays(), last.rays.primary);
      EXPECT_GT(last.aa.padded_rays, 0u);  // 7-pixel tiles: 8 x 8 corners, but 97 x 70 leaves odd edges
    }
}

TEST(Renderer, SignaturesRefineASupersetOfThePixels) {
  // The same frame with all signature parts refines a superset of the pixels.
  const Scene scene = box_scene();
  RenderSettings s;
  s.width = 97;
  s.height = 70;
  s.adaptive.eps = 0.2f;
  RenderStats plain, with;
  const Film a = render(scene, s, &plain);
  s.adaptive.signature = kSignatureAll;
  const Film b = render(scene, s, &with);
  EXPECT_GT(with.aa.level2_pixels, plain.aa.level2_pixels);
  for (size_t i = 0; i < a.level.size(); ++i) {
    if (a.level[i] > 1) {
      EXPECT_GT(b.level[i], 1) << "pixel " << i;
    }
  }
}

TEST(Renderer, LatticeTracesTwentyFiveRaysPerPixelPlusTheRing) {
  RenderSettings s;
  s.width = 64;
  s.height = 64;
  s.aa = AaMode::Uniform;
  s.uniform = {UniformPattern::Lattice, 25};
  RenderStats stats;
  render(box_scene(), s, &stats);
  EXPECT_EQ(stats.samples, 64u * 64u * 24u + 65u * 65u);
}

TEST(Renderer, UniformPatternsConvergeToEachOther) {
  RenderSettings s;
  s.width = 48;
  s.height = 48;
  s.aa = AaMode::Uniform;
  s.uniform = {UniformPattern::Grid, 256};
  const Film grid = render(box_scene(), s);
  s.uniform = {UniformPattern::Lattice, 25};
  const Film lattice = render(box_scene(), s);
  double sum = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < grid.radiance.size(); ++i) {
    const glm::vec3 d = grid.radiance[i] - lattice.radiance[i];
    sum_sq += double(glm::dot(d, d)) / 3.0;
    sum += double(grid.radiance[i].g);
  }
  const double rmse = std::sqrt(sum_sq / double(grid.radiance.size()));
  const double mean = sum / double(grid.radiance.size());
  EXPECT_GT(mean, 0.0);
  EXPECT_LT(rmse, 0.05 * mean);  // 25 well-spread points are close to 256 on this scene
}

TEST(Renderer, CancelStopsPromptly) {
  RenderSettings s;
  s.width = 256;
  s.height = 256;
  s.aa = AaMode::None;
  std::atomic<bool> cancel{true};
  RenderCallbacks callbacks;
  callbacks.cancel = &cancel;
  RenderStats stats;
  render(box_scene(), s, &stats, callbacks);
  EXPECT_TRUE(stats.cancelled);
  EXPECT_EQ(stats.rays.primary, 0u);
}

// A map still being made (level 1 overlaps it) gives the image and ray counts of the
// finished map, with both filters and tiles that share margins.
TEST(Renderer, PendingMapIsBitIdenticalToAFinishedOne) {
  const Scene scene = box_scene();
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  RenderSettings s;
  s.width = 90;
  s.height = 61;
  s.tile_size = 16;
  s.threads = 2;
  GeoMap geo;
  geo.width = s.width;
  geo.height = s.height;
  geo.flags.assign(size_t(s.width) * s.height, 0);
  for (int y = 0; y < s.height; ++y) geo.flags[size_t(y) * s.width + (y * 7) % s.width] = 1;  // a diagonal
  for (Filter filter : {Filter::Box, Filter::Mitchell}) {
    s.adaptive.filter = filter;
    s.adaptive.signature = filter == Filter::Box ? kSignatureNone : kSignatureAll;  // with and without signatures
    s.adaptive.highlights = s.adaptive.curvature = filter == Filter::Box;           // with flags and the ring
    Film a, b;
    RenderStats sa, sb;
    render_frame(shader, scene.cameras[0], geo, s, a, sa);
    // The map is made only once level 1 is done (a fixed sleep could end before level 1
    // even started under a sanitizer): the tiles then wait for it, as with a slow device.
    const size_t blocks = corner_field_plan(s).blocks;
    ASSERT_GT(blocks, 0u);
    std::atomic<size_t> corners_done{0};
    RenderCallbacks callbacks;
    callbacks.corners_done = [&](const RayCounters&) { ++corners_done; };
    std::shared_future<GeoMap> pending = std::async(std::launch::async, [&] {
      while (corners_done.load() < blocks) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      return geo;
    });
    render_frame(shader, scene.cameras[0], pending, s, b, sb, callbacks);
    EXPECT_EQ(corners_done.load(), blocks);
    EXPECT_TRUE(bit_identical(a, b));
    EXPECT_EQ(sa.rays.total(), sb.rays.total());
    EXPECT_EQ(sa.aa.rays[0], sb.aa.rays[0]);
    EXPECT_EQ(sa.aa.rays[2], sb.aa.rays[2]);
    EXPECT_EQ(sa.aa.geo_pixels, sb.aa.geo_pixels);
    EXPECT_GT(sa.aa.geo_pixels, 0u);
  }
}

// What a BLEND surface shows behind it is probed for the highlight flag and the footprint
// (the path tree's refraction node) in the lanes where the surface does not refract too; a
// BLEND glass's lane keeps that node for its refraction. The choice is each lane's own: a
// region render, whose packets hold other neighbours, gives the same pixels bit for bit
// (it did not while one refracting lane withdrew the probes of its whole packet: 14 pixels
// of each region differed). The glass scene with its glass alpha-blended too, as exporters
// write glass with both alpha and transmission.
TEST(Renderer, ProbesBehindBlendSurfacesDoNotDependOnThePacket) {
  Scene scene = load_scene(std::filesystem::path(ZZ_SOURCE_DIR) / "scenes" / "glass.json");
  int blended = 0;
  for (Material& m : scene.materials)
    if (m.transmission > 0.0f) m.alpha_mode = AlphaMode::Blend, m.base_alpha = 0.6f, ++blended;
  ASSERT_GT(blended, 0);
  scene.finalize_materials();
  RenderSettings s;  // set below to the CLI's defaults (without the visibility map)
  s.width = 96;
  s.height = 96;
  s.threads = 2;
  s.adaptive.eps = 0.05f;
  s.adaptive.eps_specular = 0.01f;
  s.adaptive.signature = kSignatureAll;
  s.adaptive.highlights = s.adaptive.footprint = s.adaptive.curvature = s.adaptive.hdr_zones = true;
  RenderStats whole_stats;
  const Film whole = render(scene, s, &whole_stats);
  EXPECT_GT(whole_stats.rays.continuation, 0u);
  EXPECT_GT(whole_stats.rays.refraction, 0u);
  for (const TileRect& r : {TileRect{13, 7, 90, 88}, TileRect{1, 3, 95, 96}}) {
    SCOPED_TRACE(testing::Message() << "region " << r.x0 << "," << r.y0 << "," << r.x1 << "," << r.y1);
    s.region = r;
    const Film part = render(scene, s);
    ASSERT_EQ(part.width, r.width());
    ASSERT_EQ(part.height, r.height());
    int differ = 0;
    for (int y = 0; y < part.height; ++y)
      for (int x = 0; x < part.width; ++x)
        differ += std::memcmp(&part.radiance[size_t(y) * part.width + x],
                              &whole.radiance[size_t(y + r.y0) * whole.width + x + r.x0], sizeof(glm::vec3)) != 0;
    EXPECT_EQ(differ, 0);
  }
}

// Level 1 for the whole region at once (aa/corner_field.h) gives the per-tile path's
// image bit for bit, with both filters, the flags and the curvature ring, a region render
// and odd sizes, while tracing fewer corners: each once, no shared rows, no ring per tile.
TEST(Renderer, CornerFieldIsBitIdenticalToPerTileCorners) {
  const Scene scene = box_scene();
  RenderSettings s;
  s.width = 93;
  s.height = 67;
  s.tile_size = 16;
  s.threads = 2;
  for (Filter filter : {Filter::Box, Filter::Mitchell}) {
    for (bool region : {false, true}) {
      SCOPED_TRACE(std::string(filter == Filter::Box ? "box" : "mitchell") + (region ? " region" : ""));
      s.adaptive.filter = filter;
      s.adaptive.signature = kSignatureAll;
      s.adaptive.highlights = true;  // probes gathered across tiles and the Mitchell margin
      s.adaptive.curvature = filter == Filter::Box;
      s.region = region ? TileRect{13, 7, 71, 50} : TileRect{};
      s.corner_field = false;
      RenderStats per_tile, whole;
      const Film a = render(scene, s, &per_tile);
      s.corner_field = true;
      const Film b = render(scene, s, &whole);
      EXPECT_TRUE(bit_identical(a, b));
      EXPECT_EQ(per_tile.aa.rays[1], whole.aa.rays[1]);
      EXPECT_EQ(per_tile.aa.rays[2], whole.aa.rays[2]);
      EXPECT_EQ(per_tile.aa.hidden_pixels, whole.aa.hidden_pixels);
      EXPECT_GT(whole.aa.hidden_pixels, 0u);  // the flags were gathered, not just absent
      // Box over the frame: every corner of the frame and its ring once; the ring is the margin.
      if (filter == Filter::Box && !region) {
        EXPECT_EQ(whole.aa.rays[0], uint64_t(s.width + 3) * uint64_t(s.height + 3));
        EXPECT_EQ(whole.aa.margin_rays, uint64_t(s.width + 3) * uint64_t(s.height + 3) -
                                            uint64_t(s.width + 1) * uint64_t(s.height + 1));
      }
      EXPECT_LT(whole.aa.rays[0], per_tile.aa.rays[0]);
      EXPECT_LT(whole.rays.primary, per_tile.rays.primary);
      EXPECT_EQ(whole.rays.primary, whole.aa.total_rays());
      EXPECT_EQ(per_tile.rays.primary, per_tile.aa.total_rays());
    }
  }
}

// Cancelled while level 1 of the whole frame is traced: no tile is rendered, nothing
// crashes, and the stats say so.
TEST(Renderer, CancelDuringTheCornerFieldStopsBeforeAnyTile) {
  RenderSettings s;
  s.width = 300;
  s.height = 200;
  s.threads = 1;
  ASSERT_GT(corner_field_plan(s).blocks, 4u);
  std::atomic<bool> cancel{false};
  size_t blocks = 0, tiles = 0;
  RenderCallbacks callbacks;
  callbacks.cancel = &cancel;
  callbacks.corners_done = [&](const RayCounters& rays) {
    EXPECT_GT(rays.primary, 0u);
    if (++blocks == 2) cancel = true;
  };
  callbacks.tile_done = [&](const TileRect&, const RayCounters&) { ++tiles; };
  RenderStats stats;
  render(box_scene(), s, &stats, callbacks);
  EXPECT_TRUE(stats.cancelled);
  EXPECT_EQ(blocks, 2u);
  EXPECT_EQ(tiles, 0u);
}

// The plan the CLI budgets memory and progress with is what the renderer does.
TEST(Renderer, CornerFieldPlanMatchesTheRender) {
  RenderSettings s;
  s.width = 150;
  s.height = 70;
  size_t blocks = 0;
  RenderCallbacks callbacks;
  callbacks.corners_done = [&](const RayCounters&) { ++blocks; };
  render(box_scene(), s, nullptr, callbacks);
  const CornerFieldPlan plan = corner_field_plan(s);
  EXPECT_EQ(blocks, plan.blocks);
  EXPECT_EQ(plan.blocks, size_t(3 * 2));  // (150 + 1) x (70 + 1) corners in 64² blocks
  EXPECT_GE(plan.bytes, uint64_t(151 * 71) * 36);
  s.corner_field = false;
  EXPECT_EQ(corner_field_plan(s).blocks, 0u);
  s.corner_field = true;
  s.aa = AaMode::Uniform;
  EXPECT_EQ(corner_field_plan(s).bytes, 0u);
}

// A 4K frame with every hidden-detail flag keeps its level-1 field (within its budget) and
// does not fall back to tracing corners per tile.
TEST(Renderer, A4kFrameWithEveryFlagFitsTheCornerFieldsBudget) {
  RenderSettings s;
  s.width = 3840;
  s.height = 2160;
  s.adaptive.highlights = s.adaptive.textures = s.adaptive.curvature = s.adaptive.footprint = true;
  s.adaptive.signature = kSignatureAll;
  const CornerFieldPlan plan = corner_field_plan(s);
  EXPECT_GT(plan.blocks, 0u);
  EXPECT_LE(plan.bytes, kCornerFieldBudget);
  EXPECT_GT(plan.bytes, uint64_t(3841) * 2161 * 36);  // it does hold the flags' bands
}

// A lit floor under a fine base-colour texture and a normal map of ridges, 2-3 texels per
// pixel: detail that four corners average badly.
Scene textured_floor() {
  Scene s = test::lit_floor(0.8f, 30.0f, 3.0f);
  s.positions.clear(), s.normals.clear(), s.uvs.clear(), s.material_of.clear();
  const glm::vec3 p[4] = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
  const glm::vec2 uv[4] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};  // repeated 40 times
  for (int t : {0, 2}) {
    const int v[3] = {0, t + 1, t + 2 == 4 ? 3 : t + 2};
    for (int k : v) {
      s.positions.push_back(p[k]);
      s.normals.push_back({0, 0, 1});
      s.uvs.push_back(uv[k]);
      s.tangents.push_back({1, 0, 0, 1});
    }
    s.material_of.push_back(0);
  }
  Texture base, ridges;
  base.width = base.height = ridges.width = ridges.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float grain = float((x * 7 + y * 13) % 11) / 10.0f;
      base.texels.push_back(glm::vec4(glm::vec3(0.2f + 0.8f * grain), 1.0f));
      const float slope = (x % 4 == 1) ? 0.6f : (x % 4 == 3 ? -0.6f : 0.0f);
      ridges.texels.push_back(glm::vec4(glm::normalize(glm::vec3(slope, 0.0f, 1.0f)) * 0.5f + 0.5f, 1.0f));
    }
  s.textures = {base, ridges};
  s.materials[0].base_color_texture.index = 0;
  s.materials[0].normal_texture.index = 1;
  s.finalize_materials();
  return s;
}

double rmse(const Film& a, const Film& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.radiance.size(); ++i) {
    const glm::vec3 d = a.radiance[i] - b.radiance[i];
    sum += double(glm::dot(d, d));
  }
  return std::sqrt(sum / double(3 * a.radiance.size()));
}

// The texture footprint correction on `scene`: closer to a 256-sample reference than the
// corners' mean, at the same rays, and bit-identical whatever the threads, tiles and
// corner field.
// `scene` at 96 x 64 with `adaptive` (footprint off, then on, one thread) and its 256-sample
// reference: the correction adds no ray and takes the error below 0.6 of what it was.
// Returns the settings of the render with it.
RenderSettings expect_footprint_closer(const Scene& scene, const AdaptiveSettings& adaptive, Film& on) {
  RenderSettings s;
  s.width = 96;
  s.height = 64;
  s.aa = AaMode::Uniform;
  s.uniform = {UniformPattern::Stratified, 256};
  const Film reference = render(scene, s);
  s.aa = AaMode::Adaptive;
  s.adaptive = adaptive;
  s.adaptive.footprint = false;
  RenderStats off_stats, on_stats;
  const Film off = render(scene, s, &off_stats);
  s.adaptive.footprint = true;
  s.threads = 1;
  on = render(scene, s, &on_stats);
  EXPECT_EQ(on_stats.rays.primary, off_stats.rays.primary);
  EXPECT_LT(rmse(on, reference), 0.6 * rmse(off, reference)) << rmse(on, reference) << " " << rmse(off, reference);
  return s;
}

// The same, then the image with the correction bit-identical across threads, tiles and the
// per-tile corners.
void expect_footprint_closer_deterministically(const Scene& scene) {
  AdaptiveSettings adaptive;
  adaptive.highlights = adaptive.curvature = true;
  Film on;
  RenderSettings s = expect_footprint_closer(scene, adaptive, on);
  s.threads = 2;
  s.tile_size = 7;
  EXPECT_TRUE(bit_identical(on, render(scene, s)));
  s.corner_field = false;
  s.tile_size = 16;
  EXPECT_TRUE(bit_identical(on, render(scene, s)));
}

TEST(Renderer, TextureFootprintComesCloserToTheReferenceDeterministically) {
  expect_footprint_closer_deterministically(textured_floor());
}

// textured_floor's texture seen in a mirror: the textured plane hangs at z = 6 facing down,
// lit from below (the light to the side, its image in the mirror out of the frame), its
// texture repeated 16 times (seen from 10 units away, about as many texels per pixel as
// the floor from 4), and the floor is a mirror.
Scene textured_ceiling_in_a_mirror() {
  Scene s = textured_floor();
  for (size_t t = 0; t < s.positions.size(); t += 3) std::swap(s.positions[t + 1], s.positions[t + 2]),
                                                    std::swap(s.uvs[t + 1], s.uvs[t + 2]);
  for (glm::vec3& p : s.positions) p.z = 6.0f;
  for (glm::vec3& n : s.normals) n = {0, 0, -1};
  for (glm::vec2& uv : s.uvs) uv *= 0.4f;
  s.materials.push_back(test::mirror_material(glm::vec3(0.9f)));
  test::add_quad(s, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 1);
  s.tangents.resize(s.positions.size(), glm::vec4(1, 0, 0, 1));
  s.lights[0].position = {6, 6, 3};
  s.finalize_materials();
  return s;
}

// The correction follows the camera ray into a mirror: the texture it shows is integrated
// over the pixel too, weighed by the mirror's reflectance (render/scene_source.h).
TEST(Renderer, TextureFootprintFollowsTheCameraRayIntoAMirror) {
  expect_footprint_closer_deterministically(textured_ceiling_in_a_mirror());
}

// A mirror's image pixel is decided at eps_specular, also where the footprint asks whether
// the pixel will be refined anyway: with eps_specular above eps, the pixels whose corners
// differ by an amount between the two stay unrefined and must still take their delta (they
// were given none, decided at eps).
TEST(Renderer, TextureFootprintInAMirrorUsesTheMirrorsThreshold) {
  AdaptiveSettings adaptive;
  adaptive.eps = 0.005f;
  adaptive.eps_specular = 0.2f;
  Film on;
  expect_footprint_closer(textured_ceiling_in_a_mirror(), adaptive, on);
}

// The footprint corrects an unrefined pixel's box mean of its corners; Mitchell weighs the
// corners as they are, so under it the correction neither runs nor takes memory (its delta
// had been computed and never read).
TEST(Renderer, TextureFootprintIsTheBoxFiltersOnly) {
  const Scene scene = textured_floor();
  RenderSettings s;
  s.width = 96;
  s.height = 64;
  s.adaptive.filter = Filter::Mitchell;
  const CornerFieldPlan off_plan = corner_field_plan(s);
  const Film off = render(scene, s);
  s.adaptive.footprint = true;
  EXPECT_EQ(corner_field_plan(s).bytes, off_plan.bytes);
  EXPECT_TRUE(bit_identical(off, render(scene, s)));
  s.adaptive.filter = Filter::Box;
  EXPECT_GT(corner_field_plan(s).bytes, off_plan.bytes);  // the box filter's correction takes memory
}

TEST(Renderer, PendingMapFailureIsRethrown) {
  const Scene scene = box_scene();
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  std::shared_future<GeoMap> failing =
      std::async(std::launch::async, []() -> GeoMap { throw std::runtime_error("no map"); });
  Film film;
  RenderStats stats;
  EXPECT_THROW(render_frame(shader, scene.cameras[0], failing, s, film, stats), std::runtime_error);
}

TEST(Tiles, CoverTheFrameExactlyOnce) {
  for (auto [w, h] : {std::pair{1, 1}, {1, 200}, {64, 64}, {65, 129}, {300, 7}}) {
    std::vector<int> cover(size_t(w) * h, 0);
    for (const TileRect& t : centre_out(make_tiles(w, h), w, h))
      for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) ++cover[size_t(y) * w + x];
    for (int c : cover) ASSERT_EQ(c, 1);
  }
}

}  // namespace
}  // namespace zz
