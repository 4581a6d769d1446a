// Choosing a scene camera from the command line, and the frame size it implies.
#pragma once

#include <cstddef>
#include <string>

#include "scene/scene.h"

namespace zz {

// The camera `spec` names: an index ("0", "2") or a camera's name. Throws a zz::Error
// listing the cameras when nothing matches, and one giving the indices when several
// cameras have that name (a batch must not render another camera than it was told).
size_t find_camera(const Scene& scene, const std::string& spec);

struct FrameSize {
  int width = 0;
  int height = 0;
};

// The image size for `camera`. Without sides from the command line (> 0): the rig's, a side
// it does not set following the camera's aspect ratio (width / height), 512 on the longer
// side. Both sides given: those. One side given: the other keeps that natural frame's
// aspect (the camera's, unless the rig sets both sides).
FrameSize frame_size(const Scene& scene, const Camera& camera, int width = 0, int height = 0);

}  // namespace zz
