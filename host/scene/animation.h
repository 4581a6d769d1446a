// Keyframe animation of node transforms, sampled the glTF 2.0 way (spec §3.11 and
// Appendix C): LINEAR (slerp for rotations), STEP, and CUBICSPLINE (Hermite with
// tangents scaled by the key interval). Before the first key and after the last, the
// first/last value holds. A scene is loaded at one time; the loader asks for each
// animated node's local transform at that time.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <optional>
#include <vector>

namespace zz {

enum class Interpolation { Linear, Step, CubicSpline };
enum class AnimatedProperty { Translation, Rotation, Scale };

struct AnimationChannel {
  int node = -1;
  AnimatedProperty property = AnimatedProperty::Translation;
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;  // seconds, non-decreasing, at least one
  // One value per key; CUBICSPLINE: three per key (in-tangent, value, out-tangent).
  // vec3 properties use xyz; rotations are quaternions stored (x, y, z, w) as in glTF.
  std::vector<glm::vec4> values;
};

// The channel's value at time t (seconds). Rotations come back unit length.
glm::vec4 sample(const AnimationChannel& channel, float t);

// Spherical linear interpolation along the shorter arc (q and -q are one rotation),
// normalised. Quaternions as glm::quat (w, x, y, z).
glm::quat slerp_shortest(glm::quat a, glm::quat b, float u);

// A node's local transform as glTF composes it: M = T * R * S.
struct NodePose {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
  glm::mat4 matrix() const;
};

struct Animation {
  std::vector<AnimationChannel> channels;

  bool empty() const { return channels.empty(); }
  bool animates(int node) const;
  // The last key time over all channels (0 when there are none).
  float end_time() const;
  // `rest` with every animated property of `node` replaced by its value at t.
  NodePose pose(int node, const NodePose& rest, float t) const;
};

// The frames an animation spans at `fps`: 0 .. ceil(end_time * fps).
int last_frame(float end_time, double fps);

// The largest frame number (--frame): a frame number, not a typo's worth of seconds times fps.
inline constexpr int kMaxFrame = 100000000;

// The frame a time `t` s falls on at `fps`, within 1e-6 of a frame (absolute: frames stay
// 1 apart); none between frames or past kMaxFrame.
std::optional<int> frame_at(double t, double fps);

}  // namespace zz
