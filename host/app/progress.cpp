#include "app/progress.h"

#include <cstdio>

namespace zz {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

Progress::Progress(int steps, bool live) : steps_(steps), live_(live), start_(std::chrono::steady_clock::now()) {}

void Progress::step_done(uint64_t step_rays) {
  const int done = ++done_;
  const uint64_t rays = rays_ += step_rays;
  if (!live_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const double t = seconds_since(start_);
  const double eta = done > 0 ? t * (steps_ - done) / done : 0.0;
  const double mrays_per_s = t > 0.0 ? double(rays) / t * 1e-6 : 0.0;
  const int width = 30, filled = steps_ > 0 ? width * done / steps_ : width;
  std::fprintf(stderr, "\r[%.*s%*s] %d/%d steps  %.1f Mrays/s  %.1fs  ETA %.1fs ", filled,
               "##############################", width - filled, "", done, steps_, mrays_per_s, t, eta);
  if (done == steps_) std::fprintf(stderr, "\r%*s\r", 90, "");
}

}  // namespace zz
