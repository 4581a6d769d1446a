#include "viewer/orbit_camera.h"

#include <algorithm>
#include <cmath>

namespace zz {

namespace {

constexpr float kPitchLimit = 1.55f;  // just short of straight up/down: look_at needs a non-parallel up

glm::vec3 direction(float yaw, float pitch) {
  // forward for yaw 0, pitch 0 is -Z; positive pitch looks down.
  return {-std::sin(yaw) * std::cos(pitch), -std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

}  // namespace

OrbitCamera::OrbitCamera(const Camera& start, float focus) : start_(start) {
  distance_ = std::max(focus, 1e-4f);
  target_ = start.position + start.forward * distance_;
  const glm::vec3 f = glm::normalize(start.forward);
  pitch_ = std::clamp(std::asin(std::clamp(-f.y, -1.0f, 1.0f)), -kPitchLimit, kPitchLimit);
  yaw_ = std::atan2(-f.x, -f.z);
}

void OrbitCamera::orbit(float dx, float dy, int viewport_height) {
  // A drag across the whole viewport height turns by ~pi; the scene follows the mouse
  // (drag right: the camera swings left around the target).
  const float k = 3.14159265f / float(std::max(viewport_height, 1));
  yaw_ -= dx * k;
  pitch_ = std::clamp(pitch_ + dy * k, -kPitchLimit, kPitchLimit);
}

void OrbitCamera::pan(float dx, float dy, int viewport_height) {
  // World units per pixel at the target's depth: the image plane there is 2 d tan(fov/2) tall,
  // so the point under the cursor stays under the cursor.
  const Camera c = camera();
  const float units = 2.0f * distance_ * std::tan(start_.yfov * 0.5f) / float(std::max(viewport_height, 1));
  target_ += (-dx * c.right + dy * c.up) * units;
}

void OrbitCamera::zoom(float wheel_steps) {
  distance_ = std::clamp(distance_ * std::pow(0.85f, wheel_steps), 1e-4f, 1e6f);
}

Camera OrbitCamera::camera() const {
  const glm::vec3 eye = target_ - direction(yaw_, pitch_) * distance_;
  Camera c = Camera::look_at(eye, target_, glm::vec3(0.0f, 1.0f, 0.0f), start_.yfov);
  c.name = start_.name;
  c.aspect = start_.aspect;
  c.znear = start_.znear;
  c.zfar = start_.zfar;
  return c;
}

float focus_distance(const Camera& camera, glm::vec3 scene_centre, float scene_radius) {
  const float along = glm::dot(scene_centre - camera.position, glm::normalize(camera.forward));
  return std::max(along, std::max(0.1f * scene_radius, 1e-3f));
}

}  // namespace zz
