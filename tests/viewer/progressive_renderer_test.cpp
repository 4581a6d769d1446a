#include "viewer/progressive_renderer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include "accel/bvh.h"
#include "render/image_io.h"
#include "scene/loader.h"

namespace zz {
namespace {

class Progressive : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::filesystem::path path = std::string(ZZ_SOURCE_DIR) + "/scenes/default.json";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing (scenes/ not generated)";
    LoadOptions load;
    load.quiet = true;
    scene_ = load_scene(path, load);
    bvh_ = Bvh::build(scene_.positions);
    shader_ = std::make_unique<Shader>(scene_, bvh_);
  }

  FrameRequest request(int w, int h, AaMode aa = AaMode::Adaptive) const {
    FrameRequest r;
    r.camera = scene_.cameras[0];
    r.settings.width = w;
    r.settings.height = h;
    r.settings.aa = aa;
    r.settings.tonemap.exposure = scene_.exposure;
    r.settings.threads = 2;
    return r;
  }

  Scene scene_;
  Bvh bvh_;
  std::unique_ptr<Shader> shader_;
};

TEST_F(Progressive, FullFrameEqualsABatchRender) {
  DisplayFrame display;
  ProgressiveRenderer renderer(*shader_, display);
  const FrameRequest r = request(150, 100);
  const uint64_t id = renderer.request(r);
  ASSERT_TRUE(renderer.wait_for(id, 120.0));
  const ProgressStatus s = renderer.status();
  EXPECT_EQ(s.completed, id);
  EXPECT_EQ(s.frames_completed, 1);
  EXPECT_EQ(s.tiles_done, s.tiles_total);
  EXPECT_EQ(s.tiles_total, 3 * 2);
  EXPECT_GE(s.rays_per_pixel, 1.0);

  // The batch path traces level 1 for the whole frame first; the viewer per tile, so tiles
  // show from the first one on: the same image, the per-tile path's rays.
  Film film, per_tile;
  RenderStats stats, per_tile_stats;
  render_frame(*shader_, r.camera, GeoMap{}, r.settings, film, stats);
  EXPECT_EQ(display.rgb(ViewMode::Image), display_bytes(film, r.settings.tonemap));
  RenderSettings tiled = r.settings;
  tiled.corner_field = false;
  render_frame(*shader_, r.camera, GeoMap{}, tiled, per_tile, per_tile_stats);
  EXPECT_DOUBLE_EQ(s.rays_per_pixel, double(per_tile_stats.rays.primary) / (150.0 * 100.0));
  EXPECT_GT(per_tile_stats.rays.primary, stats.rays.primary);
}

// The map depends on the view only: a new eps (or filter) at the same camera and size
// reuses it; a new camera makes a new one. The source sees the request's cancel flag.
TEST_F(Progressive, TheMapIsMadeOncePerViewAndSeesTheCancelFlag) {
  DisplayFrame display;
  std::atomic<int> made{0};
  std::atomic<bool> saw_cancel_flag{false};
  ProgressiveRenderer::GeoSource source = [&](const Camera&, int w, int h, const std::atomic<bool>* cancel) {
    ++made;
    saw_cancel_flag = cancel != nullptr;
    GeoMap map{w, h, std::vector<uint8_t>(size_t(w) * h, 0)};
    map.flags[0] = kGeoEdge;
    return map;
  };
  ProgressiveRenderer renderer(*shader_, display, source);
  FrameRequest r = request(64, 48);
  ASSERT_TRUE(renderer.wait_for(renderer.request(r), 120.0));
  EXPECT_EQ(made, 1);
  EXPECT_TRUE(saw_cancel_flag);
  EXPECT_TRUE(display.has_geo());
  r.settings.adaptive.eps = 0.1f;
  ASSERT_TRUE(renderer.wait_for(renderer.request(r), 120.0));
  EXPECT_EQ(made, 1);
  r.camera.position += glm::vec3(0.1f, 0.0f, 0.0f);
  ASSERT_TRUE(renderer.wait_for(renderer.request(r), 120.0));
  EXPECT_EQ(made, 2);
  r.settings.width = 80;  // another size: another map
  ASSERT_TRUE(renderer.wait_for(renderer.request(r), 120.0));
  EXPECT_EQ(made, 3);
}

