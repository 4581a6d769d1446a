// Uniform supersampling (aa/uniform.h): the baselines' weights, sample counts and cancel.
#include "aa/uniform.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "core/film.h"
#include "test_sources.h"

namespace zz {
namespace {

// A constant colour that raises `cancel` once it has traced `after` points.
struct CancellingSource {
  std::atomic<bool>* cancel = nullptr;
  uint64_t after = 0;
  uint64_t traced = 0;
  Rgb4 sample4(float4, float4) {
    traced += 4;
    if (traced >= after) cancel->store(true);
    return {float4(0.5f), float4(0.5f), float4(0.5f)};
  }
};

struct Tile {
  Film film{8, 8};
  std::vector<glm::vec3> scratch = std::vector<glm::vec3>(9 * 9 + 8 * 8);
  TileTarget target() { return film.target({0, 0, 8, 8}); }
};

TEST(Uniform, EveryPatternAveragesAConstantToItselfWithItsSampleCount) {
  const struct {
    UniformSettings settings;
    uint64_t samples;  // for the 8 x 8 tile
  } cases[] = {
      {{UniformPattern::Center, 1}, 64},
      {{UniformPattern::Grid, 16}, 64 * 16},
      {{UniformPattern::Stratified, 9}, 64 * 9},
      {{UniformPattern::Lattice, 25}, 9 * 9 + 64 * 24},  // shared corners once, 24 inner points each
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(int(c.settings.pattern));
    Tile tile;
    test::ConstantSource source;
    UniformStats stats;
    EXPECT_TRUE(render_tile_uniform(source, tile.target(), c.settings, tile.scratch.data(), stats));
    EXPECT_EQ(stats.samples, c.samples);
    for (const glm::vec3& p : tile.film.radiance) {
      EXPECT_NEAR(p.x, 0.25f, 1e-6f);
      EXPECT_NEAR(p.y, 0.5f, 1e-6f);
      EXPECT_NEAR(p.z, 0.75f, 1e-6f);
    }
    const uint8_t per_pixel = uint8_t(c.settings.spp);
    for (uint8_t r : tile.film.rays) EXPECT_EQ(r, per_pixel);
  }
}

TEST(Uniform, ACancelledTileStopsWithinARowAndLeavesItsTargetUntouched) {
  const UniformSettings patterns[] = {{UniformPattern::Center, 1},
                                      {UniformPattern::Stratified, 256},
                                      {UniformPattern::Lattice, 25}};
  for (const UniformSettings& settings : patterns) {
    SCOPED_TRACE(int(settings.pattern));
    // Set before the tile starts: nothing is traced.
    {
      Tile tile;
      std::atomic<bool> cancel{true};
      test::ConstantSource source;
      UniformStats stats;
      EXPECT_FALSE(render_tile_uniform(source, tile.target(), settings, tile.scratch.data(), stats, &cancel));
      EXPECT_EQ(stats.samples, 0u);
    }
    // Set by the first packet: the row in flight finishes (one row of points, at most the
    // corner row's 9 for the lattice) and nothing is written to the film.
    Tile tile;
    tile.film.radiance.assign(64, glm::vec3(-1.0f));
    std::atomic<bool> cancel{false};
    CancellingSource source{&cancel, 4};
    UniformStats stats;
    EXPECT_FALSE(render_tile_uniform(source, tile.target(), settings, tile.scratch.data(), stats, &cancel));
    const uint64_t row = settings.pattern == UniformPattern::Lattice ? 9 : uint64_t(8) * settings.spp;
    EXPECT_GT(source.traced, 0u);
    EXPECT_LE(source.traced, row + 4);  // + the padded last packet the stream flushes
    for (const glm::vec3& p : tile.film.radiance) EXPECT_EQ(p, glm::vec3(-1.0f));
    for (uint8_t r : tile.film.rays) EXPECT_EQ(r, 0);
  }
}

// A constant colour that records every point it traces (a padded last packet repeats one).
struct RecordingSource {
  std::set<std::pair<float, float>> points;
  Rgb4 sample4(float4 px, float4 py) {
    alignas(16) float x[4], y[4];
    px.store(x);
    py.store(y);
    for (int i = 0; i < 4; ++i) points.insert({x[i], y[i]});
    return {float4(0.5f), float4(0.5f), float4(0.5f)};
  }
};

std::set<std::pair<float, float>> traced(const UniformSettings& settings) {
  Tile tile;
  RecordingSource source;
  UniformStats stats;
  EXPECT_TRUE(render_tile_uniform(source, tile.target(), settings, tile.scratch.data(), stats));
  return source.points;
}

// none: one ray through each pixel's centre.
TEST(Uniform, CentreTracesThePixelCentre) {
  std::set<std::pair<float, float>> want;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) want.insert({x + 0.5f, y + 0.5f});
  EXPECT_EQ(traced({UniformPattern::Center, 1}), want);
}

// grid: the n x n points ((i + 1/2) / n, (j + 1/2) / n) of every pixel, all n² of them.
TEST(Uniform, GridTracesTheRegularNByNPointsOfEveryPixel) {
  std::set<std::pair<float, float>> want;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) want.insert({x + (i + 0.5f) / 3, y + (j + 0.5f) / 3});
  EXPECT_EQ(traced({UniformPattern::Grid, 9}), want);
}

