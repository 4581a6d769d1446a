#include "app/render_options.h"

#include <cmath>

#include "core/error.h"

namespace zz {

void add_render_options(CLI::App* cmd, RenderOptions& o) {
  cmd->add_option("--width", o.width, "Image width (default: the scene's)")->check(CLI::Range(1, 16384));
  cmd->add_option("--height", o.height, "Image height (default: the scene's)")->check(CLI::Range(1, 16384));
  cmd->add_option("--aa", o.aa, "Antialiasing: adaptive | none | uniform")
      ->check(CLI::IsMember({"adaptive", "none", "uniform"}));
  cmd->add_option("--eps", o.eps, "Adaptive: colour threshold on display values [0,1]")->check(CLI::Range(0.0f, 1.0f));
  cmd->add_option("--tables", o.tables, "Adaptive: zone table set (paper, tuned, tuned-hq, all)");
  cmd->add_option("--geo-policy", o.geo_policy, "Adaptive: geo pixels trace per tables (paper) or every zone (all)");
  cmd->add_option("--filter", o.filter, "Adaptive: reconstruction filter box | mitchell");
  cmd->add_option("--spp", o.spp, "Samples per pixel for --aa uniform (4, 9, 16, 25, ...)")->check(CLI::Range(1, 4096));
  cmd->add_option("--pattern", o.pattern, "Uniform pattern: grid | stratified | lattice")
      ->check(CLI::IsMember({"grid", "stratified", "lattice"}));
  cmd->add_option("--edges", o.edges, "Visibility map of geometric edges: vulkan | off")
      ->check(CLI::IsMember({"vulkan", "off"}));
  cmd->add_option("--edge-ss", o.edge_ss, "Visibility map supersampling per axis (4 normal, 6 high quality)")
      ->check(CLI::Range(1, 16));
  cmd->add_option("--edge-angle", o.edge_angle, "Visibility map: normal angle threshold, degrees")
      ->check(CLI::Range(0.0f, 180.0f));
  cmd->add_option("--edge-depth", o.edge_depth, "Visibility map: relative distance threshold")
      ->check(CLI::Range(1e-6f, 100.0f));
  cmd->add_option("--vk-device", o.vk_device, "Vulkan device index (default: first GPU, else lavapipe)");
  cmd->add_flag("--vk-validate", o.vk_validate, "Vulkan validation layers; exit non-zero if they report anything");
  cmd->add_option("--threads", o.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  cmd->add_option("--assets", o.assets, "Directory of third-party models (default $ZIGZAG_ASSETS or ../shared/scenes)");
  cmd->add_option("--exposure", o.exposure, "Tone-mapping exposure (default: the scene's)")->check(CLI::Range(1e-6f, 1e6f));
  cmd->add_option("--max-depth", o.max_depth, "Reflection/refraction bounces (default: the scene's)")
      ->check(CLI::Range(0, 64));
}

RenderSettings make_render_settings(const RenderOptions& o, const Scene& scene) {
  RenderSettings s;
  s.width = o.width > 0 ? o.width : scene.default_width;
  s.height = o.height > 0 ? o.height : scene.default_height;
  if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384)
    throw Error("resolution " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                " is out of range (1..16384 per side)");
  s.threads = o.threads;
  s.tonemap.exposure = o.exposure > 0.0f ? o.exposure : scene.exposure;
  if (o.aa == "adaptive") {
    s.aa = AaMode::Adaptive;
    s.adaptive.eps = o.eps;
    s.adaptive.tables = &parse_table_set(o.tables);
    s.adaptive.geo_policy = parse_geo_policy(o.geo_policy);
    s.adaptive.filter = parse_filter(o.filter);
  } else if (o.aa == "none") {
    s.aa = AaMode::None;
  } else {
    s.aa = AaMode::Uniform;
    if (o.pattern == "lattice") {
      if (o.spp != 25) throw Error("--pattern lattice needs --spp 25 (the 25-point lattice)");
      s.uniform = {UniformPattern::Lattice, 25};
    } else {
      const int n = int(std::lround(std::sqrt(double(o.spp))));
      if (o.spp < 1 || n * n != o.spp)
        throw Error("--spp must be a perfect square (4, 9, 16, 25, ...) for --pattern " + o.pattern);
      s.uniform = {o.pattern == "grid" ? UniformPattern::Grid : UniformPattern::Stratified, o.spp};
    }
  }
  return s;
}

VisibilitySettings make_visibility_settings(const RenderOptions& o) {
  VisibilitySettings vs;
  vs.supersample = o.edge_ss;
  vs.normal_angle_deg = o.edge_angle;
  vs.depth_rel = o.edge_depth;
  return vs;
}

bool wants_visibility_map(const RenderOptions& o) { return o.edges == "vulkan" && o.aa == "adaptive"; }

}  // namespace zz
