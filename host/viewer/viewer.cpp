#include "viewer/viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <memory>
#include <optional>

#include "core/error.h"
#include "gpu/device.h"
#include "render/image_io.h"
#include "viewer/display_frame.h"
#include "viewer/orbit_camera.h"
#include "viewer/presenter.h"
#include "viewer/script.h"

namespace zz {

namespace {

constexpr const char* kNoPresentation =
    "no Vulkan driver that can present to this display; install one with `apt-get install "
    "mesa-vulkan-drivers` (lavapipe, CPU), or use `zigzag render`";

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct WindowDeleter {
  void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); }
};

class Viewer {
 public:
  Viewer(const Shader& shader, const ViewerOptions& options);
  ~Viewer();
  int run();

 private:
  // Input, shared by GLFW callbacks and the script.
  void on_key(int key);
  void on_button(int button, bool pressed, double x, double y);
  void on_cursor(double x, double y);
  void on_scroll(double steps);
  void on_framebuffer(int width, int height);
  void on_refresh();

  // Runs a GLFW callback's body: nothing may unwind through GLFW's C frames, so any
  // exception (zz::Interrupted is not a std::exception) is kept for run() to rethrow
  // after the loop, and the window is asked to close.
  template <class F>
  static void guarded(GLFWwindow* w, F&& body) noexcept;

  void restart();
  void camera_moved();
  void save_screenshot(const std::filesystem::path& path);
  void update_title(bool force);
  bool frame_done() const;
  bool view_shown() const;
  void give_up_after_timeout(const char* what);
  // A scripted resize the window manager did not grant within 5 s is given up on.
  void expire_pending_resize();
  // Runs script events until one must wait; false once the viewer should close.
  void step_script();
  // Seconds the front script event has been waiting; its clock starts at the first call.
  double script_waited() {
    if (!script_waiting_since_) script_waiting_since_ = Clock::now();
    return since(*script_waiting_since_);
  }

  const Shader& shader_;
  ViewerOptions options_;
  Clock::time_point start_ = Clock::now();

  std::unique_ptr<GLFWwindow, WindowDeleter> window_;
  std::unique_ptr<VulkanContext> context_;
  std::unique_ptr<Presenter> presenter_;
  DisplayFrame display_;
  std::unique_ptr<ProgressiveRenderer> renderer_;

  Camera camera_;
  OrbitCamera orbit_;
  RenderSettings settings_;
  ViewTweaks tweaks_;
  ViewMode mode_ = ViewMode::Image;
  uint64_t request_ = 0;
  int render_width_ = 0, render_height_ = 0;

  int drag_button_ = -1;
  double last_x_ = 0, last_y_ = 0;
  int screenshots_ = 0;

  std::deque<ScriptEvent> script_;
  std::optional<Clock::time_point> script_waiting_since_;  // the front event's (wait, sleep)
  int pending_width_ = 0, pending_height_ = 0;  // a scripted resize not yet seen
  Clock::time_point pending_since_;
  int exit_code_ = 0;
  double first_frame_since_start_ = -1.0;

  uint64_t presented_version_ = ~uint64_t(0);
  ViewMode presented_mode_ = ViewMode::Image;
  int presented_fb_w_ = 0, presented_fb_h_ = 0;
  // The window lost its contents (exposed, restored) or the last present failed: the
  // picture may be unchanged, but it must be presented again.
  bool needs_present_ = false;
  std::exception_ptr callback_error_;  // the first exception a GLFW callback caught
  Clock::time_point title_time_;
  std::string title_;
};

