// Level 1 for the whole frame (aa/corner_field.h): the hidden-detail flags, computed block
// by block and, where a pixel's probe stencil straddles blocks, from the boundary bands,
// are those of the per-tile path for every pixel, whatever the frame's size against the
// block size (last blocks 1 to 4 corners wide included).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <map>

#include "test_sources.h"

namespace zz {
namespace {

// A flat grey whose probes say where they were taken; a pixel hides detail where a hash of
// its whole 4 x 4 stencil says so, so a wrong probe anywhere in it changes the image. Every
// stencil read is checked against the positions it should hold.
std::atomic<int> g_misplaced{0};

// A source without signatures whose probes hold the corner they were taken at;
// Derived::colour(px, py) is its radiance.
template <class Derived>
struct PositionProbes {
  struct Probe {
    int32_t x = 0, y = 0;
  };
  Rgb4 sample4(float4 px, float4 py) const { return static_cast<const Derived&>(*this).colour(px, py); }
  Rgb4 sample4(float4 px, float4 py, int4& sig) const {
    sig = int4(0);
    return sample4(px, py);
  }
  Rgb4 sample4(float4 px, float4 py, int4& sig, ProbeLanes<Probe> probes) const {
    for (int i = 0; i < 4; ++i) probes[i] = {int32_t(px[i]), int32_t(py[i])};
    return sample4(px, py, sig);
  }
};

struct StencilSource : PositionProbes<StencilSource> {
  Rgb4 colour(float4, float4) const { return {float4(0.2f), float4(0.2f), float4(0.2f)}; }
  bool specular_corners(const Probe*, ptrdiff_t) const { return false; }
  MissedDetail hidden_radiance(const Probe* tl, ptrdiff_t stride, float4, float4) const {
    uint32_t h = 2166136261u;
    for (int j = -1; j <= 2; ++j)
      for (int i = -1; i <= 2; ++i) {
        const Probe& p = tl[j * stride + i];
        if (p.x != tl->x + i || p.y != tl->y + j) g_misplaced.fetch_add(1, std::memory_order_relaxed);
        h = (h ^ uint32_t(p.x * 31 + p.y * 977)) * 16777619u;
      }
    return {(h >> 7) % 3 == 0 ? float4(100.0f, 100.0f, 100.0f, 0.0f) : float4(0.0f), kAllLatticePoints};
  }
};
static_assert(HiddenDetailSource<StencilSource>);

// Texture detail the corners miss may make the pixel darker as well as brighter, and the
// tone map's concavity moves the display more for the same radiance down: detail 0.01
// below a mean of 0.02 moves it past eps where 0.01 above does not, so it flags.
struct TextureDetailSource : PositionProbes<TextureDetailSource> {
  bool two_sided = false;
  Rgb4 colour(float4, float4) const { return {float4(0.02f), float4(0.02f), float4(0.02f)}; }
  bool specular_corners(const Probe*, ptrdiff_t) const { return false; }
  MissedDetail hidden_radiance(const Probe*, ptrdiff_t, float4, float4) const {
    const float4 h(0.01f, 0.01f, 0.01f, 0.0f);
    return {h, kAllLatticePoints, two_sided ? h : float4(0.0f)};
  }
};
static_assert(HiddenDetailSource<TextureDetailSource>);

TEST(HiddenDetail, DetailThatMayDarkenIsJudgedDownwardToo) {
  const ToneMap tonemap;
  const float4 mean(0.02f, 0.02f, 0.02f, 0.0f), eps(0.05f);
  const float up = (tonemap.apply4(mean + float4(0.01f)) - tonemap.apply4(mean))[0];
  const float down = (tonemap.apply4(mean) - tonemap.apply4(mean - float4(0.01f)))[0];
  ASSERT_LT(up, 0.05f);  // the case: only the downward move shows
  ASSERT_GT(down, 0.05f);
  TextureDetailSource source;
  TextureDetailSource::Probe probes[16];
  EXPECT_EQ(hidden_detail_shows(source, probes + 5, 4, mean, tonemap, eps), 0u);  // a highlight's, only upward
  source.two_sided = true;
  EXPECT_EQ(hidden_detail_shows(source, probes + 5, 4, mean, tonemap, eps), kHiddenFlag | kAllLatticePoints);
}

// A move of the display by exactly eps is no discontinuity (as every comparison, §2): the
// flag takes more than eps.
TEST(HiddenDetail, DetailMovingTheDisplayByExactlyEpsDoesNotFlag) {
  const ToneMap tonemap;
  const float4 mean(0.02f, 0.02f, 0.02f, 0.0f);
  const float up = (tonemap.apply4(mean + float4(0.01f, 0.01f, 0.01f, 0.0f)) - tonemap.apply4(mean))[0];
  TextureDetailSource source;  // brighter only
  TextureDetailSource::Probe probes[16];
  EXPECT_EQ(hidden_detail_shows(source, probes + 5, 4, mean, tonemap, float4(up)), 0u);
  EXPECT_EQ(hidden_detail_shows(source, probes + 5, 4, mean, tonemap, float4(std::nextafter(up, 0.0f))),
            kHiddenFlag | kAllLatticePoints);
}

// A source that records the `visible` it is asked with and finds nothing.
struct VisibleRecorder : PositionProbes<VisibleRecorder> {
  mutable float4 visible{0.0f};
  Rgb4 colour(float4, float4) const { return {float4(0.2f), float4(0.2f), float4(0.2f)}; }
  bool specular_corners(const Probe*, ptrdiff_t) const { return false; }
  MissedDetail hidden_radiance(const Probe*, ptrdiff_t, float4, float4 v) const {
    visible = v;
    return {};
  }
};
static_assert(HiddenDetailSource<VisibleRecorder>);

// What a source may skip as invisible (`visible`) could not show: added to the corners'
// mean, it moves no channel's display by more than eps, dark or bright.
TEST(HiddenDetail, WhatASourceMaySkipCouldNotShow) {
  const ToneMap tonemap;
  const float4 eps(0.02f, 0.05f, 0.1f, 0.05f);
  for (const float m : {0.001f, 0.02f, 0.2f, 1.0f, 8.0f}) {
    const float4 mean(m, 2.0f * m, 0.5f * m, 0.0f);
    VisibleRecorder source;
    VisibleRecorder::Probe probes[16];
    EXPECT_EQ(hidden_detail_shows(source, probes + 5, 4, mean, tonemap, eps), 0u);
    const float4 shown = tonemap.apply4(mean + source.visible) - tonemap.apply4(mean);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(source.visible[c], 0.0f) << m << " " << c;
      EXPECT_LE(shown[c], eps[c]) << m << " " << c;
    }
  }
}

// The same at a fine eps (1/1000 of the display) just above sRGB's linear toe, where the
// table's chords rise faster than the tangent (up to 0.8 % here): the 2 % margin on the
// slope keeps what a source may skip below eps.
TEST(HiddenDetail, WhatASourceMaySkipCouldNotShowAtAFineEpsNearTheSrgbToe) {
  const ToneMap tonemap;
  const float4 eps(0.001f);
  for (const float m : {0.00333971f, 0.00334f, 0.00336f}) {
    const float4 mean(m, m, m, 0.0f);
    VisibleRecorder source;
    VisibleRecorder::Probe probes[16];
    EXPECT_EQ(hidden_detail_shows(source, probes + 5, 4, mean, tonemap, eps), 0u);
    const float4 shown = tonemap.apply4(mean + source.visible) - tonemap.apply4(mean);
    for (int c = 0; c < 3; ++c) EXPECT_LE(shown[c], eps[c]) << m << " " << c;
  }
}

bool same(const Film& a, const Film& b) {
  return a.radiance.size() == b.radiance.size() &&
         std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec3)) == 0 &&
         a.rays == b.rays && a.level == b.level;
}

