// The viewer's CPU-side picture of the frame being rendered: display bytes and AOVs per
// pixel, written tile by tile from the render workers, read by the UI thread to fill the
// swapchain staging buffer. Holding display bytes (not radiance) keeps presentation a
// plain copy and makes the image view byte-identical to `zigzag render`'s PNG.
#pragma once

#include <cstdint>
#include <mutex>
#include <vector>

#include "core/geo_map.h"
#include "core/tile.h"
#include "core/tonemap.h"
#include "core/film.h"
#include "viewer/view_mode.h"

namespace zz {

class DisplayFrame {
 public:
  int width() const;
  int height() const;
  // Changes the frame size; the content is cleared when the size changes.
  void resize(int width, int height);

  // Copies a finished tile of `film`, rendered at 1/scale of this frame's size, into the
  // frame; each film pixel covers a scale x scale block (nearest upscaling).
  void put_tile(const Film& film, const TileRect& rect, int scale, const ToneMap& tonemap);
  // The visibility map of the frame; an empty map shows as "not available".
  void set_geo(const GeoMap& geo);
  bool has_geo() const;

  // The view as 4 bytes per pixel (B,G,R,A when bgra, else R,G,B,A) into `out`
  // (resized), with the size it has at this moment (the render thread may resize it).
  void compose(ViewMode mode, bool bgra, std::vector<uint8_t>& out, int& width, int& height) const;
  // The view as 8-bit RGB (for screenshots); width/height, when given, receive the size
  // it was composed at (the render thread may resize the frame at any time).
  std::vector<uint8_t> rgb(ViewMode mode, int* width = nullptr, int* height = nullptr) const;

  // Bumped on every change: the UI presents only when it moved.
  uint64_t version() const;

 private:
  void compose_locked(ViewMode mode, bool bgra, int channels, uint8_t* dst) const;

  mutable std::mutex mutex_;
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> rgb_;    // display bytes, 3 per pixel
  std::vector<uint8_t> rays_;   // rays per pixel (saturating)
  std::vector<uint8_t> level_;  // AA level (+4 vertical)
  GeoMap geo_;
  uint64_t version_ = 0;
};

// Per-pixel colours of the AOV views, the same as `zigzag render --aov rays|levels`
// (pixels not rendered yet are black); levels use render/aov.h level_colour.
void heat_color(int rays, uint8_t rgb[3]);

}  // namespace zz
