// Render progress on stderr: a live bar with rays/s and ETA on a terminal, nothing
// otherwise. tile_done is called from worker threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>

namespace zz {

double seconds_since(std::chrono::steady_clock::time_point t);

class Progress {
 public:
  Progress(int tiles, bool live);
  void tile_done(uint64_t tile_rays);

 private:
  int tiles_;
  bool live_;
  std::atomic<int> done_{0};
  std::atomic<uint64_t> rays_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace zz
