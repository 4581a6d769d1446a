#include "gpu/geo_flags_cpu.h"

#include <smmintrin.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace zz {
namespace {

float dot3(glm::vec3 a, glm::vec3 b) {
  float r = a.x * b.x + a.y * b.y;
  return r + a.z * b.z;
}

// One row of pair bits, 64 pairs per word.
struct BitRows {
  int words_per_row = 0;
  std::vector<uint64_t> bits;
  BitRows(int rows, int pairs) : words_per_row((pairs + 63) / 64 + 1), bits(size_t(rows) * words_per_row, 0) {}
  uint64_t* row(int r) { return &bits[size_t(r) * words_per_row]; }
  static void set(uint64_t* row, int i) { row[i >> 6] |= uint64_t(1) << (i & 63); }
  // Bits [start, start + n) of a row (n <= 32); the spare last word keeps i + 1 in range.
  static uint64_t window(const uint64_t* row, int start, int n) {
    int w = start >> 6, b = start & 63;
    uint64_t lo = row[w] >> b;
    uint64_t hi = b ? row[w + 1] << (64 - b) : 0;
    return (lo | hi) & ((uint64_t(1) << n) - 1);
  }
};

struct Rule {
  const std::vector<glm::vec4>& planes;
  const gpu::FlagPush& p;
  const std::vector<glm::vec4>* normals;  // w: material tag; with the material rule on

  bool orthographic() const { return p.limits.w != 0.0f; }
  glm::vec3 grid_step(int gx, int gy) const { return float(gx) * glm::vec3(p.du) + float(gy) * glm::vec3(p.dv); }
  glm::vec3 ray_dir(int gx, int gy) const {
    if (orthographic()) return glm::vec3(p.dir00);
    glm::vec3 d = glm::vec3(p.dir00) + float(gx) * glm::vec3(p.du);
    return d + float(gy) * glm::vec3(p.dv);
  }
  bool far_apart(float a, float b) const {  // orthographic: relative to the view's height (du.w)
    float diff = std::fabs(a - b);
    float lim = p.limits.y * (orthographic() ? p.du.w : std::min(a, b));
    return !(diff <= lim);
  }
  // Ids known to differ; `inner`: both samples in one pixel (the material rule's pairs).
  bool differs(uint32_t ia, int gxa, int gya, uint32_t ib, int gxb, int gyb, bool inner) const {
    if (ia == 0 || ib == 0) return true;
    if (inner && p.limits.z != 0.0f && (*normals)[ia - 1].w != (*normals)[ib - 1].w) return true;
    const glm::vec4 pa = planes[ia - 1], pb = planes[ib - 1];
    const glm::vec3 na(pa), nb(pb);
    const glm::vec3 da = ray_dir(gxa, gya), db = ray_dir(gxb, gyb);
    const float sa = dot3(na, da), sb = dot3(nb, db);
    float c = dot3(na, nb);
    if ((sa < 0.0f) != (sb < 0.0f)) c = -c;
    if (c < p.limits.x) return true;
    // An orthographic ray's origin lies grid_step from the planes' (shaders/geo_flags.comp).
    float ha = pa.w, hb = pb.w, hab = ha, hba = hb;
    if (orthographic()) {
      const glm::vec3 oa = grid_step(gxa, gya), ob = grid_step(gxb, gyb);
      hab = ha - dot3(na, ob);
      hba = hb - dot3(nb, oa);
      ha = ha - dot3(na, oa);
      hb = hb - dot3(nb, ob);
    }
    const float taa = ha / sa, tba = hba / dot3(nb, da), tab = hab / dot3(na, db), tbb = hb / sb;
    return far_apart(taa, tba) || far_apart(tbb, tab);
  }
};

// Bit k of the result: a[k] != b[k], for 4 ids at once.
inline int differ4(const uint32_t* a, const uint32_t* b) {
  const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a));
  const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b));
  return ~_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(x, y))) & 0xF;
}

}  // namespace