TEST_F(Progressive, ANewRequestCancelsTheOldOneAndWins) {
  DisplayFrame display;
  ProgressiveRenderer renderer(*shader_, display);
  FrameRequest slow = request(800, 600, AaMode::Uniform);
  slow.settings.uniform = {UniformPattern::Stratified, 64};
  slow.preview_scale = 1;  // no preview: `b` cancels the tiles
  const uint64_t a = renderer.request(slow);
  // Only once the render thread has taken `a` does `b` cancel a frame in flight (before,
  // it would merely replace a pending request). Up to 30 s on a loaded machine.
  for (int i = 0; i < 3000 && renderer.status().request != a; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(renderer.status().request, a);
  ASSERT_NE(renderer.status().completed, a);  // 800 x 600 x 64 samples: far from done
  const uint64_t b = renderer.request(request(64, 48));
  EXPECT_GT(b, a);
  ASSERT_TRUE(renderer.wait_for(b, 120.0));
  const ProgressStatus s = renderer.status();
  EXPECT_EQ(s.completed, b);
  EXPECT_EQ(s.frames_completed, 1);  // the slow frame never completed
  EXPECT_EQ(display.width(), 64);
  EXPECT_EQ(display.height(), 48);
}

TEST_F(Progressive, DestroyingMidFrameCancelsAndJoins) {
  DisplayFrame display;
  auto renderer = std::make_unique<ProgressiveRenderer>(*shader_, display);
  FrameRequest slow = request(1024, 768, AaMode::Uniform);
  slow.settings.uniform = {UniformPattern::Stratified, 256};
  // No preview: a slow machine could still be in it after the sleep, and the cancel timed
  // below is the tiles' (a tile of 256 points per pixel is a million rays).
  slow.preview_scale = 1;
  const uint64_t id = renderer->request(slow);
  // Wait (up to 30 s on a loaded machine) until the render thread has taken the request.
  for (int i = 0; i < 3000 && renderer->status().request != id; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  // Mid-frame: 1024 x 768 x 256 samples take far longer than 200 ms.
  const ProgressStatus before = renderer->status();
  ASSERT_EQ(before.request, id);
  ASSERT_FALSE(before.preview);
  EXPECT_EQ(before.frames_completed, 0);
  EXPECT_NE(before.completed, id);
  EXPECT_GT(before.tiles_total, 0);
  EXPECT_LT(before.tiles_done, before.tiles_total);
  const auto t0 = std::chrono::steady_clock::now();
  renderer.reset();  // must return (cancel at the next tile), not finish the frame
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // A tile of this frame takes well under a second; finishing the frame would take
  // minutes. The bound is loose for a noisy 2-core machine.
  EXPECT_LT(seconds, 10.0);
}

TEST_F(Progressive, PreviewIsFullyReplacedByTheFullFrame) {
  DisplayFrame display;
  ProgressiveRenderer renderer(*shader_, display);
  FrameRequest r = request(128, 96);
  r.preview_scale = 4;
  const uint64_t id = renderer.request(r);
  ASSERT_TRUE(renderer.wait_for(id, 120.0));
  // The preview ran (set only when it finished): otherwise there was nothing to replace.
  EXPECT_GT(renderer.status().last_preview_seconds, 0.0);
  // The full frame overwrote every preview pixel: the result equals a run without preview.
  DisplayFrame direct;
  ProgressiveRenderer renderer2(*shader_, direct);
  r.preview_scale = 1;
  ASSERT_TRUE(renderer2.wait_for(renderer2.request(r), 120.0));
  EXPECT_EQ(renderer2.status().last_preview_seconds, 0.0);
  EXPECT_EQ(display.rgb(ViewMode::Image), direct.rgb(ViewMode::Image));
  EXPECT_EQ(display.rgb(ViewMode::Rays), direct.rgb(ViewMode::Rays));
}

// A preview far over its budget (the first after a resize, or a slow scene at 1/16) is
// cut by the next request once it has run kPreviewCutAfter budgets, so a move never waits
// for it; the next previews are smaller.
TEST_F(Progressive, APreviewFarOverItsBudgetIsCutByTheNextRequest) {
  DisplayFrame display;
  ProgressiveRenderer renderer(*shader_, display);
  FrameRequest slow = request(6144, 6144);  // a 3072^2 preview: seconds of rays
  slow.preview_scale = 2;
  const uint64_t a = renderer.request(slow);
  for (int i = 0; i < 3000 && renderer.status().request != a; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(renderer.status().request, a);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // over 4 budgets (133 ms)
  FrameRequest next = request(64, 48);
  next.preview_scale = 2;
  const uint64_t b = renderer.request(next);
  ASSERT_TRUE(renderer.wait_for(b, 120.0));
  const ProgressStatus s = renderer.status();
  EXPECT_EQ(s.completed, b);
  EXPECT_EQ(s.previews_completed, 1);  // b's: a's was cut
  EXPECT_GT(s.last_preview_seconds, 0.0);
}

TEST(PreviewScale, GrowsWithTheTimeAPreviewTookAndComesBack) {
  EXPECT_EQ(next_preview_scale(4, kPreviewBudget, 4), 4);         // on budget: kept
  EXPECT_EQ(next_preview_scale(4, 4.0 * kPreviewBudget, 4), 8);   // 4x the pixels' time: half the side
  EXPECT_EQ(next_preview_scale(4, 5.0 * kPreviewBudget, 4), 16);  // a little more: a quarter
  EXPECT_EQ(next_preview_scale(8, 1000.0, 4), kMaxPreviewScale);
  EXPECT_EQ(next_preview_scale(16, 0.001, 4), 4);                  // fast again: the request's
  EXPECT_EQ(next_preview_scale(16, 0.2 * kPreviewBudget, 2), 8);
  EXPECT_EQ(next_preview_scale(32, 1000.0, 32), 32);               // never below the request's
}

// A drag sends a request per mouse event, faster than a preview takes. Each preview
// finishes all the same (one that a newer request cut short would leave the border of
// the frame showing older poses; before, none finished until the drag stopped), and the
// newest request's frame completes. The first preview, 2048 x 1536 rays, takes far over
// the budget on any CPU, so the next ones are smaller.
TEST_F(Progressive, PreviewsFinishWhileRequestsStreamIn) {
  DisplayFrame display;
  ProgressiveRenderer renderer(*shader_, display);
  FrameRequest r = request(4096, 3072);
  r.preview_scale = 2;
  const auto start = std::chrono::steady_clock::now();
  int sent = 0;
  while (renderer.status().previews_completed < 4 && std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
    r.camera.position += glm::vec3(0.001f, 0.0f, 0.0f);
    renderer.request(r);
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const ProgressStatus during = renderer.status();
  EXPECT_GE(during.previews_completed, 4) << sent << " requests";
  EXPECT_GT(sent, 2 * during.previews_completed);  // the stream outran them: the newest is taken, not each
  EXPECT_GE(during.preview_scale, 4);              // over budget: smaller previews
  EXPECT_LE(during.preview_scale, kMaxPreviewScale);
  EXPECT_EQ(during.completed, 0u);                 // no full frame while the camera moves
  r.settings.width = 96;  // a small last frame, so the wait is short
  r.settings.height = 64;
  const uint64_t last = renderer.request(r);
  ASSERT_TRUE(renderer.wait_for(last, 120.0));
  EXPECT_EQ(renderer.status().completed, last);
}

}  // namespace
}  // namespace zz
