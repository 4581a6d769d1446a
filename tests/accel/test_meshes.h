// Small generated meshes and a brute-force reference shared by the accel tests.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "accel/ray.h"
#include "accel/watertight.h"

namespace zz::test {

inline void add_tri(std::vector<glm::vec3>& p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  p.push_back(a), p.push_back(b), p.push_back(c);
}

// n random triangles in [-1, 1]^3 with edge lengths up to `size` (overlapping soup).
inline std::vector<glm::vec3> random_soup(std::mt19937& rng, int n, float size) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<glm::vec3> p;
  for (int i = 0; i < n; ++i) {
    glm::vec3 c(u(rng), u(rng), u(rng));
    add_tri(p, c, c + size * glm::vec3(u(rng), u(rng), u(rng)),
            c + size * glm::vec3(u(rng), u(rng), u(rng)));
  }
  return p;
}

// A closed UV sphere; every shared vertex is the same float triple in each triangle.
inline std::vector<glm::vec3> uv_sphere(int slices, int stacks, float radius, glm::vec3 center) {
  std::vector<glm::vec3> grid;
  for (int j = 0; j <= stacks; ++j)
    for (int i = 0; i <= slices; ++i) {
      float th = 3.14159265f * float(j) / float(stacks), ph = 6.2831853f * float(i % slices) / float(slices);
      glm::vec3 d(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
      if (j == 0 || j == stacks) d = glm::vec3(0.0f, j == 0 ? 1.0f : -1.0f, 0.0f);
      grid.push_back(center + radius * d);
    }
  auto at = [&](int i, int j) { return grid[size_t(j) * size_t(slices + 1) + size_t(i)]; };
  std::vector<glm::vec3> p;
  for (int j = 0; j < stacks; ++j)
    for (int i = 0; i < slices; ++i) {
      if (j != 0) add_tri(p, at(i, j), at(i + 1, j), at(i + 1, j + 1));
      if (j != stacks - 1) add_tri(p, at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return p;
}

// The closed cube [lo, hi]^3 as 12 triangles.
inline std::vector<glm::vec3> cube(glm::vec3 lo, glm::vec3 hi) {
  std::vector<glm::vec3> p;
  glm::vec3 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = glm::vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : quads) {
    add_tri(p, c[q[0]], c[q[1]], c[q[2]]);
    add_tri(p, c[q[0]], c[q[2]], c[q[3]]);
  }
  return p;
}

// A fan of n triangles around `center` in the plane z = center.z (a closed disk).
inline std::vector<glm::vec3> fan(int n, glm::vec3 center, float radius) {
  std::vector<glm::vec3> rim;
  for (int i = 0; i < n; ++i) {
    float a = 6.2831853f * float(i) / float(n);
    rim.push_back(center + radius * glm::vec3(std::cos(a), std::sin(a), 0.0f));
  }
  std::vector<glm::vec3> p;
  for (int i = 0; i < n; ++i) add_tri(p, center, rim[size_t(i)], rim[size_t((i + 1) % n)]);
  return p;
}

// The float kernel alone on triangle t of p, as the BVH calls it for `ray` (shear `s`).
inline watertight::Result<float> float_test(const std::vector<glm::vec3>& p, const Ray& ray,
                                            const watertight::RayShear& s, size_t t) {
  const watertight::SpawnReach<float> reach =
      watertight::spawn_reach(ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z);
  const glm::vec3 a = p[3 * t] - ray.origin, b = p[3 * t + 1] - ray.origin, c = p[3 * t + 2] - ray.origin;
  return watertight::intersect<float>(a[s.kx], a[s.ky], a[s.kz], b[s.kx], b[s.ky], b[s.kz], c[s.kx], c[s.ky],
                                      c[s.kz], s.sx, s.sy, s.sz, reach);
}

// The reference answer: every triangle through the same kernel, same tie-break.
inline Hit brute_force(const std::vector<glm::vec3>& p, const Ray& ray) {
  Hit best;
  watertight::RayShear s = watertight::make_shear(ray.dir);
  if (!s.valid) return best;
  float tmax = std::fmin(ray.tmax, 3.4028235e38f);
  const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
  for (size_t t = 0; t < p.size() / 3; ++t) {
    auto h = float_test(p, ray, s, t);
    watertight::settle_uncertain(h, [&](int) {
      return watertight::exact_intersect(&p[3 * t].x, &p[3 * t + 1].x, &p[3 * t + 2].x, o, s.kx, s.ky, s.kz, s.sx,
                                         s.sy, s.sz);
    });
    if (!h.hit || !(h.t <= tmax)) continue;
    if (best.hit() && !(h.t < best.t)) continue;  // ties keep the lower index
    best = Hit{h.t, h.u, h.v, int32_t(t)};
    tmax = h.t;
  }
  return best;
}

// Whether the float test alone leaves ray's hit on triangle `prim` in doubt (the hits only
// the double-precision re-test settles).
inline bool float_test_in_doubt(const std::vector<glm::vec3>& p, const Ray& ray, int32_t prim) {
  return float_test(p, ray, watertight::make_shear(ray.dir), size_t(prim)).uncertain;
}

inline glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  while (true) {
    glm::vec3 d(g(rng), g(rng), g(rng));
    float l = glm::length(d);
    if (l > 1e-3f) return d / l;
  }
}

}  // namespace zz::test
