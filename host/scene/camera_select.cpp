#include "scene/camera_select.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace zz {

size_t find_camera(const Scene& scene, const std::string& spec) {
  if (!spec.empty() && std::all_of(spec.begin(), spec.end(), [](unsigned char c) { return std::isdigit(c); })) {
    const size_t index = spec.size() <= 9 ? size_t(std::stoul(spec)) : scene.cameras.size();
    if (index < scene.cameras.size()) return index;
    throw Error("camera " + spec + " out of range (the scene has " + std::to_string(scene.cameras.size()) +
                " camera" + (scene.cameras.size() == 1 ? "" : "s") + ")");
  }
  std::vector<size_t> named;
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    if (scene.cameras[i].name == spec) named.push_back(i);
  if (named.size() == 1) return named[0];
  if (named.size() > 1) {
    std::string indices;
    for (size_t i : named) indices += (indices.empty() ? "" : ", ") + std::to_string(i);
    throw Error("camera name '" + spec + "' is ambiguous: cameras " + indices + " have it (give an index, --camera " +
                std::to_string(named[0]) + ")");
  }
  std::string names;
  for (size_t i = 0; i < scene.cameras.size(); ++i)
    names += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  throw Error("no camera named '" + spec + "' (cameras: " + names + ")");
}

namespace {

// Clamped before rounding: a side from an aspect of 1e-30 must not overflow lround.
int clamped_side(double v) { return int(std::lround(std::clamp(v, 1.0, double(kMaxImageSide)))); }

// The frame the scene itself asks for: the rig's sides, a side it does not set from the
// camera's aspect (square where the camera has none: it takes the frame's), 512 on the
// longer side.
FrameSize natural_frame_size(const Scene& scene, float aspect, bool known) {
  const int width = scene.width_given ? scene.default_width : 0;
  const int height = scene.height_given ? scene.default_height : 0;
  if (width > 0 && height > 0) return {width, height};
  if (width > 0) return {width, known ? clamped_side(width / aspect) : width};
  if (height > 0) return {known ? clamped_side(height * aspect) : height, height};
  if (!known) return {scene.default_width, scene.default_height};
  const int longer = std::max(scene.default_width, scene.default_height);
  return aspect >= 1.0f ? FrameSize{longer, clamped_side(longer / aspect)} : FrameSize{clamped_side(longer * aspect), longer};
}

}  // namespace

FrameSize frame_size(const Scene& scene, const Camera& camera, int width, int height) {
  if (width > 0 && height > 0) return {width, height};
  const float aspect = camera.aspect;
  const bool known = std::isfinite(aspect) && aspect > 0.0f;
  const FrameSize natural = natural_frame_size(scene, aspect, known);
  if (width <= 0 && height <= 0) return natural;
  // One side given: the other keeps the natural frame's shape (`--width 96` on a 1024² rig
  // is a 96² preview, not a 96 x 1024 strip), exactly the camera's where the rig does not
  // fix both sides.
  const double shape = known && !(scene.width_given && scene.height_given) ? double(aspect)
                                                                           : double(natural.width) / natural.height;
  if (width > 0) return {width, clamped_side(width / shape)};
  return {clamped_side(height * shape), height};
}

}  // namespace zz
