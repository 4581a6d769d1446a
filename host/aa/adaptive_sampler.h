// The adaptive sampler of one tile (ALGORITHM.md §1–§8).
//
// Level 1 traces the (w+1) x (h+1) corner grid of the tile (its pixels' corners plus the
// ring it shares with its neighbours, traced again by them: the paper's one-pixel
// overlap) in 2x2 packets; with the curvature correction one more ring (the second
// differences of the tile's border pixels need their neighbours' corners), and with the
// hidden-detail flags the source's probes of every corner decide which pixels hide more
// than their corners show (hidden_detail.h). Every pixel then runs levels 1–3 of
// adaptive_pixel.h. The renderer and render_frame_adaptive trace level 1 of a whole frame
// at once instead (corner_field.h: each corner once) and hand each tile its grid; same
// image.
//
// Filters. Box needs only the pixel's own lattice. Mitchell (radius 2) needs the lattice
// of the neighbouring pixels too, across tile borders. Design: the tile runs levels 1–3
// over its rect grown by a 2-pixel margin (clipped to the frame) into a per-thread
// buffer, then filters its own pixels from that buffer. A pixel's lattice is a pure
// function of its position (corners are lane-independent samples at fixed points; the
// rest follows from them), so the image is bit-identical for any tile size, thread
// count or order. Memory is one region buffer per thread ((64+4)² pixels x 25 points x
// 16 B = 1.9 MB), independent of the frame size (a frame-wide lattice would need
// 25 x 16 B per pixel: 6.7 GB at 4096²). Cost: margin pixels run levels 2-3 twice; for
// 64² tiles that is (68² - 64²)/64² ≈ 12.5 % more of the refinement rays (per tile, level 1
// of the margin too), all counted in AaStats::rays and reported in AaStats::margin_rays.
#pragma once

#include <algorithm>
#include <cassert>
#include <chrono>
#include <type_traits>
#include <vector>

#include "aa/aa_stats.h"
#include "aa/adaptive_pixel.h"
#include "aa/adaptive_settings.h"
#include "aa/filters.h"
#include "aa/hidden_detail.h"
#include "aa/mitchell.h"
#include "core/geo_map.h"
#include "core/tile.h"

namespace zz {

// Level 1 of a tile's region, written by trace_corners (or gather_corners, from a whole
// frame's field: corner_field.h) and read by refine_tile: the
// region's (w+1) x (h+1) corner samples, and per region pixel whether the source said
// the corners may have missed something that shows (hidden_detail.h).
struct CornerGrid {
  std::vector<float4> linear;      // AoS (r, g, b, 0)
  std::vector<float4> display;     // tone-mapped
  std::vector<int32_t> signature;  // signature.h (0 when the source has none)
  std::vector<HiddenFlag> hidden;  // per region pixel; empty when no source flags
  std::vector<float4> footprint;   // per region pixel, the footprint delta; empty unless on

  // Grows (never shrinks, so per-thread grids are reused without allocating).
  void reserve(size_t corners, size_t pixels, size_t footprint_pixels) {
    if (linear.size() < corners) {
      linear.resize(corners);
      display.resize(corners);
      signature.resize(corners);
    }
    if (hidden.size() < pixels) hidden.resize(pixels);
    if (footprint.size() < footprint_pixels) footprint.resize(footprint_pixels);
  }
};

// Per-thread buffers, grown on first use and then reused (no allocation per pixel).
struct AdaptiveScratch {
  CornerGrid corners;
  std::vector<float4> lattice;         // Mitchell: 25 per region pixel, by physical k
  std::vector<uint8_t> refined;        // Mitchell: per region pixel
  std::vector<uint8_t> around;         // --fill-gaps: refined_around's decisions

