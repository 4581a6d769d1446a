#include "render/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "core/error.h"
#include "render/renderer.h"
#include "render/texture_detail.h"
#include "render/texture_range.h"

namespace zz {

uint64_t frame_bytes(int width, int height, int threads) {
  const uint64_t pixels = uint64_t(width) * uint64_t(height);
  const uint64_t film = pixels * (12 + 1 + 1);  // radiance, rays, level
  const uint64_t geo = pixels;                   // visibility flags
  const uint64_t display = pixels * 3;           // 8-bit image handed to the writer
  const uint64_t scratch = uint64_t(std::max(threads, 1)) * (4u << 20);  // region buffers per worker
  return film + geo + display + scratch;
}

uint64_t render_bytes(const RenderSettings& settings, const TileRect& region, const Scene& scene) {
  const int threads = settings.threads > 0 ? settings.threads : int(std::thread::hardware_concurrency());
  uint64_t need = frame_bytes(region.width(), region.height(), threads) + corner_field_plan(settings).bytes;
  if (settings.aa == AaMode::Adaptive && settings.adaptive.highlights) need += normal_map_spread_bytes(scene);
  if (settings.aa == AaMode::Adaptive && settings.adaptive.textures) need += texture_pyramid_bytes(scene);
  return need;
}

uint64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  uint64_t size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

uint64_t available_bytes() {
  uint64_t budget = 0;
  auto tighten = [&](uint64_t b) { budget = budget == 0 ? b : std::min(budget, b); };
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t value;
  std::string unit;
  while (meminfo >> key >> value) {
    std::getline(meminfo, unit);
    if (key == "MemAvailable:") {
      tighten(value * 1024);
      break;
    }
  }
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    // Address space already mapped counts against the limit.
    uint64_t mapped = 0;
    std::ifstream statm("/proc/self/statm");
    if (statm >> mapped) mapped *= 4096;
    tighten(uint64_t(limit.rlim_cur) > mapped ? uint64_t(limit.rlim_cur) - mapped : 1);
  }
  if (const char* env = std::getenv("ZIGZAG_MEMORY_LIMIT")) {
    char* end = nullptr;
    const unsigned long long b = std::strtoull(env, &end, 10);
    if (end != env && b > 0) tighten(b);
  }
  return budget;
}

void check_memory(uint64_t needed, const char* what) {
  const uint64_t available = available_bytes();
  if (available == 0 || needed <= available) return;
  char msg[256];
  std::snprintf(msg, sizeof msg, "%s needs about %.2f GiB of memory but only %.2f GiB is available", what,
                double(needed) / double(1ull << 30), double(available) / double(1ull << 30));
  throw Error(msg);
}

}  // namespace zz
