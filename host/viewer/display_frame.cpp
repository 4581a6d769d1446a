#include "viewer/display_frame.h"

#include <algorithm>

#include "core/simd.h"
#include "render/aov.h"

namespace zz {

namespace {

// One pixel's display bytes with the exact arithmetic of display_bytes() (tone map in
// SSE lanes, *255 + 0.5, clamp, truncate), so the image view equals the PNG bit for bit.
void display_pixel(const ToneMap& tonemap, const glm::vec3& c, uint8_t out[3]) {
  const float4 t = tonemap.apply4(float4(c.x, c.y, c.z, 0.0f)) * float4(255.0f) + float4(0.5f);
  for (int k = 0; k < 3; ++k) out[k] = uint8_t(std::clamp(t[k], 0.0f, 255.0f));
}

}  // namespace

void heat_color(int rays, uint8_t rgb[3]) {
  if (rays <= 0) {  // not rendered yet
    rgb[0] = rgb[1] = rgb[2] = 0;
    return;
  }
  ray_count_colour(rays, rgb);  // the ramp of `zigzag render --aov rays`
}

int DisplayFrame::width() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return width_;
}

int DisplayFrame::height() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return height_;
}

void DisplayFrame::resize(int width, int height) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (width == width_ && height == height_) return;
  width_ = width;
  height_ = height;
  const size_t n = size_t(width) * height;
  rgb_.assign(n * 3, 0);
  rays_.assign(n, 0);
  level_.assign(n, 0);
  geo_ = {};
  ++version_;
}

void DisplayFrame::put_tile(const Film& film, const TileRect& rect, int scale, const ToneMap& tonemap) {
  // Convert outside the lock: the tile's film pixels are final and owned by this worker.
  const int tw = rect.width(), th = rect.height();
  std::vector<uint8_t> bytes(size_t(tw) * th * 3);
  for (int y = 0; y < th; ++y)
    for (int x = 0; x < tw; ++x)
      display_pixel(tonemap, film.radiance[size_t(rect.y0 + y) * film.width + rect.x0 + x],
                    &bytes[(size_t(y) * tw + x) * 3]);

  std::lock_guard<std::mutex> lock(mutex_);
  for (int y = 0; y < th; ++y) {
    const size_t src = size_t(rect.y0 + y) * film.width + rect.x0;
    const int dy0 = (rect.y0 + y) * scale, dy1 = std::min(dy0 + scale, height_);
    for (int x = 0; x < tw; ++x) {
      const uint8_t* b = &bytes[(size_t(y) * tw + x) * 3];
      const int dx0 = (rect.x0 + x) * scale, dx1 = std::min(dx0 + scale, width_);
      for (int dy = dy0; dy < dy1; ++dy)
        for (int dx = dx0; dx < dx1; ++dx) {
          const size_t d = size_t(dy) * width_ + dx;
          std::copy(b, b + 3, &rgb_[d * 3]);
          rays_[d] = film.rays[src + x];
          level_[d] = film.level[src + x];
        }
    }
  }
  ++version_;
}

void DisplayFrame::set_geo(const GeoMap& geo) {
  std::lock_guard<std::mutex> lock(mutex_);
  geo_ = geo;
  ++version_;
}

bool DisplayFrame::has_geo() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !geo_.empty() && geo_.width == width_ && geo_.height == height_;
}

uint64_t DisplayFrame::version() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

void DisplayFrame::compose(ViewMode mode, bool bgra, std::vector<uint8_t>& out, int& width, int& height) const {
  std::lock_guard<std::mutex> lock(mutex_);
  width = width_;
  height = height_;
  out.resize(size_t(width_) * height_ * 4);
  compose_locked(mode, bgra, 4, out.data());
}

std::vector<uint8_t> DisplayFrame::rgb(ViewMode mode, int* width, int* height) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (width) *width = width_;
  if (height) *height = height_;
  std::vector<uint8_t> out(size_t(width_) * height_ * 3);
  compose_locked(mode, false, 3, out.data());
  return out;
}

void DisplayFrame::compose_locked(ViewMode mode, bool bgra, int channels, uint8_t* dst) const {
  const size_t n = size_t(width_) * height_;
  const bool geo_ok = !geo_.empty() && geo_.width == width_ && geo_.height == height_;
  const int r = bgra ? 2 : 0, b = bgra ? 0 : 2;
  for (size_t i = 0; i < n; ++i) {
    uint8_t c[3] = {0, 0, 0};
    switch (mode) {
      case ViewMode::Image: std::copy(&rgb_[i * 3], &rgb_[i * 3] + 3, c); break;
      case ViewMode::Rays: heat_color(rays_[i], c); break;
      case ViewMode::Level: level_colour(level_[i], c); break;
      case ViewMode::Geo:
        if (geo_ok) {
          c[0] = c[1] = c[2] = geo_.flags[i] ? 255 : 0;  // as `zigzag render --aov geo`
        } else {
          // Not available: a dark checkerboard (the title says why).
          const size_t x = i % size_t(width_), y = i / size_t(width_);
          c[0] = c[1] = c[2] = ((x / 16 + y / 16) & 1) ? 48 : 32;
        }
        break;
    }
    uint8_t* d = dst + i * channels;
    d[r] = c[0];
    d[1] = c[1];
    d[b] = c[2];
    if (channels == 4) d[3] = 255;
  }
}

}  // namespace zz