  static AdaptiveScratch& local() {
    static thread_local AdaptiveScratch s;
    return s;
  }
};

// The probe type of a source's samples (hidden_detail.h); an empty one for the others.
struct NoProbe {};
template <class S>
struct ProbeOf {
  using type = NoProbe;
};
template <HiddenDetailSource S>
struct ProbeOf<S> {
  using type = typename S::Probe;
};

// Per-thread probes of a tile's corner grid, one buffer per probe type.
template <class Probe>
Probe* corner_probes(size_t n) {
  static thread_local std::vector<Probe> probes;
  if (probes.size() < n) probes.resize(n);
  return probes.data();
}

// `r` grown by `m` pixels on every side, clipped to the frame.
inline TileRect grown_in_frame(const TileRect& r, int m, int frame_width, int frame_height) {
  return {std::max(0, r.x0 - m), std::max(0, r.y0 - m), std::min(frame_width, r.x1 + m),
          std::min(frame_height, r.y1 + m)};
}
// Pixels beyond a tile whose samples the filter weighs (Mitchell reads its neighbours' lattices).
inline int filter_margin(Filter filter) { return filter == Filter::Mitchell ? kMitchellRadius : 0; }

// The pixels a tile's sampler covers: the tile grown by the filter's margin, clipped to the
// frame.
inline TileRect adaptive_region(const TileRect& tile, int frame_width, int frame_height, Filter filter) {
  return grown_in_frame(tile, filter_margin(filter), frame_width, frame_height);
}

// Whether --fill-gaps runs: its gaps are image pixels, decided at eps_specular (and only a
// source with probes tells them: refine_tile's `hidden`).
inline bool gaps_apply(const AdaptiveSettings& settings) {
  return settings.fill_gaps && settings.eps_specular >= 0.0f && !settings.refine_all;
}

// The pixels of the visibility map that a render of `region` reads, so a caller rendering
// part of a frame needs the map over them: the refined pixels (adaptive_region) and, with
// --fill-gaps, one more on every side, whose level-1 decisions refined_around makes from the
// map too. A map made over less reads 0 there, and the region's border pixels would decide
// otherwise than in the full frame.
inline TileRect adaptive_geo_reads(const TileRect& region, int frame_width, int frame_height,
                                   const AdaptiveSettings& settings) {
  const int m = filter_margin(settings.filter) + (gaps_apply(settings) ? 1 : 0);
  return grown_in_frame(region, m, frame_width, frame_height);
}

// Where a tile's corner grid lies: the region's (w+1) x (h+1) pixel corners, grown by a
// ring of one corner on every side when the curvature correction (adaptive_pixel.h) or the
// highlight flag (the normals' curvature, render/specular_peak.h) needs its neighbours'
// corners; (x0, y0) is the grid's first corner in frame pixels.
struct CornerLayout {
  TileRect region;  // the pixels refined
  int ring = 0;     // corners beyond the region's own on every side
  int x0 = 0, y0 = 0, width = 0, height = 0;
  size_t corners() const { return size_t(width) * size_t(height); }
  size_t pixels() const { return size_t(region.width()) * size_t(region.height()); }
  // Grid index of the corner at frame position (x, y).
  int index(int x, int y) const { return (y - y0) * width + (x - x0); }
};
// The curvature correction is the box filter's (Mitchell weighs the corners as they are).
inline bool curvature_applies(const AdaptiveSettings& settings) {
  return settings.curvature && settings.filter == Filter::Box && !settings.refine_all;
}
// The hidden-detail flags read the ring too (the highlight flag's normals one corner beyond
// the pixel's; every pixel's flag word, which the footprint correction and the mirror's
// threshold ride in, is made from a stencil). Sources without probes never read it: it
// costs them only the ring's corners (about 4 / 64 of a tile's with per-tile corners, none
// extra with the corner field beyond its outer edge).
inline bool corner_ring(const AdaptiveSettings& settings) {
  return curvature_applies(settings) ||
         ((settings.highlights || settings.textures || footprint_applies(settings) || settings.eps_specular >= 0.0f) &&
          !settings.refine_all);
}
inline CornerLayout corner_layout(const TileTarget& target, const AdaptiveSettings& settings) {
  CornerLayout l;
  l.region = adaptive_region(target.rect, target.frame_width, target.frame_height, settings.filter);
  l.ring = corner_ring(settings) ? 1 : 0;
  l.x0 = l.region.x0 - l.ring;
  l.y0 = l.region.y0 - l.ring;
  l.width = l.region.width() + 1 + 2 * l.ring;
  l.height = l.region.height() + 1 + 2 * l.ring;
  return l;
}

// The pixel corners of `r`, (w + 1) x (h + 1): what level 1 of `r` needs at the least.
inline uint64_t own_corners(const TileRect& r) { return uint64_t(r.width() + 1) * uint64_t(r.height() + 1); }

// Whether a tile of `source` under `settings` fills CornerGrid::hidden.
template <SampleSource S>
constexpr bool flags_hidden(const AdaptiveSettings& settings) {
  if constexpr (HiddenDetailSource<S>)
    return (settings.highlights || settings.textures || (FootprintSource<S> && footprint_applies(settings)) ||
            settings.eps_specular >= 0.0f) &&
           !settings.refine_all;
  return false;
}

// Whether unrefined pixels of a source of `S` under `settings` take the footprint delta.
template <class S>
constexpr bool corrects_footprint(const AdaptiveSettings& settings) {
  if constexpr (FootprintSource<S>) return footprint_applies(settings);
  return false;
}

// Level 1 over a block of corners: the w x h corners from frame position (x0, y0) in 2x2
// packets (an odd last row or column repeats a lane), written row by row with `stride`
// into the arrays (probes only when non-null, with row pitch `probe_stride`). Adds the
// distinct points to stats.rays[0] and the repeated lanes to stats.padded_rays; returns the
// distinct points.
template <SampleSource S, class Probe>
uint64_t trace_corner_block(S& source, const ToneMap& tonemap, int x0, int y0, int w, int h, size_t stride,
                            float4* corner_lin, float4* corner_disp, int32_t* corner_sig, Probe* probes,
                            size_t probe_stride, AaStats& stats) {
  uint64_t corner_rays = 0;
  [[maybe_unused]] Probe spare[3];
  for (int j = 0; j < h; j += 2) {
    const int j1 = std::min(j + 1, h - 1);
    for (int i = 0; i < w; i += 2) {
      const int i1 = std::min(i + 1, w - 1);
      const float4 px(float(x0 + i), float(x0 + i1), float(x0 + i), float(x0 + i1));
      const float4 py(float(y0 + j), float(y0 + j), float(y0 + j1), float(y0 + j1));
      int4 sig;
      const size_t at[4] = {j * probe_stride + i, j * probe_stride + i1, j1 * probe_stride + i,
                            j1 * probe_stride + i1};
      Rgb4 c;
      if constexpr (HiddenDetailSource<S>) {
        if (probes) {
          // Distinct lanes write their probes in place; a repeated lane writes to `spare`.
          c = source.sample4(px, py, sig,
                             ProbeLanes<Probe>(probes + at[0], i1 != i ? probes + at[1] : &spare[0],
                                               j1 != j ? probes + at[2] : &spare[1],
                                               i1 != i && j1 != j ? probes + at[3] : &spare[2]));
        } else {
          c = sample4_signed(source, px, py, sig);
        }
      } else {
        c = sample4_signed(source, px, py, sig);
      }
      const Rgb4 d = tonemap.apply4(c);
      float4 l[4], t[4];
      alignas(16) int32_t g[4];
      aos_from_soa(c, l[0], l[1], l[2], l[3]);
      aos_from_soa(d, t[0], t[1], t[2], t[3]);
      sig.store(g);
      // Write lanes back to front so a repeated lane never overwrites a distinct one.
      const size_t idx[4] = {j * stride + i, j * stride + i1, j1 * stride + i, j1 * stride + i1};
      for (int lane = 3; lane >= 0; --lane)
        corner_lin[idx[lane]] = l[lane], corner_disp[idx[lane]] = t[lane], corner_sig[idx[lane]] = g[lane];
      corner_rays += uint64_t(1 + (i1 != i)) * uint64_t(1 + (j1 != j));
    }
  }
  stats.rays[0] += corner_rays;
  stats.padded_rays += 4 * uint64_t((w + 1) / 2) * uint64_t((h + 1) / 2) - corner_rays;
  return corner_rays;
}

// A pixel's four corners (TL, TR, BL, BR) in a corner grid of row pitch `stride`, `tl` its
// TL corner: display colours as the level-1 and level-2 comparisons read them, and their
// signatures.
inline Rgb4 pixel_corners(const float4* tl, ptrdiff_t stride) {
  return soa_from_aos(tl[0], tl[1], tl[stride], tl[stride + 1]);
}
inline int4 pixel_corners(const int32_t* tl, ptrdiff_t stride) {
  return int4(tl[0], tl[1], tl[stride], tl[stride + 1]);
}

// What level 1 traced at a block's corners: corner (i, j) at [j * stride + i].
struct CornerView {
  const float4* linear;
  const float4* display;
  const int32_t* signature;
  ptrdiff_t stride;
};

// The footprint correction's per-corner share (FootprintSource::footprint_corner) for the
// two rows of corners under one row of pixels, made when a pixel first needs it: each corner
// serves up to four pixels. Row 0 is the pixels' top corners, row 1 their bottom ones;
// next_row() moves down a row, keeping the bottom row's. Per thread, reused.
template <class S>
struct FootprintRows {};  // a source without the correction: flag_hidden_block never asks
template <FootprintSource S>
struct FootprintRows<S> {
  using Corner = typename S::FootprintCorner;
  std::vector<Corner>* rows = nullptr;
  std::vector<uint8_t>* ready = nullptr;
  size_t width = 0;
  int top = 0;  // which half of `rows` holds row 0

