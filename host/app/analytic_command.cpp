// `zigzag analytic`: the antialiasing code on a built-in analytic image, compared with
// 1 ray/px, the uniform 25-point lattice and a 5x5 grid against exact coverage (issue 4).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "aa/analytic.h"
#include "app/json_text.h"
#include "app/output_paths.h"
#include "app/render_options.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "render/image_io.h"

namespace zz {
namespace {

struct AnalyticArgs {
  std::string image = "star";
  int size = 256;
  AdaptiveOptions adaptive;  // the same defaults as `zigzag render`
  int geo_ss = 0;
  int threads = 0;
  std::string out;
  std::string json;
};

nlohmann::json to_json(const AnalyticRun& r) {
  nlohmann::json j = {{"method", r.method},
                      {"rays_per_pixel", r.rays_per_pixel},
                      {"level2_fraction", r.level2_fraction},
                      {"level3_fraction", r.level3_fraction},
                      {"rmse", r.error.rmse},
                      {"max_error", r.error.max_error},
                      {"pixels_off", r.error.pixels_off}};
  if (r.stats.pixels) {
    j["rays_by_level"] = {r.stats.per_pixel(r.stats.rays[0]), r.stats.per_pixel(r.stats.rays[1]),
                          r.stats.per_pixel(r.stats.rays[2])};
    j["zones_traced"] = r.stats.zones_traced;
    j["zones_interpolated"] = r.stats.zones_interpolated;
    j["geo_pixels"] = r.stats.geo_pixels;
    j["vertical_pixels"] = r.stats.vertical_pixels;
    j["margin_rays_per_pixel"] = r.stats.per_pixel(r.stats.margin_rays);
    j["seconds"] = {{"corners", r.stats.seconds_corners},
                    {"refine", r.stats.seconds_refine},
                    {"filter", r.stats.seconds_filter}};
  }
  return j;
}

void run(const AnalyticArgs& a) {
  as_usage_checks([&] {  // before the runs: a bad invocation costs nothing
    if (!a.out.empty()) preflight_output("--out", a.out, true);
    if (!a.json.empty()) preflight_output("--json", a.json, false);
    if (!a.out.empty() && !a.json.empty() && output_identity(a.out) == output_identity(a.json))
      throw Error(std::filesystem::path(a.out).lexically_normal() == std::filesystem::path(a.json).lexically_normal()
                      ? "--out and --json would both write " + a.out
                      : "--out " + a.out + " and --json " + a.json + " are one file or stream: their bytes would mix");
  });
  AnalyticOptions o;
  o.image = a.image;
  o.size = a.size;
  apply_adaptive_options(a.adaptive, o.settings);
  o.geo_ss = a.geo_ss;
  o.threads = a.threads;
  const AnalyticReport report = run_analytic(o);

  const char* tables = a.adaptive.tables->name;
  const char* geo_policy = name_of(kGeoPolicies, a.adaptive.geo_policy);
  const char* filter = name_of(kFilters, a.adaptive.filter);
  std::printf("analytic %s %dx%d  eps %g  tables %s  geo-policy %s  geo-ss %d  filter %s\n", a.image.c_str(), a.size,
              a.size, double(a.adaptive.eps), tables, geo_policy, a.geo_ss, filter);
  std::printf("%-10s %8s %8s %8s %10s %8s %10s\n", "method", "rays/px", "level2", "level3", "rmse", "x lattice",
              "off>0.1");
  const double lattice_rmse = report.runs[2].error.rmse;
  for (const AnalyticRun& r : report.runs)
    std::printf("%-10s %8.3f %8.3f %8.3f %10.6f %8.2f %10llu\n", r.method.c_str(), r.rays_per_pixel,
                r.level2_fraction, r.level3_fraction, r.error.rmse,
                lattice_rmse > 0 ? r.error.rmse / lattice_rmse : 0.0, (unsigned long long)r.error.pixels_off);

  OutputSet outputs;  // published together (core/atomic_file.h)
  if (!a.json.empty()) {
    nlohmann::json j = {{"image", a.image},   {"size", a.size},           {"eps", a.adaptive.eps},
                        {"tables", tables},   {"geo_policy", geo_policy}, {"geo_ss", a.geo_ss},
                        {"filter", filter},   {"signature", signature_name(a.adaptive.signature)},
                        {"runs", nlohmann::json::array()}};
    for (const AnalyticRun& r : report.runs) j["runs"].push_back(to_json(r));
    write_text_atomically(a.json, json_text(j, 2) + "\n", &outputs);
  }
  if (!a.out.empty()) {
    // Analytic values are already display values in [0, 1]: quantise without a tone map.
    const Film& fb = report.adaptive;
    std::vector<uint8_t> rgb(size_t(fb.width) * fb.height * 3);
    for (size_t i = 0; i < fb.radiance.size(); ++i)
      for (int c = 0; c < 3; ++c)
        rgb[3 * i + c] = uint8_t(std::clamp(fb.radiance[i][c], 0.0f, 1.0f) * 255.0f + 0.5f);
    write_rgb8(a.out, fb.width, fb.height, rgb, &outputs);
  }
  outputs.commit();
}

}  // namespace

void add_analytic_command(CLI::App& app) {
  auto args = std::make_shared<AnalyticArgs>();
  CLI::App* cmd = app.add_subcommand("analytic", "Run the antialiasing on a built-in analytic image");
  std::vector<std::string> image_names;
  std::string images;  // the help: star|zoneplate|...
  for (std::string_view n : analytic_image_names()) {
    images += (images.empty() ? "" : "|") + std::string(n);
    image_names.emplace_back(n);
  }
  cmd->add_option("--image", args->image, images)->capture_default_str()->check(CLI::IsMember(image_names));
  cmd->add_option("--size", args->size, "Frame size N (N x N pixels)")->capture_default_str()->check(CLI::Range(1, 8192));
  add_adaptive_options(cmd, args->adaptive);
  cmd->add_option("--geo-ss", args->geo_ss, "Geo map samples per pixel axis (0 = no geo map)")
      ->capture_default_str()
      ->check(CLI::Range(0, 16));
  cmd->add_option("--threads", args->threads, "Worker threads (0 = all)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->add_option("--out", args->out, "Write the adaptive image (PNG)");
  cmd->add_option("--json", args->json, "Write the comparison as JSON");
  cmd->callback([args] { run(*args); });
}

}  // namespace zz
