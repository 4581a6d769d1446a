// The analytic images and the harness: adaptive error against the 25-point lattice.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "aa/analytic.h"
#include "core/error.h"

namespace zz {
namespace {

// Exact references are the slow part: one per image for the whole test program.
const std::vector<glm::vec3>* reference(const char* image) {
  static std::map<std::string, std::vector<glm::vec3>> cache;
  auto it = cache.find(image);
  if (it == cache.end()) it = cache.emplace(image, exact_reference(make_analytic_image(image, 256))).first;
  return &it->second;
}

// `image` at 256² against its exact reference, eps 0.1 (AdaptiveSettings' default).
AnalyticOptions options(const char* image, const char* tables, GeoPolicy gp = GeoPolicy::Paper, int geo_ss = 0,
                        unsigned signature = kSignatureNone) {
  AnalyticOptions o;
  o.settings.signature = signature;
  o.reference = reference(image);
  o.image = image;
  o.size = 256;
  o.settings.tables = find_table_set(tables);
  o.settings.geo_policy = gp;
  o.geo_ss = geo_ss;
  return o;
}
AnalyticReport run(const char* image, const char* tables, GeoPolicy gp = GeoPolicy::Paper, int geo_ss = 0,
                   unsigned signature = kSignatureNone) {
  return run_analytic(options(image, tables, gp, geo_ss, signature));
}

double ratio(const AnalyticReport& r) { return r.runs[0].error.rmse / r.runs[2].error.rmse; }

TEST(Analytic, StarErrorWithinMeasuredBoundsOfTheLattice) {
  // Measured at 256², eps 0.1, box (see the aa report): paper 2.09x the lattice's RMSE at
  // 2.19 rays/px, tuned 1.83x at 2.16, all 1.66x at 3.38, geo ss 4 + policy all 1.00x at
  // 4.09. Bounds leave ~10 % headroom: a real regression (a wrong table row, a zone
  // traced at the wrong place) moves these by far more (ALGORITHM.md §9 independently
  // measured 2x / 1.6x / 1x for the same configurations).
  const AnalyticReport paper = run("star", "paper");
  EXPECT_LT(ratio(paper), 2.3);
  EXPECT_LT(paper.runs[0].rays_per_pixel, 2.4);
  const AnalyticReport tuned = run("star", "tuned");
  EXPECT_LT(ratio(tuned), 2.0);
  EXPECT_LT(ratio(tuned), ratio(paper));
  EXPECT_LE(tuned.runs[0].rays_per_pixel, paper.runs[0].rays_per_pixel);
  EXPECT_LT(ratio(run("star", "all")), 1.8);
  // tuned-hq: measured 1.66x at 2.86 rays/px (all: 1.66x at 3.38).
  const AnalyticReport hq = run("star", "tuned-hq");
  EXPECT_LT(ratio(hq), 1.8);
  EXPECT_LT(hq.runs[0].rays_per_pixel, 3.1);
  const AnalyticReport geo = run("star", "paper", GeoPolicy::All, 4);
  EXPECT_LT(ratio(geo), 1.05);
  EXPECT_LT(geo.runs[0].rays_per_pixel, 4.5);
  // The other methods: 1 spp aliases badly, the 5x5 grid is the best uniform pattern.
  EXPECT_GT(paper.runs[1].error.rmse, 5 * paper.runs[2].error.rmse);
  EXPECT_NEAR(paper.runs[2].rays_per_pixel, 25.0, 0.1);
  // Absolute errors of the uniform runs, measured at 256² (0.007218 lattice25 = refine_all,
  // 0.073811 1 spp, 0.004380 grid 5x5) and reproduced independently with a numpy brute
  // force (star, 32² reference, the lattice's 24 inner points + 4 corners at 1/4 each):
  // 0.0072178, 0.0738109, 0.0043799. Pinned to 10 %. The lattice's RMSE is 1.65x the 5x5
  // grid's on the star: a property of the two point sets (the numpy run gives the same
  // ratio), not of this code, so they are not expected to be within 20 % of each other.
  EXPECT_NEAR(paper.runs[2].error.rmse, 0.007218, 0.1 * 0.007218);
  EXPECT_NEAR(paper.runs[1].error.rmse, 0.073811, 0.1 * 0.073811);
  EXPECT_NEAR(paper.runs[3].error.rmse, 0.004380, 0.1 * 0.004380);
  EXPECT_NEAR(paper.runs[2].error.rmse / paper.runs[3].error.rmse, 1.648, 0.05);
  EXPECT_EQ(paper.runs[1].rays_per_pixel, 1.0);
  EXPECT_EQ(paper.runs[3].rays_per_pixel, 25.0);
}

// GeoPolicy::Split on the star with object signatures and the geo map (256², eps 0.1,
// tuned tables; measured): paper 1.287x the lattice's RMSE at 2.858 rays/px, split 1.235x
// at 2.921, all 1.000x at 4.076. The split zones are where a sector's edge runs between
// samples of the two sectors; the penumbra, one object, has none and stays as it was.
TEST(Analytic, SplitZonesCostFewRaysAndRemoveError) {
  const AnalyticReport paper = run("star", "tuned", GeoPolicy::Paper, 4, kSignatureObject);
  const AnalyticReport split = run("star", "tuned", GeoPolicy::Split, 4, kSignatureObject);
  const AnalyticReport all = run("star", "tuned", GeoPolicy::All, 4, kSignatureObject);
  EXPECT_LT(ratio(split), ratio(paper) - 0.03);
  EXPECT_GT(split.runs[0].rays_per_pixel, paper.runs[0].rays_per_pixel);
  EXPECT_LT(split.runs[0].rays_per_pixel, paper.runs[0].rays_per_pixel + 0.1);
  EXPECT_LT(split.runs[0].rays_per_pixel, all.runs[0].rays_per_pixel - 1.0);
  const AnalyticReport one_object = run("penumbra", "tuned", GeoPolicy::Split, 4, kSignatureObject);
  const AnalyticReport one_object_paper = run("penumbra", "tuned", GeoPolicy::Paper, 4, kSignatureObject);
  EXPECT_EQ(one_object.runs[0].rays_per_pixel, one_object_paper.runs[0].rays_per_pixel);
  EXPECT_EQ(one_object.runs[0].error.rmse, one_object_paper.runs[0].error.rmse);
}

// --split-unflagged on the star with object signatures (256², eps 0.1, tuned tables;
// measured): without a map no pixel is a geo pixel, and splitting the refined ones took
// 1.831x -> 1.795x the lattice's RMSE (pixels off 53 -> 47) for 2.164 -> 2.227 rays/px; with
// the map every pixel whose samples saw two sectors is a geo pixel already, and the
// penumbra, one object, has no split zones: both stay as they were.
TEST(Analytic, UnflaggedPixelsSplitTheirZonesWhereNoMapFlagsThem) {
  auto with = [](const char* image, int geo_ss, bool split_unflagged) {
    AnalyticOptions o = options(image, "tuned", GeoPolicy::Split, geo_ss, kSignatureObject);
    o.settings.split_unflagged = split_unflagged;
    return run_analytic(o);
  };
  const AnalyticReport off = with("star", 0, false), on = with("star", 0, true);
  EXPECT_LT(ratio(on), ratio(off) - 0.02);
  EXPECT_GT(on.runs[0].rays_per_pixel, off.runs[0].rays_per_pixel);
  EXPECT_LT(on.runs[0].rays_per_pixel, off.runs[0].rays_per_pixel + 0.1);
  const AnalyticReport map_off = with("star", 4, false), map_on = with("star", 4, true);
  EXPECT_EQ(map_on.runs[0].rays_per_pixel, map_off.runs[0].rays_per_pixel);
  EXPECT_EQ(map_on.runs[0].error.rmse, map_off.runs[0].error.rmse);
  const AnalyticReport one_off = with("penumbra", 0, false), one_on = with("penumbra", 0, true);
  EXPECT_EQ(one_on.runs[0].rays_per_pixel, one_off.runs[0].rays_per_pixel);
  EXPECT_EQ(one_on.runs[0].error.rmse, one_off.runs[0].error.rmse);
}

// The map's edge direction (--geo-orient) on the same star: measured 1.24x -> 1.12x the
// lattice's RMSE (pixels off 36 -> 14) at the same 2.937 rays/px. A sector edge nearly
// parallel to a pixel side that cuts a corner off now lies along the zones, not across them.
// Images without geometry edges (one object) have no geo pixels and stay as they were.
TEST(Analytic, TheMapsEdgeDirectionOrientsCornerCutsAtNoRays) {
  auto with = [](const char* image, bool orient) {
    AnalyticOptions o = options(image, "tuned", GeoPolicy::Split, 4, kSignatureObject);
    o.settings.geo_orient = orient;
    o.settings.geo_zones = false;
    return run_analytic(o);
  };
  const AnalyticReport off = with("star", false), on = with("star", true);
  EXPECT_LT(ratio(on), ratio(off) - 0.08);
  EXPECT_LT(on.runs[0].error.pixels_off, off.runs[0].error.pixels_off);
  EXPECT_NEAR(on.runs[0].rays_per_pixel, off.runs[0].rays_per_pixel, 0.01);
  EXPECT_GT(on.runs[0].stats.vertical_pixels, off.runs[0].stats.vertical_pixels);
  const AnalyticReport p_off = with("penumbra", false), p_on = with("penumbra", true);
  EXPECT_EQ(p_on.runs[0].error.rmse, p_off.runs[0].error.rmse);
}

// The map's zones (--geo-zones) on top (measured): 1.12x -> 1.00x the lattice's RMSE (pixels
// off 14 -> 4, the lattice's own 4) for fewer rays (2.937 -> 2.873 rays/px): geo pixels whose
// masks all stayed zero trace the zones where the map saw the edge, not all five.
TEST(Analytic, TheMapsZonesReachTheLatticeOnTheStarForFewerRays) {
  auto with = [](bool zones) {
    AnalyticOptions o = options("star", "tuned", GeoPolicy::Split, 4, kSignatureObject);
    o.settings.geo_orient = true;
    o.settings.geo_zones = zones;
    return run_analytic(o);
  };
  const AnalyticReport off = with(false), on = with(true);
  EXPECT_LT(ratio(on), 1.03);
  EXPECT_LT(ratio(on), ratio(off) - 0.08);
  EXPECT_LE(on.runs[0].error.pixels_off, on.runs[2].error.pixels_off + 2);
  EXPECT_LT(on.runs[0].rays_per_pixel, off.runs[0].rays_per_pixel);
}

// refine_all with the box filter is the 25-point lattice pattern of lattice.h, box-filtered
// as documented there: the 24 inner points P_k = (k/25, (7k mod 25)/25), k = 1..24, and the
// four corners at 1/4 each, over 25. Computed here point by point from the image function
// (positions rounded to float as the sampler's are) and compared pixel by pixel.
TEST(Analytic, RefineAllIsTheBoxFilteredLatticeOnTheStar) {
  const int n = 64;
  const AnalyticImage star = make_analytic_image("star", n);
  AdaptiveSettings s;
  s.refine_all = true;
  Film film(n, n);
  const AaStats stats = render_frame_adaptive(AnalyticSource{&star}, film, GeoMap{}, s, 16, 1);
  EXPECT_EQ(stats.level2_pixels, uint64_t(n) * n);
  EXPECT_EQ(stats.zones_traced, uint64_t(n) * n * 5);
  double worst = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      double sum = 0;
      for (int k = 1; k < 25; ++k)
        sum += star.eval(float(x) + float(k) / 25.0f, float(y) + float((7 * k) % 25) / 25.0f).r;
      for (int c = 0; c < 4; ++c) sum += 0.25 * star.eval(x + (c & 1), y + (c >> 1)).r;
      const double want = sum / 25.0;
      const glm::vec3 got = film.radiance[size_t(y) * n + x];
      worst = std::max(worst, std::abs(double(got.r) - want));
      ASSERT_NEAR(got.r, want, 1e-6) << x << "," << y;
      ASSERT_EQ(got.r, got.g);
      ASSERT_EQ(got.r, got.b);
    }
  std::printf("refine_all vs lattice box: max %.3g\n", worst);
}

TEST(Analytic, ZoneplateErrorWithinMeasuredBound) {
  // The zone plate reaches 0.5 cycles/px at r = 128 and aliases beyond: there the four
  // corners of a pixel can agree while its centre differs (level 1 sees nothing), which
  // the lattice's 25 points resolve. Measured: 50x the lattice's (tiny, 5e-4) RMSE, 0.026
  // absolute, 19 rays/px. Bound: 55x and 0.03 absolute.
  const AnalyticReport r = run("zoneplate", "paper");
  EXPECT_LT(ratio(r), 55.0);
  EXPECT_LT(r.runs[0].error.rmse, 0.03);
  EXPECT_LT(r.runs[0].error.rmse, r.runs[1].error.rmse);  // better than 1 spp
}

TEST(Analytic, GradientAndPenumbra) {
  const AnalyticReport g = run("gradient", "paper");
  EXPECT_EQ(g.runs[0].stats.rays[1] + g.runs[0].stats.rays[2], 0u);
  // The frame's 257 x 257 corners, each once, in 64² blocks: the last column of blocks is
  // 1 corner wide and the last row 1 tall, so their 2x2 packets repeat a lane (4 x 64 + 4 x
  // 64 + 3 padded lanes: camera rays all the same).
  EXPECT_NEAR(g.runs[0].rays_per_pixel, (257.0 * 257 + 4 * 64 + 4 * 64 + 3) / (256.0 * 256.0), 1e-9);
  EXPECT_EQ(g.runs[0].stats.rays[0], 257u * 257);
  EXPECT_LT(g.runs[0].error.rmse, 1e-5);
  const AnalyticReport p = run("penumbra", "paper");
  EXPECT_LT(p.runs[0].error.rmse, 0.002);
  EXPECT_EQ(p.runs[0].error.pixels_off, 0u);
  EXPECT_LT(p.runs[0].rays_per_pixel, 1.2);
}

TEST(Analytic, GeoMapMarksOnlyGeometryEdges) {
  const AnalyticImage star = make_analytic_image("star", 64);
  const GeoMap geo = analytic_geo_map(star, 4);
  int n = 0;
  for (uint8_t f : geo.flags) n += f != 0;
  EXPECT_GT(n, 300);
  EXPECT_LT(n, 64 * 64 / 2);
  // Star at 64²: wedges are 10° wide. Mid-wedge (5°, radius 28 px) is clear; the wedge
  // boundary along the +x axis (y = 32) is flagged.
  EXPECT_FALSE(geo.at(59, 34));
  EXPECT_TRUE(geo.at(59, 31) || geo.at(59, 32));
  // That boundary runs along x; the one along the +y axis (x = 32) does not.
  EXPECT_TRUE(geo.along_x(59, 31) || geo.along_x(59, 32));
  EXPECT_TRUE(geo.at(31, 59) || geo.at(32, 59));
  EXPECT_FALSE(geo.along_x(31, 59) || geo.along_x(32, 59));
  for (const char* name : {"gradient", "zoneplate", "penumbra"}) {
    const GeoMap g = analytic_geo_map(make_analytic_image(name, 32), 4);
    for (uint8_t f : g.flags) EXPECT_EQ(f, 0) << name;
  }
  EXPECT_THROW(make_analytic_image("nope", 8), Error);
}

}  // namespace
}  // namespace zz