  void reset(int corners_per_row) {
    thread_local std::vector<Corner> storage;
    thread_local std::vector<uint8_t> made;
    width = size_t(corners_per_row);
    if (storage.size() < 2 * width) storage.resize(2 * width);
    made.assign(2 * width, 0);
    rows = &storage;
    ready = &made;
    top = 0;
  }
  void next_row() {
    std::fill_n(ready->begin() + ptrdiff_t(size_t(top) * width), width, uint8_t(0));
    top ^= 1;
  }
  const Corner* at(const S& source, const typename S::Probe* probe, int row, int column) {
    const size_t k = size_t(top ^ row) * width + size_t(column);
    if (!(*ready)[k]) {
      (*rows)[k] = source.footprint_corner(*probe);
      (*ready)[k] = 1;
    }
    return &(*rows)[k];
  }
};

// The hidden-detail flags (hidden_detail.h) of a w x h block of pixels: pixel (i, j)'s TL
// corner is probes[j * probe_stride + i] and corners' (i, j) (a ring of probes around the
// block must exist), its flag goes to flags[j * flag_stride + i] and, when `footprint` is
// non-null, its footprint delta to footprint[j * flag_stride + i]. A pixel that level 1
// refines whatever the map says (its corners differ, or it is flagged) never uses its
// delta, which is then left at 0.
template <HiddenDetailSource S>
void flag_hidden_block(const S& source, const typename S::Probe* probes, ptrdiff_t probe_stride, CornerView corners,
                       int w, int h, const AdaptiveSettings& settings, HiddenFlag* flags, float4* footprint,
                       ptrdiff_t flag_stride) {
  const float4 eps(settings.eps);
  const bool flagging = settings.highlights || settings.textures;
  const ptrdiff_t cs = corners.stride;
  [[maybe_unused]] FootprintRows<S> prepared;
  if constexpr (FootprintSource<S>) {
    if (footprint) prepared.reset(w + 1);
  }
  for (int j = 0; j < h; ++j) {
    if constexpr (FootprintSource<S>) {
      if (footprint && j > 0) prepared.next_row();
    }
    for (int i = 0; i < w; ++i) {
      const ptrdiff_t at = j * cs + i;
      const float4* c = corners.linear + at;
      const typename S::Probe* tl = probes + j * probe_stride + i;
      const float4 mean = corner_mean(c[0], c[1], c[cs], c[cs + 1]);
      const HiddenFlag flag = flagging ? hidden_detail_shows(source, tl, probe_stride, mean, settings.tonemap, eps) : 0;
      const bool flagged = flag != 0;
      const bool specular = settings.eps_specular >= 0.0f && source.specular_corners(tl, probe_stride);
      flags[j * flag_stride + i] = flag | (specular ? kSpecularCorners : 0u);
      if constexpr (FootprintSource<S>) {
        if (!footprint) continue;
        // At the pixel's own threshold, as refine_tile decides: a mirror's or a glass's image
        // pixel at eps_specular (at eps, one between the two thresholds computed a delta that
        // refine_tile then refined away, or, with eps_specular above eps, stayed unrefined
        // without its delta).
        const bool refined = decide_level1(pixel_corners(corners.display + at, cs),
                                           pixel_corners(corners.signature + at, cs),
                                           specular ? float4(settings.eps_specular) : eps, flagged, false)
                                 .refine;
        if (refined) {
          footprint[j * flag_stride + i] = float4(0.0f);
          continue;
        }
        const typename S::FootprintCorner* const four[4] = {
            prepared.at(source, tl, 0, i), prepared.at(source, tl + 1, 0, i + 1),
            prepared.at(source, tl + probe_stride, 1, i), prepared.at(source, tl + probe_stride + 1, 1, i + 1)};
        footprint[j * flag_stride + i] = source.footprint_delta(tl, probe_stride, four, mean);
      }
    }
  }
}

// The hidden-detail flag of every region pixel from the probes of a tile's own corner grid
// (laid out as `layout`, row pitch layout.width).
template <HiddenDetailSource S>
void flag_hidden_pixels(const S& source, const CornerLayout& layout, const typename S::Probe* probes,
                        const AdaptiveSettings& settings, CornerGrid& grid) {
  assert(layout.ring >= 1);  // the highlight flag reads the normals one corner beyond the pixel's
  const TileRect region = layout.region;
  const size_t first = size_t(layout.index(region.x0, region.y0));
  const CornerView corners{grid.linear.data() + first, grid.display.data() + first, grid.signature.data() + first,
                           layout.width};
  flag_hidden_block(source, probes + first, layout.width, corners, region.width(), region.height(), settings,
                    grid.hidden.data(),
                    corrects_footprint<S>(settings) ? grid.footprint.data() : nullptr, region.width());
}

// Level 1 of a tile: the corner grid of its region in 2x2 packets into `grid` (grown to
// fit), and, where the source can say so, which pixels hide more than their corners show.
// Needs no visibility map, so it can run while the map is still being made.
template <SampleSource S>
void trace_corners(S& source, const TileTarget& target, const AdaptiveSettings& settings, CornerGrid& grid,
                   AaStats& stats) {
  const TileRect tile = target.rect;
  if (tile.width() <= 0 || tile.height() <= 0) return;
  const CornerLayout layout = corner_layout(target, settings);
  const bool probing = flags_hidden<S>(settings);
  grid.reserve(layout.corners(), probing ? layout.pixels() : 0, corrects_footprint<S>(settings) ? layout.pixels() : 0);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();

  using Probe = typename ProbeOf<S>::type;
  Probe* probes = probing ? corner_probes<Probe>(layout.corners()) : nullptr;
  const uint64_t corner_rays =
      trace_corner_block(source, settings.tonemap, layout.x0, layout.y0, layout.width, layout.height,
                         size_t(layout.width), grid.linear.data(), grid.display.data(), grid.signature.data(), probes,
                         size_t(layout.width), stats);
  if constexpr (HiddenDetailSource<S>) {
    if (probing) flag_hidden_pixels(source, layout, probes, settings, grid);
  }
  stats.margin_rays += corner_rays - own_corners(tile);
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

// --fill-gaps: whether each pixel of the region grown by one on every side refines at level
// 1 by its corners' colours and signatures at `eps` or by the map, into `around` (row pitch
// region width + 2; 0 beyond the frame). No hidden-detail flag: a pixel beyond the region
// lacks the probes' second ring. Made from the ring of corners and the frame's map, so a
// pixel decides the same whichever tile it borders.
inline void refined_around(const CornerLayout& layout, const CornerGrid& grid, const GeoMap& geo, float4 eps,
                           int frame_width, int frame_height, std::vector<uint8_t>& around) {
  assert(layout.ring >= 1);
  const TileRect r = layout.region;
  const size_t pitch = size_t(r.width()) + 2;
  around.assign(pitch * (size_t(r.height()) + 2), 0);
  const int cw = layout.width;
  for (int y = std::max(r.y0 - 1, 0); y <= std::min(r.y1, frame_height - 1); ++y)
    for (int x = std::max(r.x0 - 1, 0); x <= std::min(r.x1, frame_width - 1); ++x) {
      const int ci = layout.index(x, y);
      around[size_t(y - r.y0 + 1) * pitch + size_t(x - r.x0 + 1)] =
          decide_level1(pixel_corners(grid.display.data() + ci, cw), pixel_corners(grid.signature.data() + ci, cw),
                        eps, geo.at(x, y), false)
              .refine;
    }
}

// Levels 2-3 and the filter of a tile whose corners trace_corners (or gather_corners) has
// put into `grid`.
template <SampleSource S>
void refine_tile(S& source, const TileTarget& target, const GeoMap& geo, const AdaptiveSettings& settings,
                 const CornerGrid& grid, AaStats& stats) {
  const TileRect tile = target.rect;
  if (tile.width() <= 0 || tile.height() <= 0) return;
  assert(geo.empty() || (geo.width == target.frame_width && geo.height == target.frame_height));
  const bool mitchell = settings.filter == Filter::Mitchell;
  const CornerLayout layout = corner_layout(target, settings);
  const TileRect region = layout.region;
  const int rw = region.width(), rh = region.height();
  const int cw = layout.width;
  const float4* corner_lin = grid.linear.data();
  const float4* corner_disp = grid.display.data();
  const int32_t* corner_sig = grid.signature.data();
  const HiddenFlag* hidden = flags_hidden<S>(settings) ? grid.hidden.data() : nullptr;
  const float4* footprint = corrects_footprint<S>(settings) ? grid.footprint.data() : nullptr;
  const bool curvature = curvature_applies(settings);
  AdaptiveScratch& scratch = AdaptiveScratch::local();
  if (mitchell && scratch.refined.size() < size_t(rw) * rh) {
    scratch.lattice.resize(size_t(rw) * rh * kLatticePoints);
    scratch.refined.resize(size_t(rw) * rh);
  }
  const float4 eps_surface(settings.eps), eps_specular(settings.eps_specular);
  const ToneMap& tonemap = settings.tonemap;
  const TableSet& tables = settings.tables ? *settings.tables : paper_table_set();
  const bool gaps = gaps_apply(settings) && hidden;
  const size_t around_pitch = size_t(rw) + 2;
  if (gaps)
    refined_around(layout, grid, geo, eps_specular, target.frame_width, target.frame_height, scratch.around);
  auto refined_at = [&](int x, int y) {
    return scratch.around[size_t(y - region.y0 + 1) * around_pitch + size_t(x - region.x0 + 1)] != 0;
  };
  using Clock = std::chrono::steady_clock;
  auto seconds_since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  Clock::time_point t0 = Clock::now();

  // ---- levels 1–3 per pixel of the region ----
  alignas(16) float4 lattice[kLatticePoints];
  for (int ry = 0; ry < rh; ++ry) {
    const int y = region.y0 + ry;
    for (int rx = 0; rx < rw; ++rx) {
      const int x = region.x0 + rx;
      const bool own = x >= tile.x0 && x < tile.x1 && y >= tile.y0 && y < tile.y1;
      const int ci = layout.index(x, y);
      const float4 tl = corner_lin[ci], tr = corner_lin[ci + 1];
      const float4 bl = corner_lin[ci + cw], br = corner_lin[ci + cw + 1];
      const Rgb4 disp = pixel_corners(corner_disp + ci, cw);

      const int4 sig = pixel_corners(corner_sig + ci, cw);
      const bool g = geo.at(x, y);
      // Detail the corners may have missed sends the pixel on like a geo flag.
      const HiddenFlag peak_flag = hidden ? hidden[size_t(ry) * rw + rx] : 0;
      const bool peak = (peak_flag & kHiddenFlag) != 0;
      // The pixel's threshold for levels 1-2 (and the curvature correction's test).
      const bool specular = (peak_flag & kSpecularCorners) != 0;
      const float4 eps = specular ? eps_specular : eps_surface;
      const bool map_along_x = geo.along_x(x, y);  // the map's frame for its zones, too
      Level1 l1 = decide_level1(disp, sig, eps, g || peak, settings.refine_all, settings.geo_orient && map_along_x);
      const bool gap = gaps && specular && !l1.refine &&
                       fills_gap(refined_at(x - 1, y), refined_at(x + 1, y), refined_at(x, y - 1), refined_at(x, y + 1));
      l1.refine |= gap;
      const bool refine = l1.refine;
      float4 value;
      int rays = 1, level = 1, zones = 0;
      Orientation o = Orientation::Horizontal;
      if (!refine) {
        value = corner_mean(tl, tr, bl, br);
        const float4 texture = footprint ? footprint[size_t(ry) * rw + rx] : float4(0.0f);
        // The corners' second differences on a textured patch are mostly the texture's.
        if (texture[3] > 0.0f) value = max(value + float4(texture[0], texture[1], texture[2], 0.0f), float4(0.0f));
        else if (curvature) value = curvature_corrected(value, corner_lin + ci, corner_disp + ci, cw, eps);
      } else {
        o = l1.orientation;
        const float4 px{float(x)}, py{float(y)};
        const Level2 l2 = trace_level2(source, px, py, o, soa_from_aos(tl, tr, bl, br), disp, sig, tonemap, eps);
        // Zones the tables would interpolate across more radiance than the display shows.
        const int hdr = settings.hdr_zones ? hdr_zones(l2, tonemap.exposure) : 0;
        // Hidden detail may be anywhere between E..H and smaller than the zones' spacing of
        // the tables' edge model: every zone.
        const int split = splits_zones(g, settings.geo_policy, settings.split_unflagged) ? split_zones(l2) : 0;
        // The map's zones are in its own frame: they count where the pixel's is the same.
        const bool map_frame = (o == Orientation::Vertical) == map_along_x;
        const int map = settings.geo_zones && g && map_frame ? geo.zones(x, y) : 0;
        // Hidden detail is traced in the zones of the lattice points where it may show.
        zones = decide_zones(tables, l2.b, l2.c0, l2.c1, hdr, split, g, settings.geo_policy, settings.refine_all,
                             map, settings.split_unflagged) |
                zones_of_points(o, peak_flag);
        trace_level3(source, px, py, l2, zones, lattice);
        value = box_lattice(tl, tr, bl, br, lattice);
        rays = refined_rays(zones);
        level = zones ? 3 : 2;
        const int traced = std::popcount(unsigned(zones));
        stats.rays[1] += 4;
        stats.rays[2] += uint64_t(4 * traced);
        if (own) {
          stats.level2_pixels += 1;
          stats.level3_pixels += zones != 0;
          stats.vertical_pixels += o == Orientation::Vertical;
          stats.zones_traced += uint64_t(traced);
          stats.zones_interpolated += uint64_t(kZones - traced);
        } else {
          stats.margin_rays += uint64_t(rays - 1);
        }
      }
      if (mitchell) {
        const size_t pi = size_t(ry) * rw + rx;
        scratch.refined[pi] = refine;
        if (refine) {
          float4* lat = &scratch.lattice[pi * kLatticePoints];
          lat[0] = tl;  // physical k = 0 is the pixel's own top-left corner
          for (int p = 1; p < kLatticePoints; ++p) lat[p] = lattice[canonical_k(o, p)];
        }
      }
      if (!own) continue;
      stats.pixels += 1;
      stats.geo_pixels += g;
      stats.hidden_pixels += peak;
      stats.specular_pixels += specular;
      stats.gap_pixels += gap;
      const size_t fi = target.index(x, y);
      if (!mitchell) {
        alignas(16) float v[4];
        value.store(v);
        target.radiance[fi] = glm::vec3(v[0], v[1], v[2]);
      }
      if (target.rays) target.rays[fi] = uint8_t(std::min(rays, 255));
      if (target.level) target.level[fi] = uint8_t(level + (o == Orientation::Vertical ? 4 : 0));
    }
  }
  stats.seconds_refine += seconds_since(t0);
  if (!mitchell) return;
  t0 = Clock::now();

  // ---- Mitchell: the filter stage over the region's samples (filters.h) ----
  SampledRegion samples;
  samples.region = region;
  samples.corners = corner_lin;
  samples.corner_x0 = layout.x0;
  samples.corner_y0 = layout.y0;
  samples.corner_stride = cw;
  samples.refined = scratch.refined.data();
  samples.lattice = scratch.lattice.data();
  mitchell_filter(samples, target);
  stats.seconds_filter += seconds_since(t0);
}

// One tile, levels 1-3 and the filter, with the per-thread corner grid.
template <SampleSource S>
void render_tile_adaptive(S& source, const TileTarget& target, const GeoMap& geo, const AdaptiveSettings& settings,
                          AaStats& stats) {
  if (target.rect.width() <= 0 || target.rect.height() <= 0) return;
  CornerGrid& grid = AdaptiveScratch::local().corners;
  trace_corners(source, target, settings, grid, stats);
  refine_tile(source, target, geo, settings, grid, stats);
}

}  // namespace zz