TEST(CornerField, HiddenFlagsMatchThePerTilePathAcrossBlockBoundaries) {
  const StencilSource source;
  AdaptiveSettings s;
  // Frame sizes whose corner grids (size + 3 with the ring) leave last blocks of 1 to 4
  // corners, or exactly fill them, and a frame of several blocks each way. The texture
  // flag alone, without the curvature ring, still gets the ring its stencil needs.
  const int sizes[][2] = {{62, 63}, {63, 64}, {64, 65}, {65, 62}, {61, 61}, {130, 70}, {1, 200}};
  for (int flags : {0, 1, 2})
    for (const auto& size : sizes) {
      const int w = size[0], h = size[1];
      const bool curvature = flags == 0;
      s.highlights = flags != 2;
      s.textures = flags == 2;
      s.curvature = curvature;
      SCOPED_TRACE(testing::Message() << w << "x" << h << " curvature " << curvature << " textures " << s.textures);
      g_misplaced = 0;
      AaStats per_tile, whole;
      const Film a = test::render(source, w, h, s, 16, 2, {}, &per_tile, /*corner_field=*/false);
      const Film b = test::render(source, w, h, s, 64, 2, {}, &whole, /*corner_field=*/true);
      EXPECT_EQ(g_misplaced.load(), 0);
      EXPECT_TRUE(same(a, b));
      EXPECT_EQ(per_tile.hidden_pixels, whole.hidden_pixels);
      // About a third of the pixels flagged: the flags were computed, not left empty.
      EXPECT_GT(whole.hidden_pixels, uint64_t(w) * uint64_t(h) / 5);
      EXPECT_LT(whole.hidden_pixels, uint64_t(w) * uint64_t(h) / 2);
    }
}

