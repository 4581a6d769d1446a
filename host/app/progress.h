// Render progress on stderr: a live bar with rays/s and ETA on a terminal, nothing
// otherwise. A step is a tile, or a block of level-1 corners traced before the tiles
// (render/renderer.h); step_done is called from worker threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>

namespace zz {

double seconds_since(std::chrono::steady_clock::time_point t);

class Progress {
 public:
  Progress(int steps, bool live);
  void step_done(uint64_t step_rays);

 private:
  int steps_;
  bool live_;
  std::atomic<int> done_{0};
  std::atomic<uint64_t> rays_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace zz
