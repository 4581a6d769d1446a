#include "viewer/progressive_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.h"

namespace zz {

int next_preview_scale(int scale, double seconds, int smallest) {
  const double wanted = scale * std::sqrt(std::max(seconds, 0.0) / kPreviewBudget);
  int next = std::max(smallest, 1);
  while (next < wanted && next < kMaxPreviewScale) next *= 2;
  return std::max(smallest, std::min(next, kMaxPreviewScale));
}

ProgressiveRenderer::ProgressiveRenderer(const Shader& shader, DisplayFrame& display, GeoSource geo)
    : shader_(shader), display_(display), geo_(std::move(geo)) {
  thread_ = std::thread([this] { run(); });
}

ProgressiveRenderer::~ProgressiveRenderer() { stop(); }

void ProgressiveRenderer::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    cancel_ = true;
    cut_preview_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

uint64_t ProgressiveRenderer::request(const FrameRequest& request) {
  uint64_t id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    id = ++next_id_;
    pending_ = request;
    pending_id_ = id;
    pending_time_ = std::chrono::steady_clock::now();
    cancel_ = true;  // the frame in flight stops at its next tile
    // A preview in flight finishes, unless it has already run far over its budget.
    if (preview_began_ &&
        std::chrono::duration<double>(pending_time_ - *preview_began_).count() > kPreviewCutAfter * kPreviewBudget)
      cut_preview_ = true;
  }
  changed_.notify_all();
  return id;
}

ProgressStatus ProgressiveRenderer::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  ProgressStatus s = status_;
  s.tiles_done = tiles_done_.load();
  return s;
}

bool ProgressiveRenderer::wait_for(uint64_t id, double timeout_seconds) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, std::chrono::duration<double>(timeout_seconds),
                           [&] { return stopping_ || status_.completed >= id || next_id_ > id || !status_.error.empty(); });
}

void ProgressiveRenderer::run() {
  for (;;) {
    FrameRequest request;
    uint64_t id;
    std::chrono::steady_clock::time_point requested;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return stopping_ || pending_.has_value(); });
      if (stopping_) return;
      request = std::move(*pending_);
      pending_.reset();
      id = pending_id_;
      requested = pending_time_;
      cancel_ = false;  // under the lock: a request() after this point cancels this frame
    }
    try {
      render(request, id, requested);
    } catch (const std::exception& e) {
      // Reported through status(): the UI thread decides how to fail, this thread lives on.
      std::lock_guard<std::mutex> lock(mutex_);
      status_.error = error_text(e);
    }
    changed_.notify_all();
  }
}

namespace {

bool same_view(const Camera& a, const Camera& b) {
  return a.position == b.position && a.right == b.right && a.up == b.up && a.forward == b.forward && a.yfov == b.yfov &&
         a.ymag == b.ymag;
}

}  // namespace

GeoMap ProgressiveRenderer::map_for(const Camera& camera, int width, int height) {
  if (last_map_ && last_map_->width == width && last_map_->height == height && same_view(last_map_->camera, camera))
    return last_map_->map;
  display_.set_geo(GeoMap{});  // the geo view says "not available" rather than show the last view's map
  GeoMap map = geo_(camera, width, height, &cancel_);
  if (cancel_) return {};
  last_map_ = MadeMap{camera, width, height, map};
  return map;
}

void ProgressiveRenderer::render(const FrameRequest& request, uint64_t id,
                                 std::chrono::steady_clock::time_point requested) {
  const auto start = requested;  // latencies count the wait behind the preview in flight
  const RenderSettings& full = request.settings;
  display_.resize(full.width, full.height);
  const int full_tiles = int(make_tiles(full.width, full.height, full.tile_size).size());
  tiles_done_ = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.request = id;
    status_.tiles_total = full_tiles;
    status_.preview = request.preview_scale > 1;
  }

  RenderCallbacks callbacks;

  if (request.preview_scale > 1) {
    // 1 ray/px at reduced size: cheap enough to follow the mouse, then refined below.
    // A newer request waits for it, unless it runs far over its budget (see the header).
    const int s = std::max(preview_scale_, request.preview_scale);
    RenderSettings preview = full;
    preview.width = std::max(1, (full.width + s - 1) / s);
    preview.height = std::max(1, (full.height + s - 1) / s);
    preview.aa = AaMode::None;
    preview.centre_out = true;
    Film film;
    RenderStats stats;
    callbacks.cancel = &cut_preview_;
    callbacks.tile_done = [&](const TileRect& rect, const RayCounters&) { display_.put_tile(film, rect, s, full.tonemap); };
    const auto preview_start = std::chrono::steady_clock::now();
    {
      std::lock_guard<std::mutex> lock(mutex_);  // with request(): a cut is either seen here or not at all
      if (stopping_) return;
      cut_preview_ = false;
      // At the smallest size a preview can have, cutting it would only leave older poses
      // on screen for good: such a preview always finishes.
      if (s < kMaxPreviewScale) preview_began_ = preview_start;
    }
    render_frame(shader_, request.camera, GeoMap{}, preview, film, stats, callbacks);
    const double preview_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - preview_start).count();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      preview_began_.reset();
    }
    // A cut preview took over kPreviewCutAfter budgets for part of the frame: smaller still.
    preview_scale_ = next_preview_scale(s, preview_s, request.preview_scale);
    if (cut_preview_) return;  // stop(), or a newer request: it starts now
    {
      std::lock_guard<std::mutex> lock(mutex_);
      status_.last_preview_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++status_.previews_completed;
      status_.previewed = id;
      status_.preview_scale = s;
    }
    changed_.notify_all();
    if (cancel_) return;
  }
  callbacks.cancel = &cancel_;

  // The visibility map after the preview, so the first coarse picture is not delayed.
  const GeoMap geo = geo_ && request.edges ? map_for(request.camera, full.width, full.height) : GeoMap{};
  if (cancel_) return;
  display_.set_geo(geo);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.preview = false;
  }
  RenderSettings settings = full;
  settings.centre_out = true;
  // Corners per tile: tiles appear from the first one on, instead of after level 1 of the
  // whole frame; the same image, for ~0.1 more rays/px (aa/corner_field.h).
  settings.corner_field = false;
  Film film;
  RenderStats stats;
  callbacks.tile_done = [&](const TileRect& rect, const RayCounters&) {
    display_.put_tile(film, rect, 1, full.tonemap);
    ++tiles_done_;
  };
  render_frame(shader_, request.camera, geo, settings, film, stats, callbacks);
  if (stats.cancelled || cancel_) return;

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.completed = id;
    ++status_.frames_completed;
    status_.last_full_seconds = seconds;
    status_.rays_per_pixel = double(stats.rays.primary) / (double(full.width) * full.height);
    if (status_.first_full_seconds < 0)
      status_.first_full_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - created_).count();
  }
  changed_.notify_all();
}

}  // namespace zz