Viewer* self(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

template <class F>
void Viewer::guarded(GLFWwindow* w, F&& body) noexcept {
  Viewer* v = self(w);
  try {
    body(v);
  } catch (...) {
    if (!v->callback_error_) v->callback_error_ = std::current_exception();
    glfwSetWindowShouldClose(w, GLFW_TRUE);
  }
}

Viewer::Viewer(const Shader& shader, const ViewerOptions& options)
    : shader_(shader), options_(options), camera_(options.camera), settings_(options.settings), tweaks_(options.tweaks) {
  require_display();
  for (const ScriptEvent& e : parse_script(options.script)) script_.push_back(e);

  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  window_.reset(glfwCreateWindow(settings_.width, settings_.height, ("zigzag view - " + options.name).c_str(),
                                 nullptr, nullptr));
  if (!window_) throw Error("cannot open a window (glfwCreateWindow failed); use `zigzag render`");
  glfwSetWindowUserPointer(window_.get(), this);
  glfwSetWindowSizeLimits(window_.get(), 1, 1, kMaxImageSide, kMaxImageSide);  // the renderer's frame limit

  VulkanOptions vk;
  vk.without_vulkan = "use `zigzag render --edges off`";  // the window presents through Vulkan, map or not
  vk.validate = options.validate;
  vk.device_index = options.vk_device;
  uint32_t count = 0;
  const char** extensions = glfwGetRequiredInstanceExtensions(&count);
  if (!extensions) throw Error(kNoPresentation);
  vk.instance_extensions.assign(extensions, extensions + count);
  vk.device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  GLFWwindow* window = window_.get();
  vk.create_surface = [window](VkInstance instance) {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    vk_check(glfwCreateWindowSurface(instance, window, nullptr, &surface), "glfwCreateWindowSurface");
    return surface;
  };
  context_ = VulkanContext::create(vk);
  presenter_ = std::make_unique<Presenter>(*context_);

  ProgressiveRenderer::GeoSource geo;
  if (options.make_geo_source) geo = options.make_geo_source(*context_);
  renderer_ = std::make_unique<ProgressiveRenderer>(shader_, display_, std::move(geo));

  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    guarded(w, [&](Viewer* v) {
      // Held down, only eps steps repeat: a held S wrote 22 screenshots in 1.5 s.
      const bool steps = key == GLFW_KEY_LEFT_BRACKET || key == GLFW_KEY_RIGHT_BRACKET;
      if (action == GLFW_PRESS || (action == GLFW_REPEAT && steps)) v->on_key(key);
    });
  });
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
    guarded(w, [&](Viewer* v) {
      double x, y;
      glfwGetCursorPos(w, &x, &y);
      v->on_button(button, action == GLFW_PRESS, x, y);
    });
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    guarded(w, [&](Viewer* v) { v->on_cursor(x, y); });
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
    guarded(w, [&](Viewer* v) { v->on_scroll(dy); });
  });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int width, int height) {
    guarded(w, [&](Viewer* v) { v->on_framebuffer(width, height); });
  });
  // Uncovered or restored: the finished picture must be shown again although it did not change.
  glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) { guarded(w, [](Viewer* v) { v->on_refresh(); }); });
  glfwSetWindowIconifyCallback(window, [](GLFWwindow* w, int) { guarded(w, [](Viewer* v) { v->on_refresh(); }); });

  orbit_ = orbit_for(camera_, options.scene_centre, options.scene_radius);
  render_width_ = settings_.width;
  render_height_ = settings_.height;
}

Viewer::~Viewer() {
  // Order matters: the render thread may use the context (visibility pass); the surface
  // (owned by the context) must go before its window.
  renderer_.reset();
  presenter_.reset();
  context_.reset();
  window_.reset();
}

void Viewer::restart() {
  FrameRequest r;
  r.camera = camera_;
  r.settings = settings_;
  r.settings.width = render_width_;
  r.settings.height = render_height_;
  apply_tweaks(tweaks_, r.settings);
  r.preview_scale = options_.preview_scale;
  r.edges = tweaks_.edges;
  request_ = renderer_->request(r);
  update_title(true);
}

void Viewer::camera_moved() {
  camera_ = orbit_.camera();
  restart();
}

void Viewer::on_key(int key) {
  switch (key) {
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_.get(), GLFW_TRUE); break;
    case GLFW_KEY_1: mode_ = ViewMode::Image; break;
    case GLFW_KEY_2: mode_ = ViewMode::Rays; break;
    case GLFW_KEY_3: mode_ = ViewMode::Level; break;
    case GLFW_KEY_4: mode_ = ViewMode::Geo; break;
    case GLFW_KEY_R:
      camera_ = options_.camera;  // exactly the scene's camera, not a round trip through the orbit
      orbit_ = orbit_for(camera_, options_.scene_centre, options_.scene_radius);
      restart();
      break;
    case GLFW_KEY_LEFT_BRACKET:
      if (tweaks_.adaptive) tweaks_.eps_down(), restart();
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      if (tweaks_.adaptive) tweaks_.eps_up(), restart();
      break;
    case GLFW_KEY_F:
      if (tweaks_.adaptive) tweaks_.mitchell = !tweaks_.mitchell, restart();
      break;
    case GLFW_KEY_E:
      if (tweaks_.adaptive) tweaks_.edges = !tweaks_.edges, restart();
      break;
    case GLFW_KEY_S: {
      if (!view_shown()) {  // an S pressed as the window opens, before there is an image
        std::fprintf(stderr, "zigzag view: nothing to save yet (the preview is being made); press S again\n");
        break;
      }
      // The next number no file has yet: an earlier session's screenshots stay.
      std::filesystem::path path;
      std::error_code ec;
      do {
        char name[64];
        std::snprintf(name, sizeof name, "zigzag_%s_%03d.png", to_string(mode_), ++screenshots_);
        std::string file = options_.name + "_" + name;
        for (char& c : file)
          if (c == '/') c = '_';
        path = options_.screenshot_dir / file;
      } while (std::filesystem::exists(path, ec) && screenshots_ < 1000000);
      save_screenshot(path);
      break;
    }
    default: break;
  }
  update_title(true);
}

