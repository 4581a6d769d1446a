#include "aa/analytic.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/worker_arena.h"

namespace zz {
namespace {

constexpr double kPi = std::numbers::pi;

struct NamedKind {
  std::string_view name;
  AnalyticKind kind;
};
constexpr NamedKind kKinds[] = {{"star", AnalyticKind::Star},
                                {"zoneplate", AnalyticKind::Zoneplate},
                                {"gradient", AnalyticKind::Gradient},
                                {"penumbra", AnalyticKind::Penumbra}};

// Signed distance (in the 256 frame) from the penumbra's line (0,40)-(256,216).
double penumbra_distance(double x, double y) {
  const double dx = 256.0, dy = 176.0, len = std::sqrt(dx * dx + dy * dy);
  return (dx * (y - 40.0) - dy * x) / len;
}

bool star_white(double x, double y) { return std::sin(18.0 * std::atan2(y - 128.0, x - 128.0)) >= 0.0; }

template <class F>
void parallel_rows(int rows, int threads, F&& f) {
  WorkerArena arena(threads);
  arena.execute([&] { tbb::parallel_for(0, rows, [&](int y) { f(y); }); });
}

}  // namespace

AnalyticImage make_analytic_image(std::string_view name, int size) {
  if (size < 1) throw Error("analytic image size must be >= 1");
  for (const NamedKind& k : kKinds)
    if (k.name == name) return {k.kind, size};
  std::string names;
  for (const NamedKind& k : kKinds) names += (names.empty() ? "" : ", ") + std::string(k.name);
  throw Error("unknown analytic image '" + std::string(name) + "' (expected one of: " + names + ")");
}

std::vector<std::string_view> analytic_image_names() {
  std::vector<std::string_view> n;
  for (const NamedKind& k : kKinds) n.push_back(k.name);
  return n;
}

glm::vec3 AnalyticImage::eval(double px, double py) const {
  const double s = 256.0 / size;
  const double x = px * s, y = py * s;
  switch (kind) {
    case AnalyticKind::Star: {
      const float g = star_white(x, y) ? 1.0f : 0.0f;
      return {g, g, g};
    }
    case AnalyticKind::Zoneplate: {
      const double r2 = (x - 128.0) * (x - 128.0) + (y - 128.0) * (y - 128.0);
      const float g = float(0.5 + 0.5 * std::cos(kPi * r2 / 256.0));
      return {g, g, g};
    }
    case AnalyticKind::Gradient:
      return {float(x / 256.0), float(y / 256.0), float(0.5 + 0.25 * std::sin(2.0 * kPi * (x + y) / 512.0))};
    case AnalyticKind::Penumbra: {
      // The ramp is 2 output pixels wide, centred on the line.
      const double d = penumbra_distance(x, y) / s;
      const double t = std::clamp((d + 1.0) / 2.0, 0.0, 1.0);
      const glm::dvec3 lo(0.25, 0.25, 0.35), hi(0.9, 0.85, 0.7);
      return glm::vec3(lo + t * (hi - lo));
    }
  }
  return {0, 0, 0};
}

uint32_t AnalyticImage::object_id(double px, double py) const {
  const double s = 256.0 / size;
  // Only the star has geometry edges; the others are one smooth surface (the penumbra
  // is a shadow: a shading discontinuity the visibility map must not see).
  if (kind == AnalyticKind::Star) return star_white(px * s, py * s) ? 1u : 2u;
  return 1u;
}

std::vector<glm::vec3> exact_reference(const AnalyticImage& image, int ss, int threads) {
  const int n = image.size;
  std::vector<glm::vec3> out(size_t(n) * n);
  parallel_rows(n, threads, [&](int y) {
    for (int x = 0; x < n; ++x) {
      glm::dvec3 sum(0.0);
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i)
          sum += glm::dvec3(image.eval(x + (i + 0.5) / ss, y + (j + 0.5) / ss));
      out[size_t(y) * n + x] = glm::vec3(sum / double(ss * ss));
    }
  });
  return out;
}

