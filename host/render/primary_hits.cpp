#include "render/primary_hits.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/fp_mode.h"
#include "core/worker_arena.h"

namespace zz {

PrimaryHits trace_primary_hits(const Shader& shader, const Camera& camera, int width, int height,
                               const TileRect& region, int threads, const std::atomic<bool>* cancel,
                               RayCounters* rays) {
  PrimaryHits hits;
  hits.width = region.width();
  hits.height = region.height();
  const size_t pixels = size_t(hits.width) * size_t(hits.height);
  hits.depth.resize(pixels);
  hits.normal.resize(pixels);
  hits.albedo.resize(pixels);
  const CameraRays camera_rays(camera, width, height);
  const CameraClip* clip = shader.clip_in_scene(camera_rays.clip);
  tbb::combinable<RayCounters> counters;
  WorkerArena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, hits.height), [&](const tbb::blocked_range<int>& rows) {
      const ScopedFlushDenormals flush_denormals;  // as the colour's tiles: MXCSR is per thread
      RayCounters& local = counters.local();
      for (int row = rows.begin(); row != rows.end(); ++row) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return;
        const int y = region.y0 + row;
        // Four pixels per packet; a row's last packet repeats its first pixel in the
        // unused lanes (each lane's result depends only on its own ray).
        for (int x0 = 0; x0 < hits.width; x0 += 4) {
          const int n = std::min(4, hits.width - x0);
          alignas(16) float px[4], py[4];
          for (int i = 0; i < 4; ++i) {
            px[i] = float(region.x0 + x0 + (i < n ? i : 0)) + 0.5f;
            py[i] = float(y) + 0.5f;
          }
          RayPacket4 packet;
          camera_rays.origins4(float4::load(px), float4::load(py), packet.ox, packet.oy, packet.oz);
          camera_rays.directions4(float4::load(px), float4::load(py), packet.dx, packet.dy, packet.dz);
          packet.tmax = float4(kInfinity);
          local.primary += 4;
          PrimaryHit4 out;
          shader.primary4(packet, out, local, clip);
          for (int i = 0; i < n; ++i) {
            const size_t k = size_t(row) * size_t(hits.width) + size_t(x0 + i);
            hits.depth[k] = out.depth[i];
            hits.normal[k] = out.normal[i];
            hits.albedo[k] = out.albedo[i];
          }
        }
      }
    });
  });
  if (rays) *rays = counters.combine([](RayCounters a, const RayCounters& b) { return a += b, a; });
  return hits;
}

}  // namespace zz
