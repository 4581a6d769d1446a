// Uniform supersampling: the baselines the adaptive sampler is measured against.
//   none        1 ray through the pixel centre
//   grid        n x n regular points ((i+1/2)/n, (j+1/2)/n)
//   stratified  n x n jittered points, jitter hashed from (pixel, sample) so the image
//               is identical whatever the thread count or tile order
//   lattice     the 25-point lattice of ALGORITHM.md §3: corners shared with the
//               neighbours (weight 1/4 each) + 24 inner points — the "25 rays" reference
// Box filter over the pixel. Samples are streamed to the source 4 at a time.
#pragma once

#include <atomic>
#include <cmath>
#include <cstdint>

#include "aa/lattice.h"
#include "aa/sample_source.h"
#include "core/tile.h"

namespace zz {

enum class UniformPattern { Center, Grid, Stratified, Lattice };

struct UniformSettings {
  UniformPattern pattern = UniformPattern::Center;
  int spp = 1;  // a perfect square for grid/stratified; 25 for lattice; 1 for centre
};

struct UniformStats {
  uint64_t samples = 0;  // image points evaluated (padding lanes of a last packet excluded)
  // Of those, the lattice's corners beyond one per pixel: a tile's far column and row of
  // its shared corner grid, w + h + 1 (adaptive's margin_rays likewise).
  uint64_t margin = 0;
};

// A stateless 32-bit hash (Jarkko Kneip's lowbias32) -> [0,1) floats for jitter.
inline uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
inline float hash_to_unit(uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }

namespace detail {

// Collects image points, traces them 4 at a time, and adds weight * colour to the
// accumulator slot each point belongs to.
template <SampleSource S>
class SampleStream {
 public:
  SampleStream(S& source, glm::vec3* accum, UniformStats& stats)
      : source_(source), accum_(accum), stats_(stats) {}
  ~SampleStream() { flush(); }

  void add(float x, float y, int slot, float weight) {
    px_[n_] = x;
    py_[n_] = y;
    slot_[n_] = slot;
    weight_[n_] = weight;
    if (++n_ == 4) flush();
  }

  void flush() {
    if (n_ == 0) return;
    for (int i = n_; i < 4; ++i) {  // pad a partial packet (the source still counts its rays)
      px_[i] = px_[0];
      py_[i] = py_[0];
    }
    Rgb4 c = source_.sample4(float4::load(px_), float4::load(py_));
    alignas(16) float r[4], g[4], b[4];
    c.r.store(r);
    c.g.store(g);
    c.b.store(b);
    for (int i = 0; i < n_; ++i) accum_[slot_[i]] += weight_[i] * glm::vec3(r[i], g[i], b[i]);
    stats_.samples += uint64_t(n_);
    n_ = 0;
  }

 private:
  S& source_;
  glm::vec3* accum_;
  UniformStats& stats_;
  alignas(16) float px_[4];
  alignas(16) float py_[4];
  int slot_[4];
  float weight_[4];
  int n_ = 0;
};

}  // namespace detail

// Renders one tile with a uniform pattern. `scratch` must hold (w+1)*(h+1) + w*h vec3
// (only the lattice pattern uses the corner part). With `cancel` set by another thread it
// stops at the next row of pixels and returns false, leaving the target untouched: a tile
// of 256 points per pixel is a million rays, too long to wait for when a viewer closes.
template <SampleSource S>
bool render_tile_uniform(S& source, const TileTarget& target, const UniformSettings& settings,
                         glm::vec3* scratch, UniformStats& stats, const std::atomic<bool>* cancel = nullptr) {
  const TileRect& r = target.rect;
  const int w = r.width(), h = r.height();
  auto cancelled = [cancel] { return cancel && cancel->load(std::memory_order_relaxed); };
  glm::vec3* pixels = scratch;
  glm::vec3* corners = scratch + size_t(w) * h;
  for (int i = 0; i < w * h; ++i) pixels[i] = glm::vec3(0.0f);
  {
    detail::SampleStream<S> stream(source, pixels, stats);
    switch (settings.pattern) {
      case UniformPattern::Center:
        for (int y = 0; y < h; ++y) {
          if (cancelled()) return false;
          for (int x = 0; x < w; ++x) stream.add(r.x0 + x + 0.5f, r.y0 + y + 0.5f, y * w + x, 1.0f);
        }
        break;
      case UniformPattern::Grid:
      case UniformPattern::Stratified: {
        const int n = int(std::lround(std::sqrt(float(settings.spp))));
        const float weight = 1.0f / float(n * n);
        const bool jitter = settings.pattern == UniformPattern::Stratified;
        for (int y = 0; y < h; ++y) {
          if (cancelled()) return false;
          for (int x = 0; x < w; ++x) {
            const uint32_t pixel_key = hash32(uint32_t(r.x0 + x) * 0x9E3779B1u ^ hash32(uint32_t(r.y0 + y)));
            for (int j = 0; j < n; ++j)
              for (int i = 0; i < n; ++i) {
                float jx = 0.5f, jy = 0.5f;
                if (jitter) {
                  const uint32_t hs = hash32(pixel_key + uint32_t(j * n + i) * 0x632BE5ABu);
                  jx = hash_to_unit(hs);
                  jy = hash_to_unit(hash32(hs ^ 0xA511E9B3u));
                }
                stream.add(r.x0 + x + (i + jx) / n, r.y0 + y + (j + jy) / n, y * w + x, weight);
              }
          }
        }
        break;
      }
      case UniformPattern::Lattice: {
        // The shared corner grid first (the tile's ring included), then 24 inner points.
        detail::SampleStream<S> corner_stream(source, corners, stats);
        for (int i = 0; i < (w + 1) * (h + 1); ++i) corners[i] = glm::vec3(0.0f);
        for (int y = 0; y <= h; ++y) {
          if (cancelled()) return false;
          for (int x = 0; x <= w; ++x) corner_stream.add(float(r.x0 + x), float(r.y0 + y), y * (w + 1) + x, 1.0f);
        }
        corner_stream.flush();
        stats.margin += uint64_t(w + h + 1);
        const float weight = 1.0f / 25.0f;
        for (int y = 0; y < h; ++y) {
          if (cancelled()) return false;
          for (int x = 0; x < w; ++x)
            for (int k = 1; k < kLatticePoints; ++k)
              stream.add(r.x0 + x + kLattice[k].u, r.y0 + y + kLattice[k].v, y * w + x, weight);
        }
        stream.flush();
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const glm::vec3 a = corners[y * (w + 1) + x], b = corners[y * (w + 1) + x + 1];
            const glm::vec3 c = corners[(y + 1) * (w + 1) + x], d = corners[(y + 1) * (w + 1) + x + 1];
            pixels[y * w + x] += (0.25f * weight) * (a + b + c + d);
          }
        break;
      }
    }
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      target.pixel(r.x0 + x, r.y0 + y) = pixels[y * w + x];
      if (target.rays) {
        const int per_pixel = settings.pattern == UniformPattern::Center ? 1 : settings.spp;
        target.rays[target.index(r.x0 + x, r.y0 + y)] = uint8_t(per_pixel > 255 ? 255 : per_pixel);
      }
      if (target.level) target.level[target.index(r.x0 + x, r.y0 + y)] = 1;
    }
  return true;
}

}  // namespace zz
