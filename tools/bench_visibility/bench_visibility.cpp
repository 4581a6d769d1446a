// Visibility map cost: raster + compute + readback at S = 4 and 6 for 512^2, 1024^2 and
// 2048^2 frames on the room, glass and car scenes (generated stand-ins when a scene does
// not load). Manual time = host wall time of VisibilityPass::run; the counters split it
// into GPU raster / compute (timestamps) and host readback. Compare LP_NUM_THREADS=1/2.
// The `.../sse` lines time the same rule on the host (gpu/geo_flags_cpu.h, one thread)
// over the same ids: the baseline the compute pass is measured against.
// Usage: bench_visibility [benchmark flags] [scene.json ...]
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "gpu/device.h"
#include "gpu/geo_flags_cpu.h"
#include "gpu/visibility.h"

using namespace zz;

namespace {

std::unique_ptr<VulkanContext> g_context;
std::vector<std::unique_ptr<Scene>> g_scenes;
std::vector<std::unique_ptr<VisibilityPass>> g_passes;

// CPU seconds of the whole process (lavapipe's worker threads included): on a machine
// shared with other jobs this is steadier than wall time.
double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void run(benchmark::State& state, VisibilityPass* pass, const Scene* scene, int size, int ss) {
  VisibilitySettings settings;
  settings.supersample = ss;
  const Camera& camera = scene->cameras.front();
  double raster = 0, compute = 0, readback = 0, geo = 0;
  int tiles = 0;
  double cpu0 = process_cpu_s();
  for (auto _ : state) {
    VisibilityTimings t;
    GeoMap map = pass->run(camera, size, size, settings, &t);
    state.SetIterationTime(t.total_s);
    raster += t.raster_s;
    compute += t.compute_s;
    readback += t.readback_s;
    tiles = t.tiles;
    size_t n = 0;
    for (uint8_t f : map.flags) n += f != 0;
    geo = double(n) / double(map.flags.size());
  }
  double it = double(state.iterations());
  state.counters["process_cpu_ms"] = 1e3 * (process_cpu_s() - cpu0) / it;
  state.counters["raster_ms"] = 1e3 * raster / it;
  state.counters["compute_ms"] = 1e3 * compute / it;
  state.counters["readback_ms"] = 1e3 * readback / it;
  state.counters["tiles"] = tiles;
  state.counters["geo_fraction"] = geo;
  state.counters["triangles"] = double(scene->triangle_count());
}

// The host SSE rule on the frame's ids (rendered once, outside the timing).
void run_sse(benchmark::State& state, VisibilityPass* pass, const Scene* scene, int size, int ss) {
  VisibilitySettings settings;
  settings.supersample = ss;
  const Camera& camera = scene->cameras.front();
  const std::vector<uint32_t> ids = pass->render_ids(camera, size, size, settings);
  const gpu::FlagPush push = make_flag_push(camera, size, size, settings);
  const std::vector<glm::vec4> planes =
      triangle_planes(scene->positions, geometric_normals(*scene), glm::vec3(push.origin));
  double cpu0 = process_cpu_s();
  size_t n = 0;
  for (auto _ : state) {
    GeoMap map = geo_flags_cpu(ids, planes, push);
    n = 0;
    for (uint8_t f : map.flags) n += f != 0;
  }
  state.counters["process_cpu_ms"] = 1e3 * (process_cpu_s() - cpu0) / double(state.iterations());
  state.counters["geo_fraction"] = double(n) / (double(size) * size);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) files.push_back(argv[i]);
  if (files.empty())
    for (const char* name : {"room", "glass", "car"}) files.push_back(std::string(ZZ_SOURCE_DIR) + "/scenes/" + name + ".json");
  try {
    g_context = VulkanContext::create({});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_visibility: %s\n", e.what());
    return 1;
  }
  const char* threads = std::getenv("LP_NUM_THREADS");
  std::printf("device: %s, LP_NUM_THREADS=%s\n", g_context->device_name().c_str(), threads ? threads : "(unset)");
  for (const auto& file : files) {
    size_t slash = file.find_last_of('/'), dot = file.find_last_of('.');
    std::string name = file.substr(slash + 1, dot == std::string::npos ? std::string::npos : dot - slash - 1);
    g_scenes.push_back(std::make_unique<Scene>(bench::scene_or_fallback(file, name)));
    g_passes.push_back(std::make_unique<VisibilityPass>(*g_context, *g_scenes.back()));
    VisibilityTimings warm;  // the first run pays the shader JIT
    g_passes.back()->run(g_scenes.back()->cameras.front(), 64, 64, {}, &warm);
    std::printf("%s: %zu triangles, upload %.1f ms, first (JIT) run %.1f ms\n", name.c_str(),
                g_scenes.back()->triangle_count(), 1e3 * warm.upload_s, 1e3 * warm.total_s);
    for (int ss : {4, 6})
      for (int size : {512, 1024, 2048})
        benchmark::RegisterBenchmark(
            (name + "/S" + std::to_string(ss) + "/" + std::to_string(size)).c_str(), run, g_passes.back().get(),
            g_scenes.back().get(), size, ss)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(size >= 2048 ? 2 : 4);
    for (int ss : {4, 6})
      benchmark::RegisterBenchmark((name + "/S" + std::to_string(ss) + "/1024/sse").c_str(), run_sse,
                                   g_passes.back().get(), g_scenes.back().get(), 1024, ss)
          ->Unit(benchmark::kMillisecond)
          ->Iterations(4);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  g_passes.clear();
  g_context.reset();
}
