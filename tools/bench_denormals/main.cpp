// bench_denormals: does the speed collapse when radiance becomes denormal?
//
// One thread traces a 128x128 frame (one camera packet per 2x2 pixels) through the
// Whitted shader, on the calling thread so that its MXCSR is the one that counts:
//   normal     lights of 60, background 0.2
//   denormal   the same scene with lights of 1e-38 and background 1e-38: every
//              radiance value along every path is denormal (below 1.2e-38)
// (the same tinted, absorbing glass block in both, so the paths are the same)
// each with FTZ/DAZ off (the default MXCSR) and on (ScopedFlushDenormals, what the tile
// tasks use). Expected: denormal/off slower than normal/off (microcode assists on
// denormal arithmetic), and denormal/on at least as fast as normal/on (flushed
// contributions are 0, so their shadow rays are skipped). Compare the CPU time per
// frame; rays/s is per CPU second. Measured (Xeon, 2 cores, busy machine, median of 5):
// normal 9.6 ms, denormal 13.5 ms without FTZ/DAZ (1.4x); with them 8.6 and 5.7 ms.
#include <benchmark/benchmark.h>

#include <optional>

#include "core/fp_mode.h"
#include "render/scene_source.h"
#include "render/shader.h"

namespace zz {
namespace {

void add_tri(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t m) {
  const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
  s.positions.insert(s.positions.end(), {a, b, c});
  s.normals.insert(s.normals.end(), {n, n, n});
  s.uvs.insert(s.uvs.end(), {glm::vec2(0), glm::vec2(0), glm::vec2(0)});
  s.material_of.push_back(m);
}

void add_box(Scene& s, glm::vec3 lo, glm::vec3 hi, uint32_t m) {
  const glm::vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                          {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  const int q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  for (const auto& f : q) add_tri(s, p[f[0]], p[f[1]], p[f[2]], m), add_tri(s, p[f[0]], p[f[2]], p[f[3]], m);
}

Scene make_scene(bool denormal) {
  Scene s;
  Material floor;
  floor.base_color = glm::vec3(0.7f);
  Material glass;
  glass.roughness = 0.0f;
  glass.transmission = 1.0f;
  glass.base_color = glm::vec3(1.0f);
  glass.attenuation_color = glm::vec3(0.3f, 0.6f, 0.9f);
  glass.attenuation_distance = 0.5f;
  s.materials = {floor, glass};
  add_tri(s, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, 0);
  add_tri(s, {-10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  add_box(s, {-1.5f, -1.5f, 0.0f}, {1.5f, 1.5f, 2.0f}, 1);
  for (glm::vec3 p : {glm::vec3(3, 2, 4), glm::vec3(-3, 1, 5), glm::vec3(0, -4, 3)}) {
    Light l;
    l.position = p;
    l.intensity = glm::vec3(denormal ? 1e-38f : 60.0f);
    s.lights.push_back(l);
  }
  s.background = glm::vec3(denormal ? 1e-38f : 0.2f);
  s.cameras.push_back(Camera::look_at({0, -6, 5}, {0, 0, 0.5f}, {0, 0, 1}, 0.8f));
  s.max_depth = 6;
  s.finalize_materials();
  return s;
}

void BM_Trace(benchmark::State& state) {
  const bool denormal = state.range(0) != 0, flush = state.range(1) != 0;
  const Scene scene = make_scene(denormal);
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const int n = 128;
  const CameraRays rays(scene.cameras[0], n, n);
  uint64_t total = 0;
  for (auto _ : state) {
    std::optional<ScopedFlushDenormals> guard;
    if (flush) guard.emplace();
    SceneSource source(shader, rays);
    float sum = 0.0f;
    for (int y = 0; y < n; y += 2)
      for (int x = 0; x < n; x += 2) {
        const Rgb4 c = source.sample4(float4(x + 0.5f, x + 1.5f, x + 0.5f, x + 1.5f),
                                      float4(y + 0.5f, y + 0.5f, y + 1.5f, y + 1.5f));
        sum += c.r[0] + c.g[1] + c.b[2];
      }
    benchmark::DoNotOptimize(sum);
    total += source.counters.total();
  }
  state.counters["rays/s"] = benchmark::Counter(double(total), benchmark::Counter::kIsRate);
  state.SetLabel(std::string(denormal ? "denormal" : "normal") + (flush ? " ftz+daz" : " default"));
}
BENCHMARK(BM_Trace)->ArgsProduct({{0, 1}, {0, 1}})->ArgNames({"denormal", "flush"})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace zz

BENCHMARK_MAIN();