void Viewer::on_button(int button, bool pressed, double x, double y) {
  if (pressed && drag_button_ < 0) {
    drag_button_ = button;
    last_x_ = x;
    last_y_ = y;
  } else if (!pressed && button == drag_button_) {
    drag_button_ = -1;
  }
}

void Viewer::on_cursor(double x, double y) {
  const double dx = x - last_x_, dy = y - last_y_;
  last_x_ = x;
  last_y_ = y;
  if (drag_button_ < 0 || (dx == 0 && dy == 0)) return;
  if (drag_button_ == GLFW_MOUSE_BUTTON_LEFT) orbit_.orbit(float(dx), float(dy), render_height_);
  else orbit_.pan(float(dx), float(dy), render_height_);
  camera_moved();
}

void Viewer::on_scroll(double steps) {
  if (steps == 0) return;
  orbit_.zoom(float(steps));
  camera_moved();
}

void Viewer::on_framebuffer(int width, int height) {
  if (width <= 0 || height <= 0) return;  // minimised: keep the frame, present nothing
  width = std::min(width, kMaxImageSide);     // a high-DPI framebuffer may exceed the window's limit
  height = std::min(height, kMaxImageSide);
  if (width == pending_width_ && height == pending_height_) pending_width_ = pending_height_ = 0;
  if (width == render_width_ && height == render_height_) return;
  render_width_ = width;
  render_height_ = height;
  restart();
}

void Viewer::on_refresh() { needs_present_ = true; }

void Viewer::save_screenshot(const std::filesystem::path& path) {
  // The composed view (not a swapchain read-back): in the image view these are exactly
  // the bytes `zigzag render` writes for the same camera and size.
  int width = 0, height = 0;
  const std::vector<uint8_t> rgb = display_.rgb(mode_, &width, &height);
  try {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    write_rgb8(path, width, height, rgb);
    const ProgressStatus s = renderer_->status();
    if (frame_done())
      std::fprintf(stderr, "zigzag view: saved %s\n", path.string().c_str());
    else  // what the window shows: a preview or finished tiles over it
      std::fprintf(stderr, "zigzag view: saved %s (frame not finished: %d of %d tiles)\n", path.string().c_str(),
                   s.tiles_done, s.tiles_total);
  } catch (const std::exception& e) {
    // Called from GLFW's C callbacks: report, never throw through them.
    std::fprintf(stderr, "zigzag view: error: screenshot %s: %s\n", path.string().c_str(), e.what());
    exit_code_ = 1;
  }
}

bool Viewer::frame_done() const {
  const ProgressStatus s = renderer_->status();
  return s.completed == request_ && pending_width_ == 0;
}

// A script event that waited past --script-timeout fails the run and closes the window.
void Viewer::give_up_after_timeout(const char* what) {
  if (script_waited() <= options_.script_timeout_seconds) return;
  std::fprintf(stderr, "zigzag view: script %s timed out after %g s\n", what, options_.script_timeout_seconds);
  exit_code_ = 1;
  glfwSetWindowShouldClose(window_.get(), GLFW_TRUE);
}

// Whether the window shows this request's image: its preview finished (tiles may still be
// coming over it), or, with no preview (--preview-scale 1), its whole frame. Before that,
// the frame may not even have its size yet.
bool Viewer::view_shown() const {
  return frame_done() || (renderer_->status().previewed == request_ && pending_width_ == 0);
}

void Viewer::expire_pending_resize() {
  if (pending_width_ == 0 || since(pending_since_) <= 5.0) return;
  int fb_w = 0, fb_h = 0;
  glfwGetFramebufferSize(window_.get(), &fb_w, &fb_h);
  std::fprintf(stderr, "zigzag view: the window stayed %dx%d (script asked for %dx%d)\n", fb_w, fb_h, pending_width_,
               pending_height_);
  pending_width_ = pending_height_ = 0;
}

