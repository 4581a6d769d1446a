// Orbit / pan / zoom around a target point, the usual model-viewer camera. The scene's
// own camera is the starting pose; the orbit parameters are derived from it so the first
// interaction continues smoothly from what the scene shows.
#pragma once

#include <glm/glm.hpp>

#include "scene/camera.h"

namespace zz {

class OrbitCamera {
 public:
  OrbitCamera() = default;
  // Orbits around the point `focus_distance` in front of `start` (world up = +Y).
  OrbitCamera(const Camera& start, float focus_distance);

  // Mouse motion in pixels over a viewport `viewport_height` pixels tall.
  void orbit(float dx, float dy, int viewport_height);  // left drag: turn around the target
  void pan(float dx, float dy, int viewport_height);    // right/middle drag: slide target + eye
  void zoom(float wheel_steps);                         // wheel: 15% closer per step up

  Camera camera() const;
  glm::vec3 target() const { return target_; }
  float distance() const { return distance_; }

 private:
  Camera start_;
  glm::vec3 target_{0.0f};
  float distance_ = 1.0f;
  float yaw_ = 0.0f;    // around +Y; 0 looks down -Z
  float pitch_ = 0.0f;  // radians above the horizon the eye is looking down from
};

// The focus distance for a camera: how far along its view the scene's centre lies
// (at least a tenth of the scene radius, so a camera inside the scene still orbits).
float focus_distance(const Camera& camera, glm::vec3 scene_centre, float scene_radius);

}  // namespace zz
