#include "viewer/orbit_camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace zz {

namespace {

constexpr float kPi = 3.14159265f;
// How close to straight up or down an orbit may turn the view (|forward.y| <= sin 1.55):
// past a pole the turntable would flip the image. A start beyond it (a camera looking
// straight down) may turn away from the pole, never towards it.
const float kPoleLimit = std::sin(1.55f);

glm::vec3 turned_about_y(glm::vec3 v, float yaw) {
  return glm::vec3(glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0.0f, 1.0f, 0.0f)) * glm::vec4(v, 0.0f));
}

}  // namespace

OrbitCamera::OrbitCamera(const Camera& start, float focus, float standoff) : start_(start) {
  distance_ = std::max(focus, 1e-4f);
  ymag_ = start.ymag;
  target_ = start.position + start.forward * distance_;
  if (start.orthographic() && standoff > distance_) {
    const float back = standoff - distance_;
    distance_ = standoff;
    start_.position -= start.forward * back;
    if (start_.znear > 0.0f) start_.znear += back;
    start_.zfar += back;  // infinity stays
  }
}

// Pitch turns the start's forward towards its -up: forward(p) = f0 cos p - u0 sin p.
glm::vec3 OrbitCamera::forward_at(float pitch) const {
  return start_.forward * std::cos(pitch) - start_.up * std::sin(pitch);
}

void OrbitCamera::orbit(float dx, float dy, int viewport_height) {
  // A drag across the whole viewport height turns by ~pi; the scene follows the mouse
  // (drag right: the camera swings left around the target).
  const float k = kPi / float(std::max(viewport_height, 1));
  yaw_ -= dx * k;
  const float wanted = pitch_ + dy * k;
  // forward(p).y = A cos(p - phi) (yaw keeps y): the poles are at p = phi + m pi, and the
  // view may come no closer to one than the limit, nor cross it.
  const float f0 = start_.forward.y, u0 = start_.up.y;
  const float a = std::sqrt(f0 * f0 + u0 * u0);
  if (!(a > kPoleLimit)) {
    pitch_ = wanted;
    return;
  }
  const float phi = std::atan2(-u0, f0), margin = std::acos(kPoleLimit / a);
  float at = (pitch_ - phi) / kPi;  // in units of pi from the first pole
  if (std::abs(at - std::round(at)) < 1e-4f) at = std::round(at);  // on a pole: either way leaves it
  if (wanted > pitch_) {
    const float next_pole = std::floor(at) + 1.0f;  // the first pole strictly ahead
    pitch_ = std::min(wanted, std::max(phi + next_pole * kPi - margin, pitch_));
  } else if (wanted < pitch_) {
    const float last_pole = std::ceil(at) - 1.0f;  // the first pole strictly behind
    pitch_ = std::max(wanted, std::min(phi + last_pole * kPi + margin, pitch_));
  }
}

void OrbitCamera::pan(float dx, float dy, int viewport_height) {
  // World units per pixel at the target's depth: the image plane there is 2 d tan(fov/2) tall
  // (orthographic: 2 ymag at any depth), so the point under the cursor stays under the cursor.
  const Camera c = camera();
  const float height = c.orthographic() ? 2.0f * ymag_ : 2.0f * distance_ * std::tan(start_.yfov * 0.5f);
  const float units = height / float(std::max(viewport_height, 1));
  target_ += (-dx * c.right + dy * c.up) * units;
}

void OrbitCamera::zoom(float wheel_steps) {
  // An orthographic view does not change with distance: it narrows instead, within a
  // millionth to a million times the start's.
  if (start_.orthographic())
    ymag_ = std::clamp(ymag_ * std::pow(0.85f, wheel_steps), start_.ymag * 1e-6f, start_.ymag * 1e6f);
  else
    distance_ = std::clamp(distance_ * std::pow(0.85f, wheel_steps), 1e-4f, 1e6f);
}

Camera OrbitCamera::camera() const {
  Camera c = start_;
  c.forward = glm::normalize(turned_about_y(forward_at(pitch_), yaw_));
  c.up = glm::normalize(turned_about_y(start_.up * std::cos(pitch_) + start_.forward * std::sin(pitch_), yaw_));
  c.right = glm::normalize(turned_about_y(start_.right, yaw_));
  c.position = target_ - c.forward * distance_;
  c.ymag = ymag_;
  c.clip_axis = glm::vec3(0.0f);  // the planes turn with the (orthonormal) view
  return c;
}

OrbitCamera orbit_for(const Camera& camera, glm::vec3 scene_centre, float scene_radius) {
  const float focus = focus_distance(camera, scene_centre, scene_radius);
  const glm::vec3 target = camera.position + glm::normalize(camera.forward) * focus;
  return OrbitCamera(camera, focus, glm::length(scene_centre - target) + 1.05f * scene_radius);
}

float focus_distance(const Camera& camera, glm::vec3 scene_centre, float scene_radius) {
  const float along = glm::dot(scene_centre - camera.position, glm::normalize(camera.forward));
  return std::max(along, std::max(0.1f * scene_radius, 1e-3f));
}

}  // namespace zz
