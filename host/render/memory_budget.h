// Fail early, with a clear message, when a frame would not fit in memory — instead of
// being OOM-killed half way through a long render.
#pragma once

#include <cstdint>
#include <string>

namespace zz {

struct RenderSettings;
struct Scene;
struct TileRect;

// Bytes a frame of w x h needs at peak: film (radiance + AOVs), visibility map,
// display image for writing, per-thread sampler scratch.
uint64_t frame_bytes(int width, int height, int threads);

// What rendering `region` of a frame needs beyond the process's memory now: the film's
// (frame_bytes), the level-1 corner field's and the highlight flag's normal-map spreads.
// The Vulkan map's raster and any output layers come on top (the callers know them).
uint64_t render_bytes(const RenderSettings& settings, const TileRect& region, const Scene& scene);

// The process's mapped address space and resident memory now (/proc/self/statm); 0 if unknown.
struct ProcessMemory {
  uint64_t mapped = 0;
  uint64_t resident = 0;
};
ProcessMemory process_memory();
uint64_t resident_bytes();  // process_memory().resident

// $ZIGZAG_MEMORY_LIMIT's value: bytes, or a whole number with K, M, G or T (KiB, MiB, GiB,
// TiB also read: powers of 1024); 0 is no limit. Throws zz::UsageError naming the variable
// for anything else ("4GB", "2e9", "-5"), which strtoull had read as 4, 2 or a huge number.
uint64_t parse_memory_limit(const std::string& text);

// $ZIGZAG_MEMORY_LIMIT read by parse_memory_limit; 0 when unset or empty. Commands call it
// before anything loads, so a malformed value is refused first.
uint64_t environment_memory_limit();

// Memory the process may still use: the smallest of MemAvailable (/proc/meminfo), RLIMIT_AS
// headroom and $ZIGZAG_MEMORY_LIMIT less the process's resident memory, if set and not
// empty or 0 (bytes 0 if unknown, at least 1 otherwise), and which of them it is.
struct MemoryBudget {
  uint64_t bytes = 0;
  std::string bound_by;
};
MemoryBudget memory_budget();

// Throws zz::Error naming the need, the budget and what sets it when `needed` exceeds what
// is available.
void check_memory(uint64_t needed, const char* what);

}  // namespace zz
