// CPU mirror of shaders/geo_flags.comp, operation for operation (the build disables FMA
// contraction, the shader marks its arithmetic `precise`), so flag bytes (the edge and the
// way it runs) match bit for bit.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geo_map.h"
#include "gpu/visibility.h"

namespace zz::test {

struct FlagReference {
  const std::vector<uint32_t>& ids;  // VisibilityPass::render_ids layout, ring included
  const std::vector<glm::vec3>& positions;
  const std::vector<glm::vec4>& normals;
  gpu::FlagPush p;

  static float dot3(glm::vec3 a, glm::vec3 b) {
    float r = a.x * b.x + a.y * b.y;
    return r + a.z * b.z;
  }
  bool orthographic() const { return p.limits.w != 0.0f; }
  glm::vec3 grid_step(glm::ivec2 g) const {
    glm::vec3 d = float(g.x) * glm::vec3(p.du);
    return d + float(g.y) * glm::vec3(p.dv);
  }
  glm::vec3 ray_dir(glm::ivec2 g) const {
    if (orthographic()) return glm::vec3(p.dir00);
    glm::vec3 d = glm::vec3(p.dir00) + float(g.x) * glm::vec3(p.du);
    return d + float(g.y) * glm::vec3(p.dv);
  }
  bool far_apart(float a, float b) const {
    float diff = std::fabs(a - b);
    float lim = p.limits.y * (orthographic() ? p.du.w : std::min(a, b));
    return !(diff <= lim);
  }
  // `inner`: both samples inside the pixel, where the material rule applies.
  bool differs(uint32_t ia, glm::ivec2 ga, uint32_t ib, glm::ivec2 gb, bool inner) const {
    if (ia == ib) return false;
    if (ia == 0 || ib == 0) return true;
    if (inner && p.limits.z != 0.0f && normals[ia - 1].w != normals[ib - 1].w) return true;
    glm::vec3 na(normals[ia - 1]), nb(normals[ib - 1]);
    glm::vec3 da = ray_dir(ga), db = ray_dir(gb);
    float sa = dot3(na, da), sb = dot3(nb, db);
    float c = dot3(na, nb);
    if ((sa < 0.0f) != (sb < 0.0f)) c = -c;
    if (c < p.limits.x) return true;
    glm::vec3 o(p.origin);
    float ha = dot3(na, positions[3 * (ia - 1)] - o);
    float hb = dot3(nb, positions[3 * (ib - 1)] - o);
    float hab = ha, hba = hb;  // an orthographic ray starts grid_step from o
    if (orthographic()) {
      glm::vec3 oa = grid_step(ga), ob = grid_step(gb);
      hab = ha - dot3(na, ob);
      hba = hb - dot3(nb, oa);
      ha = ha - dot3(na, oa);
      hb = hb - dot3(nb, ob);
    }
    float taa = ha / sa, tba = hba / dot3(nb, da), tab = hab / dot3(na, db), tbb = hb / sb;
    return far_apart(taa, tba) || far_apart(tbb, tab);
  }
  uint32_t id(glm::ivec2 g) const {  // frame supersample, ring = -1 and W*S
    int stride = p.frame.x * p.frame.z + 2;
    return ids[size_t(g.y + 1) * stride + size_t(g.x + 1)];
  }
  // The pixel's flag byte: its differing pairs, counted (GeoPairs) with the zones they meet.
  uint8_t pixel(int x, int y) const {
    int s = p.frame.z;
    auto pair = [&](glm::ivec2 a, glm::ivec2 b, bool inner) { return differs(id(a), a, id(b), b, inner); };
    GeoPairs pairs{s};
    for (int j = 0; j < s; ++j)
      for (int i = -1; i < s; ++i)
        if (pair({x * s + i, y * s + j}, {x * s + i + 1, y * s + j}, i >= 0 && i + 1 < s)) pairs.horizontal(i, j);
    for (int i = 0; i < s; ++i)
      for (int j = -1; j < s; ++j)
        if (pair({x * s + i, y * s + j}, {x * s + i, y * s + j + 1}, j >= 0 && j + 1 < s)) pairs.vertical(i, j);
    return pairs.byte();
  }
  GeoMap map() const {
    GeoMap m;
    m.width = p.frame.x;
    m.height = p.frame.y;
    m.flags.resize(size_t(m.width) * m.height);
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) m.flags[size_t(y) * m.width + x] = pixel(x, y);
    return m;
  }
};

}  // namespace zz::test
