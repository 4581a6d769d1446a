// The `zigzag view` window: GLFW (no client API) + a Vulkan swapchain on the gpu
// module's VulkanContext, progressive tiles from a background render thread, orbit/pan/
// zoom camera, AOV views and screenshots. The UI loop only polls events and presents
// when the picture changed; it never waits for a frame.
#pragma once

#include <glm/glm.hpp>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>

#include "render/renderer.h"
#include "scene/camera.h"
#include "viewer/progressive_renderer.h"
#include "viewer/view_tweaks.h"

namespace zz {

class VulkanContext;

struct ViewerOptions {
  std::string name = "scene";  // shown in the title and screenshot names
  // When the command started (before scene loading): the exit summary reports the time
  // to the first full frame from here as well as from the window opening.
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  Camera camera;               // start (and reset) pose
  glm::vec3 scene_centre{0.0f};
  float scene_radius = 1.0f;
  RenderSettings settings;  // width/height = initial window size
  ViewTweaks tweaks;
  int preview_scale = 4;    // coarse pass at 1/preview_scale size; 1 = none

  bool validate = false;  // Vulkan validation layers; any message makes run() return non-zero
  int vk_device = -1;     // VulkanOptions::device_index
  std::filesystem::path screenshot_dir = ".";
  bool exit_after_frame = false;       // quit after the first full frame (after the script)
  std::filesystem::path screenshot;    // saved before quitting with exit_after_frame
  std::string script;                  // scripted input (viewer/script.h)
  double script_timeout_seconds = 600; // a `wait` longer than this fails the run

  // Optional visibility map for a frame, built on the render thread with the viewer's
  // Vulkan context (which serialises the queue shared with the presenter itself).
  std::function<ProgressiveRenderer::GeoSource(VulkanContext& context)> make_geo_source;
};

// Makes sure a window can be opened (GLFW initialised with a display); throws zz::Error
// "no display; use `zigzag render`" otherwise. Idempotent; cheap enough to call first.
void require_display();

// Opens the window and runs until Esc / close / the script or exit-after-frame ends it.
// Returns the process exit code: 0, or non-zero on validation messages or a script
// failure. Throws zz::Error on setup failures (no Vulkan device, ...).
int run_viewer(const Shader& shader, const ViewerOptions& options);

}  // namespace zz