// A source whose footprint delta is asked for a pixel only where level 1 would not refine it
// anyway: its corners' colours step at x = 3 and the highlight flag fires for pixels whose
// TL corner is at y = 2.
struct CountingFootprintSource : PositionProbes<CountingFootprintSource> {
  mutable int asked = 0;
  Rgb4 colour(float4 px, float4) const {
    const float4 c = select(px >= float4(3.0f), float4(0.9f), float4(0.1f));
    return {c, c, c};
  }
  bool specular_corners(const Probe*, ptrdiff_t) const { return false; }
  MissedDetail hidden_radiance(const Probe* tl, ptrdiff_t, float4, float4) const {
    return {tl->y == 2 ? float4(100.0f, 100.0f, 100.0f, 0.0f) : float4(0.0f), kAllLatticePoints};
  }
  // A corner's share is its position, made once per corner: `prepared` counts per corner.
  struct FootprintCorner {
    int32_t x = -100, y = -100;
  };
  mutable std::map<std::pair<int, int>, int> prepared;
  FootprintCorner footprint_corner(const Probe& p) const {
    ++prepared[{p.x, p.y}];
    return {p.x, p.y};
  }
  float4 footprint_delta(const Probe* tl, ptrdiff_t, const FootprintCorner* const corners[4], float4) const {
    ++asked;
    for (int k = 0; k < 4; ++k)
      if (corners[k]->x != tl->x + (k & 1) || corners[k]->y != tl->y + (k >> 1)) ++misplaced;
    return float4(0.01f, 0.02f, 0.03f, 1.0f);
  }
  mutable int misplaced = 0;
};
static_assert(FootprintSource<CountingFootprintSource>);

