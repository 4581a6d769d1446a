// glTF animations -> Animation: every channel of every animation that targets a node's
// translation, rotation or scale (all animations play together, on one clock). Morph
// target weights are not supported and are skipped with a warning.
#pragma once

#include <functional>
#include <string>

#include "scene/animation.h"

namespace tinygltf {
class Model;
class Node;
}  // namespace tinygltf

namespace zz::gltf {

// Throws zz::Error naming the file for malformed samplers (bad accessors, key counts,
// non-finite or decreasing times, unknown interpolation).
Animation read_animations(const tinygltf::Model& model, const std::string& file,
                          const std::function<void(const std::string&)>& warn);

// The node's own translation, rotation (normalised) and scale, defaults where absent.
NodePose rest_pose(const tinygltf::Node& node);

}  // namespace zz::gltf