void Viewer::step_script() {
  while (!script_.empty()) {
    ScriptEvent& e = script_.front();
    // A script's screenshot (S too) waits for the first image the window shows: straight
    // after the window opened it came out empty or black, as the race went.
    const bool saves = e.kind == ScriptEvent::Kind::Screenshot || (e.kind == ScriptEvent::Kind::Key && e.text == "S");
    if (saves && !view_shown()) {
      give_up_after_timeout("screenshot");
      return;
    }
    if (saves) script_waiting_since_.reset();
    if (e.kind == ScriptEvent::Kind::Wait) {
      if (!frame_done()) {
        give_up_after_timeout("'wait'");
        return;
      }
      script_waiting_since_.reset();
      const ProgressStatus s = renderer_->status();
      std::fprintf(stderr, "zigzag view: frame %llu complete (%dx%d, preview %.3f s, full %.3f s, %.2f rays/px)\n",
                   (unsigned long long)s.completed, render_width_, render_height_, s.last_preview_seconds,
                   s.last_full_seconds, s.rays_per_pixel);
    } else if (e.kind == ScriptEvent::Kind::Sleep) {
      if (script_waited() < e.steps) return;  // the event loop and the render go on meanwhile
      script_waiting_since_.reset();
    } else if (e.kind == ScriptEvent::Kind::Drag) {
      // The same path as a real drag: press, a few motion events, release.
      on_button(e.button, true, e.x0, e.y0);
      constexpr int kSteps = 8;
      for (int i = 1; i <= kSteps; ++i)
        on_cursor(e.x0 + (e.x1 - e.x0) * i / kSteps, e.y0 + (e.y1 - e.y0) * i / kSteps);
      on_button(e.button, false, e.x1, e.y1);
    } else if (e.kind == ScriptEvent::Kind::Scroll) {
      on_scroll(e.steps);
    } else if (e.kind == ScriptEvent::Kind::Key) {
      static constexpr int kCodes[] = {GLFW_KEY_R, GLFW_KEY_S, GLFW_KEY_F, GLFW_KEY_E,
                                       GLFW_KEY_1, GLFW_KEY_2, GLFW_KEY_3, GLFW_KEY_4,
                                       GLFW_KEY_LEFT_BRACKET, GLFW_KEY_RIGHT_BRACKET, GLFW_KEY_ESCAPE};
      static_assert(std::size(kCodes) == kScriptKeys.size(), "one GLFW key per script key, in order");
      for (size_t k = 0; k < kScriptKeys.size(); ++k)  // parse_script gave one of these names
        if (e.text == kScriptKeys[k]) on_key(kCodes[k]);
    } else if (e.kind == ScriptEvent::Kind::Resize) {
      // X11 reports a framebuffer size only when it changes: asking for the current size
      // must not wait for a report that never comes (it hung --exit-after-frame).
      int fb_w = 0, fb_h = 0;
      glfwGetFramebufferSize(window_.get(), &fb_w, &fb_h);
      const bool same = int(e.x0) == fb_w && int(e.y0) == fb_h;
      pending_width_ = same ? 0 : int(e.x0);
      pending_height_ = same ? 0 : int(e.y0);
      pending_since_ = Clock::now();
      glfwSetWindowSize(window_.get(), int(e.x0), int(e.y0));
    } else if (e.kind == ScriptEvent::Kind::Screenshot) {
      save_screenshot(e.text);
    } else if (e.kind == ScriptEvent::Kind::Quit) {
      glfwSetWindowShouldClose(window_.get(), GLFW_TRUE);
    }
    script_.pop_front();
  }
}

void Viewer::update_title(bool force) {
  if (!force && since(title_time_) < 0.25) return;
  title_time_ = Clock::now();
  const ProgressStatus s = renderer_->status();
  char text[512];
  std::string state;
  if (s.completed == request_ && request_ != 0) state = "done";
  else if (s.preview && s.request == request_) state = "preview";
  else state = std::to_string(s.tiles_done) + "/" + std::to_string(s.tiles_total) + " tiles";
  char knobs[96];
  if (tweaks_.adaptive)
    std::snprintf(knobs, sizeof knobs, "eps %.3g %s edges %s", tweaks_.eps, tweaks_.mitchell ? "mitchell" : "box",
                  tweaks_.edges ? "on" : "off");
  else if (settings_.aa == AaMode::Uniform)
    std::snprintf(knobs, sizeof knobs, "uniform %d spp", settings_.uniform.spp);
  else
    std::snprintf(knobs, sizeof knobs, "no antialiasing");
  std::snprintf(text, sizeof text, "zigzag view - %s - %dx%d - %s%s - %.2f rays/px - last full frame %.2f s - %s - %s",
                options_.name.c_str(), render_width_, render_height_, to_string(mode_),
                mode_ == ViewMode::Geo && !display_.has_geo() ? " (not available)" : "", s.rays_per_pixel,
                s.last_full_seconds, state.c_str(), knobs);
  if (title_ != text) {
    title_ = text;
    glfwSetWindowTitle(window_.get(), text);
  }
}

