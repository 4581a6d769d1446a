#include "scene/camera.h"

#include <algorithm>
#include <cmath>

#include "scene/lights.h"  // unit_direction

namespace zz {

Camera Camera::look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up_hint, float yfov) {
  Camera c;
  c.position = eye;
  // unit_direction: glm::normalize's bits where |v|^2 is finite, and a direction where it
  // overflows (a camera 1e19 from its target).
  c.forward = unit_direction(target - eye).value_or(glm::vec3(0.0f, 0.0f, -1.0f));
  c.right = unit_direction(glm::cross(c.forward, up_hint)).value_or(glm::vec3(1.0f, 0.0f, 0.0f));
  c.up = glm::cross(c.right, c.forward);
  c.yfov = yfov;
  return c;
}

CameraRays::CameraRays(const Camera& camera, int width, int height) {
  // The image plane: at distance 1 with half height tan(yfov/2), or for an orthographic
  // camera through its position with half height ymag; square pixels.
  orthographic = camera.orthographic();
  float half_h = orthographic ? camera.ymag : std::tan(camera.yfov * 0.5f);
  float pixel = 2.0f * half_h / float(height);
  float half_w = pixel * float(width) * 0.5f;
  if (orthographic) {
    origin = camera.position - camera.right * half_w + camera.up * half_h;
    ou = camera.right * pixel;
    ov = -camera.up * pixel;
    dir00 = camera.forward;
    du = dv = glm::vec3(0.0f);
  } else {
    origin = camera.position;
    du = camera.right * pixel;
    dv = -camera.up * pixel;
    dir00 = camera.forward - camera.right * half_w + camera.up * half_h;
  }
  clip = CameraClip{camera.position, camera.clip_axis == glm::vec3(0.0f) ? camera.forward : camera.clip_axis,
                    camera.znear, camera.zfar};
}

bool CameraClip::cuts_into(glm::vec3 lo, glm::vec3 hi) const {
  if (!clips()) return false;
  double nearest = std::numeric_limits<double>::infinity(), farthest = -nearest;
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const double d = glm::dot(corner - glm::dvec3(origin), glm::dvec3(forward));
    nearest = std::min(nearest, d);
    farthest = std::max(farthest, d);
  }
  // What lies behind the camera is out of view anyway; what lies at depth [0, znear) or
  // beyond zfar is cut. A box's corners bound the depth of every point in it; the margin
  // covers the rounding of a traced hit's depth.
  constexpr double kMargin = 1e-4;
  return (znear > 0.0f && nearest < double(znear) * (1.0 + kMargin) && farthest > 0.0) ||
         farthest > double(zfar) * (1.0 - kMargin);
}

glm::vec3 CameraRays::direction(float px, float py) const {
  // Same arithmetic as the packet path, so single rays and packets agree bit for bit.
  float4 x, y, z;
  directions4(float4(px), float4(py), x, y, z);
  return {x[0], y[0], z[0]};
}

glm::vec3 CameraRays::origin_at(float px, float py) const {
  float4 x, y, z;
  origins4(float4(px), float4(py), x, y, z);
  return {x[0], y[0], z[0]};
}

void CameraRays::origins4(float4 px, float4 py, float4& ox, float4& oy, float4& oz) const {
  if (!orthographic) {
    ox = float4(origin.x), oy = float4(origin.y), oz = float4(origin.z);
    return;
  }
  ox = float4(origin.x) + px * float4(ou.x) + py * float4(ov.x);
  oy = float4(origin.y) + px * float4(ou.y) + py * float4(ov.y);
  oz = float4(origin.z) + px * float4(ou.z) + py * float4(ov.z);
}

void CameraRays::directions4(float4 px, float4 py, float4& dx, float4& dy, float4& dz) const {
  float4 x = float4(dir00.x) + px * float4(du.x) + py * float4(dv.x);
  float4 y = float4(dir00.y) + px * float4(du.y) + py * float4(dv.y);
  float4 z = float4(dir00.z) + px * float4(du.z) + py * float4(dv.z);
  float4 inv_len = rcp_exact(sqrt(x * x + y * y + z * z));
  dx = x * inv_len;
  dy = y * inv_len;
  dz = z * inv_len;
}

}  // namespace zz
