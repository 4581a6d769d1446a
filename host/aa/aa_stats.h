// Counts of the adaptive sampler (ALGORITHM.md §10), one per tile, merged in tile order.
// The counts are integers, so merging is exact and the totals do not depend on thread
// count. Times are CPU seconds summed over tiles (wall-clock per tile, so with N threads
// they add up to about N x the elapsed time); levels 2 and 3 interleave per pixel and are
// timed together with the level-1 decisions and the box filter as "refine".
#pragma once

#include <cstdint>

namespace zz {

struct AaStats {
  uint64_t pixels = 0;             // pixels written (a tile's own pixels)
  uint64_t rays[3] = {0, 0, 0};    // distinct points traced at level 1 (corners), 2 (E..H), 3 (zigzags)
  // Lanes traced only to fill a packet (the corner grid's odd last row or column repeats a
  // point). They are camera rays like any other, so rays/px counts them: total_rays() is
  // the renderer's primary ray count (RayCounters::primary), one definition of rays/px.
  uint64_t padded_rays = 0;
  uint64_t margin_rays = 0;        // part of rays[] spent on the Mitchell margin (§8)
  uint64_t level2_pixels = 0;      // own pixels that reached level 2 (or 3)
  uint64_t level3_pixels = 0;      // own pixels that traced at least one zone
  uint64_t vertical_pixels = 0;    // own refined pixels in the vertical orientation
  uint64_t zones_traced = 0;       // over own refined pixels
  uint64_t zones_interpolated = 0;
  uint64_t geo_pixels = 0;         // own pixels whose geo flag was set
  uint64_t hidden_pixels = 0;      // own pixels flagged for detail between their corners (hidden_detail.h)
  uint64_t specular_pixels = 0;    // own pixels that took eps_specular (kSpecularCorners)
  uint64_t gap_pixels = 0;         // own pixels refined only as a gap between refined ones (fills_gap)
  double seconds_corners = 0;      // level 1: tracing + tone mapping the corner grid
  double seconds_refine = 0;       // per-pixel levels 1–3 (+ box filter)
  double seconds_filter = 0;       // Mitchell pass

  void merge(const AaStats& o) {
    pixels += o.pixels;
    for (int i = 0; i < 3; ++i) rays[i] += o.rays[i];
    padded_rays += o.padded_rays;
    margin_rays += o.margin_rays;
    level2_pixels += o.level2_pixels;
    level3_pixels += o.level3_pixels;
    vertical_pixels += o.vertical_pixels;
    zones_traced += o.zones_traced;
    zones_interpolated += o.zones_interpolated;
    geo_pixels += o.geo_pixels;
    hidden_pixels += o.hidden_pixels;
    specular_pixels += o.specular_pixels;
    gap_pixels += o.gap_pixels;
    seconds_corners += o.seconds_corners;
    seconds_refine += o.seconds_refine;
    seconds_filter += o.seconds_filter;
  }
  uint64_t total_rays() const { return rays[0] + rays[1] + rays[2] + padded_rays; }
  double per_pixel(uint64_t n) const { return pixels ? double(n) / double(pixels) : 0.0; }
  double rays_per_pixel() const { return per_pixel(total_rays()); }
  double level2_fraction() const { return per_pixel(level2_pixels); }
  double level3_fraction() const { return per_pixel(level3_pixels); }
};

}  // namespace zz
