// Progressive rendering for the viewer: a background thread runs render_frame() for the
// latest request — first a coarse preview (1 ray/px at reduced size, shown with nearest
// upscaling), then the full frame — and every finished tile goes straight into the
// DisplayFrame. A new request cancels the map and full frame in flight (render_frame stops
// at the next tile) and restarts; the UI thread never waits for a frame.
//
// A preview finishes before the next request starts: cancelled at every mouse event, a
// drag would show a centre of the new pose inside a border of older ones. Its size is
// chosen so that it takes about kPreviewBudget: the scale doubles (up to
// kMaxPreviewScale) while previews take longer, and comes back to the request's when they
// are fast again. A preview that has run kPreviewCutAfter budgets is cut by the next
// request (the first after a resize, say), so no move waits long for it, unless it is
// already at kMaxPreviewScale: a scene too slow for that keeps its previews whole.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/geo_map.h"
#include "render/renderer.h"
#include "scene/camera.h"
#include "viewer/display_frame.h"

namespace zz {

inline constexpr double kPreviewBudget = 1.0 / 30.0;  // seconds a preview may take
inline constexpr int kMaxPreviewScale = 16;
inline constexpr double kPreviewCutAfter = 4.0;  // budgets

// The preview scale after one that took `seconds` at `scale`: the power of two that
// brings the next near kPreviewBudget (its cost goes with the pixels, 1/scale^2), within
// [smallest, kMaxPreviewScale].
int next_preview_scale(int scale, double seconds, int smallest);

struct FrameRequest {
  Camera camera;
  RenderSettings settings;  // width/height = the display size
  int preview_scale = 4;    // the smallest preview scale; 0 or 1: no preview pass
  bool edges = true;        // build the visibility map (when a GeoSource exists)
};

struct ProgressStatus {
  uint64_t request = 0;       // id of the request being (or last) rendered
  uint64_t completed = 0;     // id of the last request whose full frame finished (0: none yet)
  int frames_completed = 0;   // full frames finished since start
  bool preview = false;       // the preview pass is running
  int previews_completed = 0; // previews finished since start (each covers the whole frame)
  uint64_t previewed = 0;     // id of the last request whose preview finished (0: none)
  int preview_scale = 0;      // the scale of the last preview that ran
  int tiles_done = 0;         // full-frame tiles finished for `request`
  int tiles_total = 0;
  double last_preview_seconds = 0.0; // request to finished coarse preview (the latency of a camera move)
  double last_full_seconds = 0.0;   // preview + full render of the last completed frame
  double first_full_seconds = -1.0; // from construction to the first completed frame
  double rays_per_pixel = 0.0;      // primary rays / pixel of the last completed frame
  std::string error;                // set when a frame failed (e.g. the visibility pass threw)
};

class ProgressiveRenderer {
 public:
  // Builds the frame's visibility map on the render thread (may return an empty map, and
  // does once `cancel` is set: a newer request makes this one's map worthless).
  using GeoSource =
      std::function<GeoMap(const Camera& camera, int width, int height, const std::atomic<bool>* cancel)>;

  ProgressiveRenderer(const Shader& shader, DisplayFrame& display, GeoSource geo = {});
  ~ProgressiveRenderer();  // cancels and joins
  ProgressiveRenderer(const ProgressiveRenderer&) = delete;
  ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

  // Replaces whatever is pending or in flight; returns the request's id.
  uint64_t request(const FrameRequest& request);
  ProgressStatus status() const;
  // Blocks until the full frame of request `id` is done (or a newer request replaced it);
  // false on timeout. For tests and scripted runs; the UI never calls it.
  bool wait_for(uint64_t id, double timeout_seconds) const;
  void stop();

 private:
  void run();
  void render(const FrameRequest& request, uint64_t id, std::chrono::steady_clock::time_point requested);

  const Shader& shader_;
  DisplayFrame& display_;
  GeoSource geo_;
  const std::chrono::steady_clock::time_point created_ = std::chrono::steady_clock::now();

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::optional<FrameRequest> pending_;
  uint64_t next_id_ = 0;
  uint64_t pending_id_ = 0;
  bool stopping_ = false;
  ProgressStatus status_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> cut_preview_{false};     // set by stop(), or by a request once the preview ran long
  // When the running preview began, while a request may still cut it (under mutex_).
  std::optional<std::chrono::steady_clock::time_point> preview_began_;
  std::chrono::steady_clock::time_point pending_time_;  // when the pending request was made
  int preview_scale_ = 0;          // render thread only: the next preview's (0: the request's)
  std::atomic<int> tiles_done_{0};
  // The last map made, for the view it was made for (render thread only): a change of eps,
  // filter or AOV view keeps the camera and size, and the map depends on nothing else.
  struct MadeMap {
    Camera camera;
    int width = 0, height = 0;
    GeoMap map;
  };
  std::optional<MadeMap> last_map_;
  // The map of this request's view: the last one if it fits, else a new one (empty when cancelled).
  GeoMap map_for(const Camera& camera, int width, int height);
  std::thread thread_;
};

}  // namespace zz
