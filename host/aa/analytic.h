// Built-in analytic 2D images (issue 4) as a SampleSource, with their exact coverage
// reference and object IDs, and the harness that runs the antialiasing code on them.
// "Tracing" a point = evaluating the image function. Images are defined on a 256² frame
// (pixel units, y down, centre (128, 128)); a --size N frame shows the same picture,
// except that the penumbra ramp stays 2 output pixels wide.
//   star       grey 1 where sin(18 atan2(y-128, x-128)) >= 0, else 0 (36 wedges)
//   zoneplate  0.5 + 0.5 cos(pi r² / 256)
//   gradient   (x/256, y/256, 0.5 + 0.25 sin(2 pi (x+y) / 512))
//   penumbra   a 2-px linear ramp from (0.25, 0.25, 0.35) to (0.9, 0.85, 0.7) across the
//              line from (0, 40) to (256, 216)
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "aa/adaptive_frame.h"
#include "core/geo_map.h"

namespace zz {

enum class AnalyticKind { Star, Zoneplate, Gradient, Penumbra };

struct AnalyticImage {
  AnalyticKind kind = AnalyticKind::Star;
  int size = 256;

  glm::vec3 eval(double x, double y) const;
  // Object under the point: adjacent regions of different geometry differ (0 = none).
  uint32_t object_id(double x, double y) const;
};

// Throws zz::Error for an unknown name.
AnalyticImage make_analytic_image(std::string_view name, int size);
std::vector<std::string_view> analytic_image_names();

// Each lane is one evaluation ("one ray"). Its signature (signature.h) is the object
// under the point when `signature` has kSignatureObject (images have no lights or mirrors).
struct AnalyticSource {
  const AnalyticImage* image;
  unsigned signature = kSignatureNone;

  Rgb4 sample4(float4 px, float4 py, int4& sig) const {
    alignas(16) float x[4], y[4];
    alignas(16) int32_t id[4] = {0, 0, 0, 0};
    if (signature & kSignatureObject) {
      px.store(x);
      py.store(y);
      for (int i = 0; i < 4; ++i) id[i] = int32_t(image->object_id(x[i], y[i]));
    }
    sig = int4(make_signature(uint32_t(id[0]), 0, 0), make_signature(uint32_t(id[1]), 0, 0),
               make_signature(uint32_t(id[2]), 0, 0), make_signature(uint32_t(id[3]), 0, 0));
    return sample4(px, py);
  }

  Rgb4 sample4(float4 px, float4 py) const {
    alignas(16) float x[4], y[4], r[4], g[4], b[4];
    px.store(x);
    py.store(y);
    for (int i = 0; i < 4; ++i) {
      glm::vec3 c = image->eval(x[i], y[i]);
      r[i] = c.r, g[i] = c.g, b[i] = c.b;
    }
    return {float4::load(r), float4::load(g), float4::load(b)};
  }
};
static_assert(SignedSampleSource<AnalyticSource>);

// Mean of ss x ss regular supersamples per pixel (issue 4: ss >= 32).
std::vector<glm::vec3> exact_reference(const AnalyticImage& image, int ss = 32, int threads = 0);

// Geo flags from object IDs at ss x ss samples per pixel plus the ring of samples around
// them (ALGORITHM.md §7), by the compute pass's rule: a pixel is geo where two neighbouring
// samples differ, at least one of them inside the pixel (ring corners and ring-to-ring
// pairs are not compared; flagging on any two samples of the block flagged 11.5 % more
// pixels of the star than the shipped map would).
GeoMap analytic_geo_map(const AnalyticImage& image, int ss);

struct ImageError {
  double rmse = 0;           // linear, over pixels and channels
  double max_error = 0;      // largest channel difference
  uint64_t pixels_off = 0;   // pixels with a channel off by more than 0.1
};
ImageError image_error(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference);

struct AnalyticRun {
  std::string method;  // adaptive, 1spp, lattice25, grid5x5
  double rays_per_pixel = 0;
  double level2_fraction = 0, level3_fraction = 0;
  ImageError error;
  AaStats stats;       // adaptive and lattice25 only
};

struct AnalyticOptions {
  std::string image = "star";
  int size = 256;
  AdaptiveSettings settings;
  int geo_ss = 0;        // 0: no geo map (--edges off)
  int threads = 0;
  int tile_size = kTileSize;
  int reference_ss = 32;
  const std::vector<glm::vec3>* reference = nullptr;  // reuse a precomputed exact reference
};

struct AnalyticReport {
  std::vector<AnalyticRun> runs;      // adaptive, 1spp, lattice25, grid5x5
  Film adaptive;              // the adaptive image and its AOVs
};

AnalyticReport run_analytic(const AnalyticOptions& options);

}  // namespace zz