TEST(CornerField, FootprintIsComputedOnlyForPixelsLevelOneLeavesUnrefined) {
  // 8 x 6 pixels with a ring of corners: corner (i, j) of the grid is frame corner (i - 1, j - 1).
  constexpr int kW = 8, kH = 6, kCw = kW + 3, kCh = kH + 3;
  CountingFootprintSource source;
  AdaptiveSettings settings;
  settings.eps = 0.05f;
  settings.highlights = true;
  settings.footprint = true;
  using Probe = CountingFootprintSource::Probe;
  std::vector<Probe> probes(size_t(kCw) * kCh);
  std::vector<float4> linear(probes.size()), display(probes.size());
  std::vector<int32_t> signature(probes.size());
  for (int j = 0; j < kCh; ++j)
    for (int i = 0; i < kCw; ++i) {
      const size_t k = size_t(j) * kCw + i;
      int4 sig;
      Probe lanes[4];
      const Rgb4 c = source.sample4(float4(float(i - 1)), float4(float(j - 1)), sig, lanes);
      probes[k] = lanes[0];
      linear[k] = float4(c.r[0], c.g[0], c.b[0], 0.0f);
      display[k] = settings.tonemap.apply4(linear[k]);
      signature[k] = 0;
    }
  const size_t tl = size_t(kCw) + 1;  // frame corner (0, 0)
  std::vector<HiddenFlag> flags(size_t(kW) * kH);
  std::vector<float4> delta(size_t(kW) * kH, float4(-1.0f));
  source.asked = 0;
  flag_hidden_block(source, probes.data() + tl, kCw, CornerView{&linear[tl], &display[tl], &signature[tl], kCw}, kW,
                    kH, settings, flags.data(), delta.data(), kW);
  int unrefined = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float4 d = delta[size_t(y) * kW + x];
      const bool flagged = flags[size_t(y) * kW + x] != 0;
      EXPECT_EQ(flagged, y == 2) << x << "," << y;
      // The step between corners x = 2 and 3 refines pixel column 2; the flag refines row 2.
      if (x == 2 || y == 2) {
        EXPECT_EQ(d[3], 0.0f) << x << "," << y;
        EXPECT_EQ(d[0], 0.0f) << x << "," << y;
      } else {
        ++unrefined;
        EXPECT_EQ(d[3], 1.0f) << x << "," << y;
        EXPECT_EQ(d[2], 0.03f) << x << "," << y;
      }
    }
  EXPECT_EQ(source.asked, unrefined);
  EXPECT_EQ(unrefined, (kW - 1) * (kH - 1));
  // Each pixel got its own four corners' shares; every corner of an unrefined pixel was
  // prepared exactly once (not once per pixel around it), and no other corner was.
  EXPECT_EQ(source.misplaced, 0);
  int corners_used = 0;
  for (int y = 0; y <= kH; ++y)
    for (int x = 0; x <= kW; ++x) {
      bool used = false;
      for (int py = y - 1; py <= y; ++py)
        for (int px = x - 1; px <= x; ++px)
          used |= px >= 0 && py >= 0 && px < kW && py < kH && px != 2 && py != 2;
      const auto it = source.prepared.find({x, y});
      if (used) {
        corners_used += 1;
        ASSERT_NE(it, source.prepared.end()) << x << "," << y;
        EXPECT_EQ(it->second, 1) << x << "," << y;
      } else {
        EXPECT_EQ(it, source.prepared.end()) << x << "," << y;
      }
    }
  EXPECT_EQ(int(source.prepared.size()), corners_used);
}

// The field holds one flag word per corner and the bands (2 x 3 corners of probes along
// each inner block boundary), not a probe per corner.
TEST(CornerField, ProbesAreKeptOnlyAlongBlockBoundaries) {
  const CornerRect r{-1, -1, 1027, 1027};  // a 1024² frame with its ring: 17 blocks each way
  using Field = CornerField<StencilSource::Probe>;
  const size_t colours = r.count() * (2 * sizeof(float4) + sizeof(int32_t));
  const size_t bands = 2 * 16 * size_t(1027) * 6 * sizeof(StencilSource::Probe);
  EXPECT_EQ(Field::bytes(r, false), colours);
  EXPECT_EQ(Field::bytes(r, true), colours + r.count() * sizeof(HiddenFlag) + bands);
}

}  // namespace
}  // namespace zz