std::vector<glm::vec4> triangle_planes(const std::vector<glm::vec3>& positions,
                                       const std::vector<glm::vec4>& normals, glm::vec3 origin) {
  std::vector<glm::vec4> planes(normals.size());
  for (size_t t = 0; t < normals.size(); ++t) {
    const glm::vec3 n(normals[t]);
    planes[t] = glm::vec4(n, dot3(n, positions[3 * t] - origin));
  }
  return planes;
}

GeoMap geo_flags_cpu(const std::vector<uint32_t>& ids, const std::vector<glm::vec4>& planes,
                     const gpu::FlagPush& p, const std::vector<glm::vec4>* normals) {
  const int W = p.frame.x, H = p.frame.y, S = p.frame.z;
  const int gw = W * S, gh = H * S, stride = gw + 2;
  if (ids.size() != size_t(stride) * (gh + 2)) throw Error("geo_flags_cpu: id image size does not match the frame");
  if (p.limits.z != 0.0f && (!normals || normals->size() != planes.size()))
    throw Error("geo_flags_cpu: the material rule needs the triangles' normals (material tags in w)");
  const Rule rule{planes, p, normals};

  // Horizontal pairs in core rows gy = iy - 1 in [0, gh): pair ix = (ix, ix + 1), ix in [0, gw].
  BitRows horizontal(gh, gw + 1);
  for (int gy = 0; gy < gh; ++gy) {
    const uint32_t* row = &ids[size_t(gy + 1) * stride];
    uint64_t* bits = horizontal.row(gy);
    auto visit = [&](int ix) {
      // Samples gx = ix - 1 and ix share a pixel unless ix starts one.
      if (rule.differs(row[ix], ix - 1, gy, row[ix + 1], ix, gy, ix % S != 0)) BitRows::set(bits, ix);
    };
    int ix = 0;
    for (; ix + 4 < stride; ix += 4)
      for (int m = differ4(row + ix, row + ix + 1); m; m &= m - 1) visit(ix + __builtin_ctz(m));
    for (; ix <= gw; ++ix)
      if (row[ix] != row[ix + 1]) visit(ix);
  }
  // Vertical pairs (iy, iy + 1) for iy in [0, gh], core columns gx = ix - 1 in [0, gw).
  BitRows vertical(gh + 1, gw);
  for (int iy = 0; iy <= gh; ++iy) {
    const uint32_t* a = &ids[size_t(iy) * stride + 1];
    const uint32_t* b = a + stride;
    uint64_t* bits = vertical.row(iy);
    auto visit = [&](int gx) {
      if (rule.differs(a[gx], gx, iy - 1, b[gx], gx, iy, iy % S != 0)) BitRows::set(bits, gx);
    };
    int gx = 0;
    for (; gx + 4 <= gw; gx += 4)
      for (int m = differ4(a + gx, b + gx); m; m &= m - 1) visit(gx + __builtin_ctz(m));
    for (; gx < gw; ++gx)
      if (a[gx] != b[gx]) visit(gx);
  }

  // Pixel (x, y): horizontal pairs ix in [xS, xS + S] of rows yS..yS+S-1, vertical pairs
  // gx in [xS, xS + S) of rows iy = yS..yS+S. A pair the material rule set lies inside one
  // pixel, so no other pixel's window holds it. The byte is the shader's (GeoPairs).
  GeoMap map;
  map.width = W;
  map.height = H;
  map.flags.assign(size_t(W) * H, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      GeoPairs pairs{S};
      for (int j = 0; j < S; ++j)  // window bit b: samples b - 1 and b of row j
        for (uint64_t m = BitRows::window(horizontal.row(y * S + j), x * S, S + 1); m; m &= m - 1)
          pairs.horizontal(__builtin_ctzll(m) - 1, j);
      for (int j = 0; j <= S; ++j)  // window bit b: column b, rows j - 1 and j
        for (uint64_t m = BitRows::window(vertical.row(y * S + j), x * S, S); m; m &= m - 1)
          pairs.vertical(__builtin_ctzll(m), j - 1);
      map.flags[size_t(y) * W + x] = pairs.byte();
    }
  return map;
}

}  // namespace zz
