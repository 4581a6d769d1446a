// Fail early, with a clear message, when a frame would not fit in memory — instead of
// being OOM-killed half way through a long render.
#pragma once

#include <cstdint>

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

// The process's resident memory now (/proc/self/statm); 0 if unknown.
uint64_t resident_bytes();

// Memory the process may still use: the smaller of MemAvailable (/proc/meminfo),
// RLIMIT_AS headroom and $ZIGZAG_MEMORY_LIMIT (bytes), if set. 0 if unknown.
uint64_t available_bytes();

// Throws zz::Error naming the need and the budget when `needed` exceeds what is available.
void check_memory(uint64_t needed, const char* what);

}  // namespace zz
