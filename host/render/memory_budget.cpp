#include "render/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/address_space.h"
#include "core/error.h"
#include "core/worker_arena.h"
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
  const int threads = worker_threads(settings.threads);
  uint64_t need = frame_bytes(region.width(), region.height(), threads) + corner_field_plan(settings).bytes;
  if (settings.aa == AaMode::Adaptive && settings.adaptive.highlights) need += normal_map_spread_bytes(scene);
  if (settings.aa == AaMode::Adaptive && settings.adaptive.textures) need += texture_pyramid_bytes(scene);
  return need;
}

ProcessMemory process_memory() {
  std::ifstream statm("/proc/self/statm");
  uint64_t size = 0, resident = 0;
  if (!(statm >> size >> resident)) return {};
  const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
  return {size * page, resident * page};
}

uint64_t resident_bytes() { return process_memory().resident; }

uint64_t parse_memory_limit(const std::string& text) {
  const auto bad = [&] {
    return UsageError("ZIGZAG_MEMORY_LIMIT=" + text +
                      ": not a memory size (bytes, or a whole number with K, M, G or T: powers of 1024, as 4G)");
  };
  uint64_t value = 0;
  const char* const end = text.data() + text.size();
  const auto [next, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || next == text.data()) throw bad();
  std::string unit(next, end);
  if (unit.size() == 3 && unit.compare(1, 2, "iB") == 0) unit.resize(1);  // KiB, MiB, GiB, TiB
  int shift = 0;
  if (unit == "K") shift = 10;
  else if (unit == "M") shift = 20;
  else if (unit == "G") shift = 30;
  else if (unit == "T") shift = 40;
  else if (!unit.empty()) throw bad();
  if (value > (UINT64_MAX >> shift)) throw bad();
  return value << shift;
}

uint64_t environment_memory_limit() {
  // Empty or 0: no limit (VAR= is how many tools unset a variable; 0 meant none before).
  const char* env = std::getenv("ZIGZAG_MEMORY_LIMIT");
  return env && *env ? parse_memory_limit(env) : 0;
}

namespace {

// "1.50 GiB", "240.00 MiB", "100.00 KiB": the unit in which `bytes` is at least 1 (a
// ZIGZAG_MEMORY_LIMIT of 100K printed as "0.00 GiB").
std::string bytes_text(uint64_t bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  double value = double(bytes);
  while (unit < 4 && value >= 1024.0) value /= 1024.0, ++unit;
  char text[48];
  if (unit == 0) std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  else std::snprintf(text, sizeof text, "%.2f %s", value, units[unit]);
  return text;
}

}  // namespace

MemoryBudget memory_budget() {
  MemoryBudget budget;
  auto tighten = [&](uint64_t b, const std::string& by) {
    if (budget.bytes != 0 && b >= budget.bytes) return;
    budget.bytes = b;
    budget.bound_by = by;
  };
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t value;
  std::string unit;
  while (meminfo >> key >> value) {
    std::getline(meminfo, unit);
    if (key == "MemAvailable:") {
      tighten(value * 1024, "the memory the system has available");
      break;
    }
  }
  const ProcessMemory process = process_memory();
  if (const uint64_t limit = address_space_limit(); limit > 0) {
    // Address space already mapped counts against the limit.
    const uint64_t mapped = process.mapped;
    tighten(limit > mapped ? limit - mapped : 1, "the address-space limit, ulimit -v, less what is mapped");
  }
  if (const uint64_t limit = environment_memory_limit(); limit > 0) {
    // A limit for the process (a farm worker's share), not for the frame alone: what the
    // process holds already (libraries, Vulkan, the scene, its BVH) counts against it.
    const uint64_t held = process.resident;
    tighten(limit > held ? limit - held : 1, std::string("ZIGZAG_MEMORY_LIMIT=") + std::getenv("ZIGZAG_MEMORY_LIMIT") +
                                                 ", less the " + bytes_text(held) + " the process holds");
  }
  return budget;
}

void check_memory(uint64_t needed, const char* what) {
  const MemoryBudget budget = memory_budget();
  if (budget.bytes == 0 || needed <= budget.bytes) return;
  const std::string left = budget.bytes <= 1 ? "none" : "only " + bytes_text(budget.bytes);  // 1: a limit used up
  throw Error(std::string(what) + " needs about " + bytes_text(needed) + " of memory but " + left + " is available (" +
              budget.bound_by + ")");
}

}  // namespace zz