// lattice: the shared corners and the 24 inner points P_k = (k/25, (7k mod 25)/25) of every pixel.
TEST(Uniform, LatticeTracesTheSharedCornersAndTheRank1LatticeOfEveryPixel) {
  std::set<std::pair<float, float>> want;
  for (int y = 0; y <= 8; ++y)
    for (int x = 0; x <= 8; ++x) want.insert({float(x), float(y)});
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int k = 1; k < kLatticePoints; ++k) want.insert({x + kLattice[k].u, y + kLattice[k].v});
  EXPECT_EQ(traced({UniformPattern::Lattice, 25}), want);
}

// stratified: one point in each of the n x n cells of a pixel, jittered in x and y independently.
TEST(Uniform, StratifiedPutsOneIndependentlyJitteredPointInEveryCell) {
  const int n = 4;
  const std::set<std::pair<float, float>> points = traced({UniformPattern::Stratified, n * n});
  ASSERT_EQ(points.size(), 64u * n * n);
  std::vector<int> per_cell(64 * n * n, 0);
  int on_the_diagonal = 0;
  for (auto [px, py] : points) {
    const int cx = int(px * n), cy = int(py * n);  // cell in the frame's 32 x 32 grid of cells
    ASSERT_TRUE(cx >= 0 && cx < 8 * n && cy >= 0 && cy < 8 * n) << px << "," << py;
    ++per_cell[size_t(cy) * 8 * n + size_t(cx)];
    on_the_diagonal += std::fabs((px * n - cx) - (py * n - cy)) < 1e-4f;  // the same jitter in x as in y
  }
  for (int c : per_cell) EXPECT_EQ(c, 1);
  EXPECT_LT(on_the_diagonal, 8);  // of 1024 points: x and y jitter are hashed apart
}

// A smooth colour that differs everywhere, so a point given to the wrong pixel, with the
// wrong weight or from the wrong corner shows.
struct SlopeSource {
  static glm::vec3 at(float x, float y) {
    return {0.1f * x + 0.01f * y * y, 0.5f + 0.3f * std::sin(0.7f * x + 1.3f * y), 0.001f * x * y + 0.02f * y};
  }
  Rgb4 sample4(float4 px, float4 py) const {
    alignas(16) float x[4], y[4], out[3][4];
    px.store(x);
    py.store(y);
    for (int i = 0; i < 4; ++i) {
      const glm::vec3 c = at(x[i], y[i]);
      out[0][i] = c.x, out[1][i] = c.y, out[2][i] = c.z;
    }
    return {float4::load(out[0]), float4::load(out[1]), float4::load(out[2])};
  }
};

// Each pattern's pixel is its points' weighted mean, at the pixel's own place in a tile that
// is not square and not at the frame's origin (review: a constant image and the set of traced
// points hold whatever pixel a point lands in, so a corner grid read with a stride of w, not
// w + 1, passed).
TEST(Uniform, EveryPixelIsTheMeanOfItsOwnPoints) {
  const TileRect rect{3, 2, 11, 7};
  auto expected = [](UniformPattern pattern, int x, int y) {
    glm::dvec3 sum(0.0);
    if (pattern == UniformPattern::Center) return glm::dvec3(SlopeSource::at(x + 0.5f, y + 0.5f));
    if (pattern == UniformPattern::Grid) {
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) sum += glm::dvec3(SlopeSource::at(x + (i + 0.5f) / 4, y + (j + 0.5f) / 4));
      return sum / 16.0;
    }
    for (int k = 1; k < kLatticePoints; ++k) sum += glm::dvec3(SlopeSource::at(x + kLattice[k].u, y + kLattice[k].v));
    const glm::dvec3 corners = glm::dvec3(SlopeSource::at(float(x), float(y))) + glm::dvec3(SlopeSource::at(float(x + 1), float(y))) +
                               glm::dvec3(SlopeSource::at(float(x), float(y + 1))) + glm::dvec3(SlopeSource::at(float(x + 1), float(y + 1)));
    return (sum + 0.25 * corners) / 25.0;
  };
  for (const UniformSettings settings : {UniformSettings{UniformPattern::Center, 1}, UniformSettings{UniformPattern::Grid, 16},
                                         UniformSettings{UniformPattern::Lattice, 25}}) {
    SCOPED_TRACE(int(settings.pattern));
    Film film(16, 12);
    std::vector<glm::vec3> scratch(size_t(rect.width() + 1) * (rect.height() + 1) + size_t(rect.width()) * rect.height());
    UniformStats stats;
    SlopeSource source;
    ASSERT_TRUE(render_tile_uniform(source, film.target(rect), settings, scratch.data(), stats));
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 16; ++x) {
        const glm::vec3 got = film.radiance[size_t(y) * 16 + x];
        const bool inside = x >= rect.x0 && x < rect.x1 && y >= rect.y0 && y < rect.y1;
        const glm::dvec3 want = inside ? expected(settings.pattern, x, y) : glm::dvec3(0.0);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 2e-6) << x << "," << y << " channel " << c;
      }
  }
}

// The rays AOV counts the points per pixel and saturates at 255; every pixel is at level 1.
TEST(Uniform, RaysSaturateAt255AndEveryPixelIsLevelOne) {
  Tile tile;
  test::ConstantSource source;
  UniformStats stats;
  EXPECT_TRUE(render_tile_uniform(source, tile.target(), {UniformPattern::Grid, 256}, tile.scratch.data(), stats));
  EXPECT_EQ(stats.samples, 64u * 256u);
  for (uint8_t r : tile.film.rays) EXPECT_EQ(r, 255);
  for (uint8_t l : tile.film.level) EXPECT_EQ(l, 1);
}

}  // namespace
}  // namespace zz
