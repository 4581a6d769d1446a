// A pinhole perspective camera, or an orthographic one (glTF's two camera types).
// Image-plane coordinates are in pixels: pixel (x, y) covers [x, x+1] x [y, y+1], y grows
// downwards, (0,0) is the top-left image corner.
// The ray tracer and the Vulkan raster pass both derive their projection from this
// type, so a ray through (px, py) and a raster sample at (px, py) see the same point.
#pragma once

#include <glm/glm.hpp>

#include <limits>
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
  float yfov = 0.8f;     // vertical field of view, radians (perspective)
  // > 0: an orthographic camera, with the view's half height in world units (glTF ymag):
  // parallel rays along `forward` from the plane through `position`; yfov is unused.
  float ymag = 0.0f;
  float aspect = 0.0f;   // width / height of the scene's intended frame; 0 = unknown
  // Clipping planes, as depths along `clip_axis` from `position` (world units): camera
  // rays and the visibility map see only what lies between them. 0 and infinity: no
  // clipping. The axis is the planes' unit normal: `forward` when zero, as for any
  // orthonormal frame; a glTF camera under a sheared node has its own (gltf_loader.cpp).
  float znear = 0.0f;
  float zfar = std::numeric_limits<float>::infinity();
  glm::vec3 clip_axis{0.0f};

  bool orthographic() const { return ymag > 0.0f; }

  static Camera look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up_hint, float yfov);
};

// The vertical fields of view a scene may give, in degrees (open interval): narrower is a
// telescope of no use, wider folds the image plane's tangent towards infinity.
inline constexpr float kMinYfovDegrees = 0.1f, kMaxYfovDegrees = 179.0f;
inline bool valid_yfov_degrees(double degrees) { return degrees > kMinYfovDegrees && degrees < kMaxYfovDegrees; }

// A camera's clipping planes (glTF znear / zfar) as the renderer applies them: a camera
// ray sees the first surface at a depth depth(p) in [znear, zfar], what lies nearer is cut
// away (the ray starts at the near plane) and what lies beyond is background.
struct CameraClip {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // the planes' unit normal, towards the view
  float znear = 0.0f;
  float zfar = std::numeric_limits<float>::infinity();

  bool clips() const { return znear > 0.0f || zfar < std::numeric_limits<float>::infinity(); }
  float depth(glm::vec3 p) const { return glm::dot(p - origin, forward); }
  // Whether the planes can cut anything inside the box [lo, hi] (depths of its corners).
  bool cuts_into(glm::vec3 lo, glm::vec3 hi) const;
};

// A camera fixed to a frame size: maps image-plane points to rays.
// dir(px, py) = dir00 + px * du + py * dv (then normalised), from origin(px, py) =
// origin + px * ou + py * ov. A pinhole has ou = ov = 0; an orthographic camera has
// du = dv = 0 and its origin at image point (0, 0).
struct CameraRays {
  glm::vec3 origin;
  glm::vec3 dir00;  // direction through image point (0, 0)
  glm::vec3 du;     // change of direction per pixel to the right
  glm::vec3 dv;     // change of direction per pixel downwards
  glm::vec3 ou{0.0f}, ov{0.0f};  // change of origin per pixel (orthographic)
  bool orthographic = false;
  CameraClip clip;  // the camera's planes

  CameraRays(const Camera& camera, int width, int height);

  glm::vec3 direction(float px, float py) const;  // normalised
  glm::vec3 origin_at(float px, float py) const;
  // Four normalised directions through (px[i], py[i]).
  void directions4(float4 px, float4 py, float4& dx, float4& dy, float4& dz) const;
  // Their origins: the pinhole's position in every lane, or points of the orthographic
  // camera's plane.
  void origins4(float4 px, float4 py, float4& ox, float4& oy, float4& oz) const;
};

}  // namespace zz
