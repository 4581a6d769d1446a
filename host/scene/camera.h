// Pinhole perspective camera. Image-plane coordinates are in pixels: pixel (x, y)
// covers [x, x+1] x [y, y+1], y grows downwards, (0,0) is the top-left image corner.
// The ray tracer and the Vulkan raster pass both derive their projection from this
// type, so a ray through (px, py) and a raster sample at (px, py) see the same point.
#pragma once

#include <glm/glm.hpp>

#include <string>

#include "core/simd.h"

namespace zz {

struct Camera {
  std::string name;
  glm::vec3 position{0.0f, 0.0f, 5.0f};
  // The view in world space: forward (the viewing direction, unit), and right and up, the
  // image plane's axes at distance 1 per unit of tan(fov) -- an orthonormal frame, except
  // under a glTF node that mirrors or scales unevenly, which they carry (gltf_loader.cpp).
  glm::vec3 right{1.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  float yfov = 0.8f;     // vertical field of view, radians
  float aspect = 0.0f;   // width / height of the scene's intended frame; 0 = unknown
  float znear = 0.01f;   // as read; neither the tracer nor the map clips by them (scenes/README.md)
  float zfar = 1000.0f;

  static Camera look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up_hint, float yfov);
};

// The vertical fields of view a scene may give, in degrees (open interval): narrower is a
// telescope of no use, wider folds the image plane's tangent towards infinity.
inline constexpr float kMinYfovDegrees = 0.1f, kMaxYfovDegrees = 179.0f;
inline bool valid_yfov_degrees(double degrees) { return degrees > kMinYfovDegrees && degrees < kMaxYfovDegrees; }

// A camera fixed to a frame size: maps image-plane points to ray directions.
// dir(px, py) = dir00 + px * du + py * dv (then normalised).
struct CameraRays {
  glm::vec3 origin;
  glm::vec3 dir00;  // direction through image point (0, 0)
  glm::vec3 du;     // change of direction per pixel to the right
  glm::vec3 dv;     // change of direction per pixel downwards

  CameraRays(const Camera& camera, int width, int height);

  glm::vec3 direction(float px, float py) const;  // normalised
  // Four normalised directions through (px[i], py[i]).
  void directions4(float4 px, float4 py, float4& dx, float4& dy, float4& dz) const;
};

}  // namespace zz
