// Orbit / pan / zoom around a target point, the usual model-viewer (turntable) camera. The
// scene's own camera is the starting pose, kept whole: its roll, and a view straight down,
// continue smoothly from what the scene shows instead of snapping to an upright camera.
#pragma once

#include <glm/glm.hpp>

#include "scene/camera.h"

namespace zz {

class OrbitCamera {
 public:
  OrbitCamera() = default;
  // Orbits around the point `focus_distance` in front of `start`. An orthographic start
  // stands back to at least `standoff` from that point (its image is the same; its planes
  // move with it), so that its plane, whose rays start there, turns around the scene and
  // not through it.
  OrbitCamera(const Camera& start, float focus_distance, float standoff = 0.0f);

  // Mouse motion in pixels over a viewport `viewport_height` pixels tall.
  void orbit(float dx, float dy, int viewport_height);  // left drag: turn around the target
  void pan(float dx, float dy, int viewport_height);    // right/middle drag: slide target + eye
  void zoom(float wheel_steps);                         // wheel: 15% closer (orthographic: smaller view) per step up

  Camera camera() const;
  glm::vec3 target() const { return target_; }
  float distance() const { return distance_; }

 private:
  glm::vec3 forward_at(float pitch) const;

  Camera start_;
  glm::vec3 target_{0.0f};
  float distance_ = 1.0f;
  float ymag_ = 0.0f;  // an orthographic start's half height, zoomed
  // The start's frame turned by pitch about its right axis (positive turns the view towards
  // the start's -up: down on screen), then by yaw about world +Y.
  float yaw_ = 0.0f;
  float pitch_ = 0.0f;
};

// The focus distance for a camera: how far along its view the scene's centre lies
// (at least a tenth of the scene radius, so a camera inside the scene still orbits).
float focus_distance(const Camera& camera, glm::vec3 scene_centre, float scene_radius);

// The viewer's orbit for a scene camera: about its focus, an orthographic one standing off
// beyond the scene's bounding sphere seen from that point.
OrbitCamera orbit_for(const Camera& camera, glm::vec3 scene_centre, float scene_radius);

}  // namespace zz