int Viewer::run() {
  restart();
  GLFWwindow* window = window_.get();
  bool exit_frame_seen = false;
  while (!glfwWindowShouldClose(window)) {
    // Wake at ~60 Hz to show finished tiles; input wakes it earlier.
    glfwWaitEventsTimeout(1.0 / 60.0);
    if (callback_error_) break;
    expire_pending_resize();
    step_script();
    if (const std::string error = renderer_->status().error; !error.empty()) {
      std::fprintf(stderr, "zigzag view: error: %s\n", error.c_str());
      exit_code_ = 1;
      break;
    }
    if (first_frame_since_start_ < 0 && renderer_->status().frames_completed > 0)
      first_frame_since_start_ = since(options_.started);  // within one UI tick (<= 1/60 s)
    if (options_.exit_after_frame && script_.empty() && !exit_frame_seen && frame_done()) {
      exit_frame_seen = true;
      if (!options_.screenshot.empty()) save_screenshot(options_.screenshot);
      glfwSetWindowShouldClose(window, GLFW_TRUE);
    }

    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    const uint64_t version = display_.version();
    if (needs_present_ || version != presented_version_ || mode_ != presented_mode_ || fb_w != presented_fb_w_ ||
        fb_h != presented_fb_h_) {
      // Minimised (0x0) or out of date: nothing was shown, so the next usable size presents
      // even when it is the size presented last.
      needs_present_ = true;
      if (fb_w > 0 && fb_h > 0 && presenter_->present(display_, mode_, uint32_t(fb_w), uint32_t(fb_h))) {
        presented_version_ = version;
        presented_mode_ = mode_;
        presented_fb_w_ = fb_w;
        presented_fb_h_ = fb_h;
        needs_present_ = false;
      }
    }
    update_title(false);
  }

  // Closing mid-render: cancel the tiles in flight and join before tearing down Vulkan.
  renderer_->stop();
  if (callback_error_) std::rethrow_exception(callback_error_);  // ~Viewer tears down
  // Closed (Esc, the window manager, a script's quit) before the frame --screenshot waited
  // for: a caller checking the exit code must not take the missing file for success.
  if (options_.exit_after_frame && !options_.screenshot.empty() && !exit_frame_seen && exit_code_ == 0) {
    std::fprintf(stderr, "zigzag view: error: the window closed before a full frame; %s not written\n",
                 options_.screenshot.string().c_str());
    exit_code_ = 1;
  }
  const ProgressStatus s = renderer_->status();
  if (s.first_full_seconds >= 0)
    std::fprintf(stderr,
                 "zigzag view: first full frame %.3f s after the command started (%.3f s after the render "
                 "thread started); last full frame %.3f s, %.2f rays/px, %d frame(s)\n",
                 first_frame_since_start_, s.first_full_seconds, s.last_full_seconds, s.rays_per_pixel,
                 s.frames_completed);
  // Everything on the device is destroyed, then the device (close): misuse while destroying
  // and objects left alive, which vkDestroyDevice reports, are in the count.
  renderer_.reset();  // holds the visibility pass
  presenter_.reset();
  context_->close();
  if (options_.validate) {
    const int messages = context_->validation_message_count();
    std::fprintf(stderr, "zigzag view: %d Vulkan validation message(s)\n", messages);
    if (messages > 0 && exit_code_ == 0) exit_code_ = 3;
  }
  return exit_code_;
}

}  // namespace

void require_display() {
  static bool ready = false;
  if (ready) return;
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x11 || !*x11) && (!wayland || !*wayland)) throw Error("no display; use `zigzag render`");
  if (!glfwInit()) {
    const char* why = nullptr;
    glfwGetError(&why);
    throw Error(std::string("no display") + (why ? " (" + std::string(why) + ")" : "") + "; use `zigzag render`");
  }
  std::atexit(glfwTerminate);
  // Before the scene loads: without a Vulkan driver the window could never show it.
  uint32_t extensions = 0;
  if (!glfwVulkanSupported() || !glfwGetRequiredInstanceExtensions(&extensions)) throw Error(kNoPresentation);
  ready = true;
}

int run_viewer(const Shader& shader, const ViewerOptions& options) {
  Viewer viewer(shader, options);
  return viewer.run();
}

}  // namespace zz
