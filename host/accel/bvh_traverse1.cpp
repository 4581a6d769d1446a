// Single-ray traversal for incoherent rays: the same tree, the same conservative slab
// test (one SSE box at a time) and the same watertight kernel as the packets, with the
// closest child first by the ray's direction sign along the node's split axis.
#include <limits>

#include "accel/box_test.h"
#include "accel/bvh.h"
#include "accel/watertight.h"

namespace zz {
namespace {

constexpr float kFloatMax = std::numeric_limits<float>::max();

struct SingleSetup {
  __m128 o;    // origin, lane 3 = 0
  __m128 rd;   // safe reciprocal direction, lane 3 = 0
  watertight::RayShear shear;
  int neg[3];
  float best;
};

// Slab test of one box: x, y, z in lanes 0..2, lane 3 carries 0 (near) and best (far).
inline bool box1(const SingleSetup& s, const BvhNode& n, float best, float& tnear) {
  __m128 t0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.lo), s.o), s.rd);
  __m128 t1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(n.hi), s.o), s.rd);
  __m128 tmin = _mm_blend_ps(_mm_min_ps(t0, t1), _mm_setzero_ps(), 0b1000);
  __m128 tmax = _mm_blend_ps(_mm_max_ps(t0, t1), _mm_set1_ps(best), 0b1000);
  tnear = hmax(tmin);
  return tnear <= hmin(tmax) * kBoxFarScale;
}

template <bool kAnyHit>
bool traverse(const std::vector<BvhNode>& nodes, const std::vector<BvhTriangle>& tris,
              SingleSetup& s, Hit* out) {
  const int kx = s.shear.kx, ky = s.shear.ky, kz = s.shear.kz;
  int32_t best_prim = std::numeric_limits<int32_t>::max();
  float best_u = 0.0f, best_v = 0.0f;
  alignas(16) float o[4];
  _mm_store_ps(o, s.o);

  struct Entry {
    float tnear;
    uint32_t node;
  } stack[kBvhMaxDepth + 1];
  int sp = 0;
  float tn;
  uint32_t node = 0;
  if (!box1(s, nodes[0], s.best, tn)) return false;
  while (true) {
    const BvhNode& n = nodes[node];
    if (!n.leaf()) {
      float tl, tr;
      bool hl = box1(s, nodes[n.first], s.best, tl);
      bool hr = box1(s, nodes[n.first + 1], s.best, tr);
      if (hl && hr) {
        bool right_first = s.neg[n.axis()];
        stack[sp].node = right_first ? n.first : n.first + 1;
        stack[sp].tnear = right_first ? tl : tr;
        ++sp;
        node = right_first ? n.first + 1 : n.first;
        continue;
      }
      if (hl || hr) {
        node = hl ? n.first : n.first + 1;
        continue;
      }
    } else {
      const BvhTriangle* tri = &tris[n.first];
      const BvhTriangle* end = tri + n.count();
      for (; tri != end; ++tri) {
        float a[3], b[3], c[3];
        for (int k = 0; k < 3; ++k) {
          a[k] = tri->v0[k] - o[k];
          b[k] = tri->v1[k] - o[k];
          c[k] = tri->v2[k] - o[k];
        }
        auto h = watertight::intersect<float>(a[kx], a[ky], a[kz], b[kx], b[ky], b[kz], c[kx],
                                              c[ky], c[kz], s.shear.sx, s.shear.sy, s.shear.sz);
        if (!h.hit || !(h.t <= s.best)) continue;
        if constexpr (kAnyHit) {
          return true;
        } else {
          // Same tie-break as the packets: equal t goes to the lower original index.
          if (h.t == s.best && tri->prim > best_prim) continue;
          s.best = h.t;
          best_u = h.u, best_v = h.v, best_prim = tri->prim;
        }
      }
    }
    while (true) {
      if (sp == 0) {
        if constexpr (!kAnyHit) {
          if (best_prim != std::numeric_limits<int32_t>::max())
            *out = Hit{s.best, best_u, best_v, best_prim};
        }
        return false;
      }
      --sp;
      if (stack[sp].tnear <= s.best * kBoxFarScale) {
        node = stack[sp].node;
        break;
      }
    }
  }
}

bool setup(const Ray& ray, SingleSetup& s) {
  s.shear = watertight::make_shear(ray.dir);
  if (!s.shear.valid || !std::isfinite(ray.origin.x) || !std::isfinite(ray.origin.y) ||
      !std::isfinite(ray.origin.z) || std::isnan(ray.tmax))
    return false;
  s.o = _mm_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, 0.0f);
  s.rd = _mm_setr_ps(safe_rcp(ray.dir.x), safe_rcp(ray.dir.y), safe_rcp(ray.dir.z), 0.0f);
  for (int k = 0; k < 3; ++k) s.neg[k] = ray.dir[k] < 0.0f;
  s.best = std::min(ray.tmax, kFloatMax);
  return s.best >= 0.0f;
}

}  // namespace

Hit Bvh::intersect1(const Ray& ray) const {
  Hit hit;
  SingleSetup s;
  if (nodes_.empty() || !setup(ray, s)) return hit;
  traverse<false>(nodes_, triangles_, s, &hit);
  return hit;
}

bool Bvh::occluded1(const Ray& ray) const {
  SingleSetup s;
  if (nodes_.empty() || !setup(ray, s)) return false;
  return traverse<true>(nodes_, triangles_, s, nullptr);
}

}  // namespace zz
