#include "scene/animation.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace zz {

namespace {

glm::quat as_quat(const glm::vec4& v) { return glm::quat(v.w, v.x, v.y, v.z); }
glm::vec4 as_vec4(const glm::quat& q) { return glm::vec4(q.x, q.y, q.z, q.w); }

glm::vec4 normalized_rotation(glm::vec4 v) {
  const float len = glm::length(v);
  return len > 0.0f && std::isfinite(len) ? v / len : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
}

}  // namespace

glm::quat slerp_shortest(glm::quat a, glm::quat b, float u) {
  float cos_theta = glm::dot(a, b);
  if (cos_theta < 0.0f) {  // the other way round the 4D sphere is the shorter arc
    b = -b;
    cos_theta = -cos_theta;
  }
  glm::quat q;
  if (cos_theta > 0.9995f) {  // nearly parallel: lerp avoids dividing by sin(theta) ~ 0
    q = a * (1.0f - u) + b * u;
  } else {
    const float theta = std::acos(std::min(cos_theta, 1.0f));
    const float s = std::sin(theta);
    q = a * (std::sin((1.0f - u) * theta) / s) + b * (std::sin(u * theta) / s);
  }
  return glm::normalize(q);
}

glm::vec4 sample(const AnimationChannel& c, float t) {
  const size_t n = c.times.size();
  const bool cubic = c.interpolation == Interpolation::CubicSpline;
  auto value = [&](size_t k) { return cubic ? c.values[3 * k + 1] : c.values[k]; };
  const bool rotation = c.property == AnimatedProperty::Rotation;
  auto finish = [&](glm::vec4 v) { return rotation ? normalized_rotation(v) : v; };
  if (n == 0) return rotation ? glm::vec4(0, 0, 0, 1) : glm::vec4(0.0f);
  if (!(t > c.times.front())) return finish(value(0));  // NaN t also clamps to the start
  if (t >= c.times.back()) return finish(value(n - 1));
  // The interval [t_k, t_k+1) holding t (upper_bound skips keys with equal times).
  const size_t k = size_t(std::upper_bound(c.times.begin(), c.times.end(), t) - c.times.begin()) - 1;
  const float t0 = c.times[k], t1 = c.times[k + 1], dt = t1 - t0;
  const float u = (t - t0) / dt;
  switch (c.interpolation) {
    case Interpolation::Step:
      return finish(value(k));
    case Interpolation::Linear:
      if (rotation) return as_vec4(slerp_shortest(as_quat(value(k)), as_quat(value(k + 1)), u));
      return value(k) * (1.0f - u) + value(k + 1) * u;
    case Interpolation::CubicSpline: {
      // glTF Appendix C: p(u) = (2u³-3u²+1) v_k + (u³-2u²+u) dt b_k + (-2u³+3u²) v_k+1 + (u³-u²) dt a_k+1
      const float u2 = u * u, u3 = u2 * u;
      const glm::vec4 vk = c.values[3 * k + 1], bk = c.values[3 * k + 2];
      const glm::vec4 vk1 = c.values[3 * (k + 1) + 1], ak1 = c.values[3 * (k + 1)];
      return finish((2 * u3 - 3 * u2 + 1) * vk + (u3 - 2 * u2 + u) * dt * bk + (-2 * u3 + 3 * u2) * vk1 +
                    (u3 - u2) * dt * ak1);
    }
  }
  return finish(value(k));
}

glm::mat4 NodePose::matrix() const {
  return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) *
         glm::scale(glm::mat4(1.0f), scale);
}

bool Animation::animates(int node) const {
  return std::any_of(channels.begin(), channels.end(), [&](const AnimationChannel& c) { return c.node == node; });
}

float Animation::end_time() const {
  float end = 0.0f;
  for (const AnimationChannel& c : channels)
    if (!c.times.empty()) end = std::max(end, c.times.back());
  return end;
}

NodePose Animation::pose(int node, const NodePose& rest, float t) const {
  NodePose p = rest;
  for (const AnimationChannel& c : channels) {
    if (c.node != node) continue;
    const glm::vec4 v = sample(c, t);
    switch (c.property) {
      case AnimatedProperty::Translation: p.translation = glm::vec3(v); break;
      case AnimatedProperty::Rotation: p.rotation = as_quat(v); break;
      case AnimatedProperty::Scale: p.scale = glm::vec3(v); break;
    }
  }
  return p;
}

int last_frame(float end_time, double fps) {
  // The tolerance keeps float key times (47/24 s is not exact) from adding a frame.
  const double frames = std::ceil(double(end_time) * fps - 1e-4);
  return frames > 0.0 ? int(std::min(frames, 1e8)) : 0;
}

std::optional<int> frame_at(double t, double fps) {
  const double at = t * fps, nearest = std::round(at);
  if (std::abs(at - nearest) <= 1e-6 && nearest >= 0.0 && nearest <= double(kMaxFrame)) return int(nearest);
  return std::nullopt;
}

}  // namespace zz