GeoMap analytic_geo_map(const AnalyticImage& image, int ss) {
  const int n = image.size, gn = n * ss + 2;  // sample index a in [-1, n*ss] stored at a+1
  std::vector<uint32_t> ids(size_t(gn) * gn);
  for (int b = 0; b < gn; ++b)
    for (int a = 0; a < gn; ++a)
      ids[size_t(b) * gn + a] = image.object_id((a - 1 + 0.5) / ss, (b - 1 + 0.5) / ss);
  GeoMap geo;
  geo.width = geo.height = n;
  geo.flags.assign(size_t(n) * n, 0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      // The compute pass's rule (shaders/geo_flags.comp): a pixel is geo where two
      // neighbouring samples differ, one of them inside it; the ring's corners and pairs
      // of ring samples are never compared. Which way the edge runs and which zones it
      // meets come with it (pixel sample i of row j is at (y * ss + 1 + j) * gn + x * ss + 1 + i).
      GeoPairs pairs{ss};
      auto at = [&](int i, int j) { return ids[size_t(y * ss + 1 + j) * gn + size_t(x * ss + 1 + i)]; };
      for (int j = 0; j < ss; ++j)
        for (int i = -1; i < ss; ++i)
          if (at(i, j) != at(i + 1, j)) pairs.horizontal(i, j);
      for (int j = -1; j < ss; ++j)
        for (int i = 0; i < ss; ++i)
          if (at(i, j) != at(i, j + 1)) pairs.vertical(i, j);
      geo.flags[size_t(y) * n + x] = pairs.byte();
    }
  return geo;
}

ImageError image_error(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference) {
  ImageError e;
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const glm::dvec3 d = glm::abs(glm::dvec3(image[i]) - glm::dvec3(reference[i]));
    sum += glm::dot(d, d);
    const double m = std::max({d.x, d.y, d.z});
    e.max_error = std::max(e.max_error, m);
    e.pixels_off += m > 0.1;
  }
  e.rmse = image.empty() ? 0.0 : std::sqrt(sum / (3.0 * double(image.size())));
  return e;
}

namespace {

// A uniform pattern of spp points per pixel, box-filtered (1 spp: the pixel centre).
std::vector<glm::vec3> render_uniform(const AnalyticImage& image, int per_axis, int threads) {
  const int n = image.size;
  std::vector<glm::vec3> out(size_t(n) * n);
  parallel_rows(n, threads, [&](int y) {
    for (int x = 0; x < n; ++x) {
      glm::vec3 sum(0.0f);
      for (int j = 0; j < per_axis; ++j)
        for (int i = 0; i < per_axis; ++i)
          sum += image.eval(float(x) + (i + 0.5f) / per_axis, float(y) + (j + 0.5f) / per_axis);
      out[size_t(y) * n + x] = sum / float(per_axis * per_axis);
    }
  });
  return out;
}

AnalyticRun adaptive_run(const char* method, const AnalyticImage& image, const GeoMap& geo,
                         const AdaptiveSettings& settings, const AnalyticOptions& o,
                         const std::vector<glm::vec3>& reference, Film& frame) {
  frame = Film(image.size, image.size);
  AnalyticRun r;
  r.method = method;
  r.stats = render_frame_adaptive(AnalyticSource{&image, settings.signature}, frame, geo, settings, o.tile_size, o.threads);
  r.rays_per_pixel = r.stats.rays_per_pixel();
  r.level2_fraction = r.stats.level2_fraction();
  r.level3_fraction = r.stats.level3_fraction();
  r.error = image_error(frame.radiance, reference);
  return r;
}

}  // namespace

AnalyticReport run_analytic(const AnalyticOptions& o) {
  const AnalyticImage image = make_analytic_image(o.image, o.size);
  const std::vector<glm::vec3> computed =
      o.reference ? std::vector<glm::vec3>{} : exact_reference(image, o.reference_ss, o.threads);
  const std::vector<glm::vec3>& reference = o.reference ? *o.reference : computed;
  const GeoMap geo = o.geo_ss > 0 ? analytic_geo_map(image, o.geo_ss) : GeoMap{};
  AnalyticReport report;
  report.runs.push_back(adaptive_run("adaptive", image, geo, o.settings, o, reference, report.adaptive));

  AnalyticRun one;
  one.method = "1spp";
  one.rays_per_pixel = 1.0;
  one.error = image_error(render_uniform(image, 1, o.threads), reference);
  report.runs.push_back(one);

  AdaptiveSettings full = o.settings;
  full.refine_all = true;
  Film lattice_frame;
  report.runs.push_back(adaptive_run("lattice25", image, GeoMap{}, full, o, reference, lattice_frame));

  AnalyticRun grid;
  grid.method = "grid5x5";
  grid.rays_per_pixel = 25.0;
  grid.error = image_error(render_uniform(image, 5, o.threads), reference);
  report.runs.push_back(grid);
  return report;
}

}  // namespace zz
