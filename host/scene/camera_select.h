// Choosing a scene camera from the command line, and the frame size it implies.
#pragma once

#include <cstddef>
#include <string>

#include "scene/scene.h"

namespace zz {

// The camera `spec` names: an index ("0", "2") or a camera's name (first match). Throws a
// zz::Error listing the cameras when nothing matches.
size_t find_camera(const Scene& scene, const std::string& spec);

struct FrameSize {
  int width = 0;
  int height = 0;
};

// The image size for `camera`. A side given on the command line (> 0) or by the rig wins,
// in that order; a missing side follows the camera's aspect ratio (width / height) when the
// camera has one, else the scene default (512). With neither side given the longer side is
// the scene's default size.
FrameSize frame_size(const Scene& scene, const Camera& camera, int width = 0, int height = 0);

}  // namespace zz
