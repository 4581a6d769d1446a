#include "scene/gltf_animation.h"

#include <tiny_gltf.h>

#include <cmath>

#include "core/error.h"
#include "scene/gltf_accessor.h"

namespace zz::gltf {

Animation read_animations(const tinygltf::Model& model, const std::string& file,
                          const std::function<void(const std::string&)>& warn) {
  Animation out;
  if (model.animations.size() > 1)
    warn(std::to_string(model.animations.size()) +
         " animations play together on one clock (a node two of them move takes the later one's pose)");
  for (size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& anim = model.animations[a];
    const std::string name = "animation '" + (anim.name.empty() ? std::to_string(a) : anim.name) + "'";
    for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
      const tinygltf::AnimationChannel& ch = anim.channels[ci];
      const std::string where = file + ": " + name + " channel " + std::to_string(ci);
      AnimationChannel c;
      if (ch.target_path == "translation") c.property = AnimatedProperty::Translation;
      else if (ch.target_path == "rotation") c.property = AnimatedProperty::Rotation;
      else if (ch.target_path == "scale") c.property = AnimatedProperty::Scale;
      else {
        warn(name + " channel " + std::to_string(ci) + " animates '" + ch.target_path + "' (not supported), skipped");
        continue;
      }
      if (ch.target_node < 0) continue;  // the spec allows a target without a node (an extension's)
      if (size_t(ch.target_node) >= model.nodes.size())
        throw Error(where + ": node " + std::to_string(ch.target_node) + " out of range");
      c.node = ch.target_node;
      if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size())
        throw Error(where + ": sampler " + std::to_string(ch.sampler) + " out of range");
      const tinygltf::AnimationSampler& s = anim.samplers[size_t(ch.sampler)];
      if (s.interpolation.empty() || s.interpolation == "LINEAR") c.interpolation = Interpolation::Linear;
      else if (s.interpolation == "STEP") c.interpolation = Interpolation::Step;
      else if (s.interpolation == "CUBICSPLINE") c.interpolation = Interpolation::CubicSpline;
      else throw Error(where + ": unknown interpolation '" + s.interpolation + "'");

      c.times = read_floats(model, s.input, 1, where + " input");
      if (c.times.empty()) throw Error(where + ": no keyframes");
      for (size_t k = 0; k < c.times.size(); ++k)
        if (!std::isfinite(c.times[k]) || c.times[k] < 0.0f || (k > 0 && c.times[k] < c.times[k - 1]))
          throw Error(where + ": keyframe times must be finite, non-negative and increasing");
      const int components = c.property == AnimatedProperty::Rotation ? 4 : 3;
      const std::vector<float> v = read_floats(model, s.output, components, where + " output");
      const size_t per_key = c.interpolation == Interpolation::CubicSpline ? 3 : 1;
      if (v.size() != c.times.size() * per_key * size_t(components))
        throw Error(where + ": " + std::to_string(v.size() / size_t(components)) + " output values for " +
                    std::to_string(c.times.size()) + " keyframes (need " + std::to_string(per_key) + " per key)");
      for (float f : v)
        if (!std::isfinite(f)) throw Error(where + ": NaN/Inf in output values");
      c.values.resize(v.size() / size_t(components));
      for (size_t i = 0; i < c.values.size(); ++i) {
        const float* p = &v[i * size_t(components)];
        c.values[i] = glm::vec4(p[0], p[1], p[2], components == 4 ? p[3] : 0.0f);
      }
      out.channels.push_back(std::move(c));
    }
  }
  return out;
}

NodePose rest_pose(const tinygltf::Node& n) {
  NodePose p;
  if (n.translation.size() == 3) p.translation = glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]));
  if (n.rotation.size() == 4) {
    const glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));
    const float len = glm::length(q);
    if (len > 0.0f && std::isfinite(len)) p.rotation = q / len;
  }
  if (n.scale.size() == 3) p.scale = glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2]));
  return p;
}

}  // namespace zz::gltf
