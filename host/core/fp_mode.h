// Floating-point mode of a worker thread: flush-to-zero (results that would be
// denormal become 0) and denormals-are-zero (denormal inputs read as 0). Denormal
// operands cost ~100 cycles per SSE op on x86 (microcode assist), so a scene whose
// radiance decays towards 1e-38 (tiny lights, long absorbing paths) could otherwise run
// orders of magnitude slower. Rendering never needs values below FLT_MIN (1.2e-38):
// they are invisible after tone mapping. MXCSR is per thread, so every tile task sets
// it; the RAII guard restores the caller's mode (TBB may run other work on the thread).
#pragma once

#include <xmmintrin.h>

namespace zz {

inline constexpr unsigned kMxcsrFlushToZero = 0x8000;     // FTZ, bit 15
inline constexpr unsigned kMxcsrDenormalsAreZero = 0x0040;  // DAZ, bit 6

class ScopedFlushDenormals {
 public:
  ScopedFlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kMxcsrFlushToZero | kMxcsrDenormalsAreZero); }
  ~ScopedFlushDenormals() { _mm_setcsr(saved_); }
  ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
  ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

 private:
  unsigned saved_;
};

// True when both FTZ and DAZ are set on the calling thread.
inline bool denormals_flushed() {
  const unsigned m = _mm_getcsr();
  return (m & kMxcsrFlushToZero) && (m & kMxcsrDenormalsAreZero);
}

}  // namespace zz
