#include "scene/camera_select.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace zz {

size_t find_camera(const Scene& scene, const std::string& spec) {
  if (!spec.empty() && std::all_of(spec.begin(), spec.end(), [](unsigned char c) { return std::isdigit(c); })) {
    const size_t index = spec.size() <= 9 ? size_t(std::stoul(spec)) : scene.cameras.size();
    if (index < scene.cameras.size()) return index;
    throw Error("camera " + spec + " out of range (the scene has " + std::to_string(scene.cameras.size()) +
                " camera" + (scene.cameras.size() == 1 ? "" : "s") + ")");
  }
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    if (scene.cameras[i].name == spec) return i;
  std::string names;
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    names += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  throw Error("no camera named '" + spec + "' (cameras: " + names + ")");
}

FrameSize frame_size(const Scene& scene, const Camera& camera, int width, int height) {
  if (width <= 0 && scene.width_given) width = scene.default_width;
  if (height <= 0 && scene.height_given) height = scene.default_height;
  const float aspect = camera.aspect;
  const bool known = std::isfinite(aspect) && aspect > 0.0f;
  auto side = [](double v) { return int(std::clamp(std::lround(v), 1L, long(kMaxImageSide))); };
  if (width > 0 && height > 0) return {width, height};
  if (width > 0) return {width, known ? side(width / aspect) : scene.default_height};
  if (height > 0) return {known ? side(height * aspect) : scene.default_width, height};
  if (!known) return {scene.default_width, scene.default_height};
  const int longer = std::max(scene.default_width, scene.default_height);
  return aspect >= 1.0f ? FrameSize{longer, side(longer / aspect)} : FrameSize{side(longer * aspect), longer};
}

}  // namespace zz
