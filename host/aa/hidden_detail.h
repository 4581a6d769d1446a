// Flags for detail between a pixel's corners, on the antialiasing side (ALGORITHM.md §11,
// ours). A source that can returns with each sample a probe of the surface it hit and, from
// the four probes of a pixel's corners, the radiance by which the pixel may differ from
// their mean because of something none of them saw: a highlight peaking between them
// (render/specular_peak.h), texture detail between them (render/texture_detail.h). The
// sampler flags the pixel when adding that radiance to the corners' mean would move the
// displayed colour by more than eps: the same test on display values as every other
// comparison (§2). Like the visibility map's geo flag it only sends a pixel to level 2; it
// never colours one. Sources without probes (analytic images, the tuner's edges) never flag.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>

#include "aa/signature.h"
#include "core/simd.h"
#include "core/tonemap.h"

namespace zz {

// Where sample4 puts each lane's probe: the caller's records, written in place.
template <class Probe>
struct ProbeLanes {
  Probe* lane[4];
  ProbeLanes(Probe* a, Probe* b, Probe* c, Probe* d) : lane{a, b, c, d} {}
  ProbeLanes(Probe (&probes)[4]) : lane{&probes[0], &probes[1], &probes[2], &probes[3]} {}  // NOLINT: implicit
  Probe& operator[](int i) const { return *lane[i]; }
};

// What a pixel's corners may have missed: the radiance (linear RGB in lanes 0-2) by which
// the pixel may differ from their mean, and where: bit p set for each physical lattice
// point p (aa/lattice.h) at which it may show. A detail whose place the source cannot tell
// names every point.
inline constexpr uint32_t kAllLatticePoints = (1u << 25) - 1;
struct MissedDetail {
  float4 radiance{0.0f};
  uint32_t points = 0;
  // Of `radiance`, what may as well make the pixel darker (texture detail: |box - corners|;
  // a highlight only adds). T is concave, so the same amount moves the display more down.
  float4 darker{0.0f};
};

// A pixel's hidden-detail flag: 0, or kHiddenFlag with the lattice points at which the
// missed detail may show (MissedDetail::points).
using HiddenFlag = uint32_t;
inline constexpr HiddenFlag kHiddenFlag = 1u << 31;
// Set beside it (on any pixel, flagged or not) where all four corners see a mirror's or a
// glass's image: the pixel takes AdaptiveSettings::eps_specular.
inline constexpr HiddenFlag kSpecularCorners = 1u << 30;

// sample4(px, py, sig, probes) fills 4 probes (distinct records); hidden_radiance(tl, stride, corner_mean,
// visible) answers for one pixel: its corners are tl[0], tl[1], tl[stride], tl[stride + 1]
// (TL, TR, BL, BR) in a grid with one more corner on every side (tl[-1 - stride] to
// tl[2 + 2 stride] exist), and `corner_mean` is the mean of their linear radiance in lanes
// 0-2. It may skip whatever stays below `visible` per channel. The answer is a function of
// those 16 probes alone (the level-1 field computes it block by block: corner_field.h).
template <class S>
concept HiddenDetailSource =
    SignedSampleSource<S> && requires(S& source, const S& csource, float4 px, float4 py, int4& sig,
                                      typename S::Probe* probes, ptrdiff_t stride, float4 mean,
                                      float4 visible) {
      { source.sample4(px, py, sig, ProbeLanes<typename S::Probe>(probes, probes, probes, probes)) } -> std::same_as<Rgb4>;
      { csource.hidden_radiance(probes, stride, mean, visible) } -> std::same_as<MissedDetail>;
      // Whether the pixel's four corners (as for hidden_radiance) all see a mirror's or a
      // glass's image rather than a surface of their own.
      { csource.specular_corners(probes, stride) } -> std::same_as<bool>;
    };

// A source that also says what a pixel finished at level 1 lacks because the mean of its
// corners is not the mean over the pixel of what they sampled (render/texture_detail.h's
// texture footprint): footprint_delta(tl, stride, prepared, mean) for the pixel whose
// corners are as for hidden_radiance (`mean` the mean of their radiance, `prepared` what
// footprint_corner made of each corner, TL, TR, BL, BR), linear RGB in lanes 0-2, and in
// lane 3 1 where it applies (0 elsewhere). footprint_corner is a corner's share of the
// work, asked once per corner rather than once for each of the four pixels around it.
// Unlike the flags it colours pixels: the sampler adds it to an unrefined pixel's corner
// mean, in place of the curvature correction (which would count the texture twice).
template <class S>
concept FootprintSource =
    HiddenDetailSource<S> && requires(const S& csource, const typename S::Probe* probes,
                                      const typename S::FootprintCorner* const* prepared, ptrdiff_t stride,
                                      float4 mean) {
      { csource.footprint_corner(*probes) } -> std::same_as<typename S::FootprintCorner>;
      { csource.footprint_delta(probes, stride, prepared, mean) } -> std::same_as<float4>;
    };

// Whether the pixel whose box-filtered value is `corner_mean` (linear RGB in lanes 0-2)
// hides more than it shows: asks the source what its corners (`tl` and `stride` as for
// hidden_radiance) may have missed, and flags the pixel when adding it would change a
// channel's tone-mapped value by more than eps (a distance equal to eps is no
// discontinuity): the flag, with the lattice points where it may show, or 0.
template <HiddenDetailSource S>
HiddenFlag hidden_detail_shows(const S& source, const typename S::Probe* tl, ptrdiff_t stride, float4 corner_mean,
                               const ToneMap& tonemap, float4 eps) {
  // T is concave: nothing below eps / T'(mean) can show (2 % margin for the table's chords;
  // enough for eps >= 5e-4: near the sRGB toe, a mean of 0.0033, eps 1e-4 shows 0.7 % more
  // than eps, about 7e-7 of the display range, so a skip never shows at 8 bits).
  const float4 visible = eps / (tonemap.slope4(corner_mean) * float4(1.02f));
  const MissedDetail missed = source.hidden_radiance(tl, stride, corner_mean, visible);
  const float4 hidden = missed.radiance;
  if (!(hidden > float4(0.0f)).any()) return 0;
  const float4 shown = tonemap.apply4(corner_mean);
  const float4 up = tonemap.apply4(corner_mean + hidden) - shown;
  const float4 down = shown - tonemap.apply4(max(corner_mean - missed.darker, float4(0.0f)));
  return (((up > eps) | (down > eps)).bits() & 0x7) != 0 ? kHiddenFlag | (missed.points & kAllLatticePoints) : 0;
}

}  // namespace zz
