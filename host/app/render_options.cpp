#include "app/render_options.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "app/option_checks.h"
#include "core/error.h"
#include "render/memory_budget.h"
#include "scene/camera_select.h"

namespace zz {
namespace {

// The options `cmd` registered after its first `before` join `group`.
void group_options_since(CLI::App* cmd, size_t before, const char* group) {
  const std::vector<CLI::Option*> options = cmd->get_options();
  for (size_t i = before; i < options.size(); ++i) options[i]->group(group);
}

}  // namespace

void add_adaptive_options(CLI::App* cmd, AdaptiveOptions& o) {
  const size_t before = cmd->get_options().size();
  cmd->add_option("--eps", o.eps, "Adaptive: colour threshold on display values [0,1]")
      ->capture_default_str()
      ->check(number_in(0.0, 1.0));
  cmd->add_option_function<std::string>(
         "--eps-specular",
         [&o](const std::string& text) {
           if (text == "off") {
             o.eps_specular = -1.0f;
             return;
           }
           size_t used = 0;
           float v = -1.0f;
           try {
             v = std::stof(text, &used);
           } catch (const std::exception&) {
             used = 0;
           }
           if (used != text.size() || !(v >= 0.0f && v <= 1.0f))
             throw CLI::ValidationError("--eps-specular", "expected off or a threshold in [0, 1], got '" + text + "'");
           o.eps_specular = v;
         },
         "Adaptive: colour threshold for pixels whose four corners all see a mirror's or a glass's image, or "
         "through a BLEND surface of alpha below 1/2 (the visibility map sees the mirror, not the edges in it), "
         "or off for --eps (default " +
             (o.eps_specular < 0.0f ? std::string("off") : CLI::detail::to_string(o.eps_specular)) + ")")
      ->type_name("off|E");
  std::vector<std::string> tables;
  for (std::string_view n : table_set_names()) tables.emplace_back(n);
  cmd->add_option_function<std::string>(
         "--tables", [&o](const std::string& name) { o.tables = &parse_table_set(name); },
         "Adaptive: zone table set (default " + std::string(o.tables->name) + ")")
      ->check(CLI::IsMember(tables));
  add_choice(cmd, "--geo-policy", o.geo_policy, kGeoPolicies,
             "Adaptive: geo pixels trace per tables (paper), also the zones between samples that saw "
             "different things (split), or every zone (all)");
  add_choice(cmd, "--filter", o.filter, kFilters, "Adaptive: reconstruction filter");
  cmd->add_option_function<std::string>(
         "--signature", [&o](const std::string& text) { o.signature = parse_signature(text); },
         "Adaptive: samples also differ where they saw different things: none, all, or a comma list of "
         "object (primary hit's material), lights (shadowed lights), secondary (first reflection/refraction "
         "hits) (default " + signature_name(o.signature) + ")")
      ->type_name("PARTS")
      ->check([](const std::string& text) {
        try {
          parse_signature(text);
          return std::string();
        } catch (const Error& e) {
          return std::string(e.what());
        }
      });
  add_choice(cmd, "--highlights", o.highlights, kOnOff,
             "Adaptive: refine pixels whose corners may have missed a highlight peaking between them");
  add_choice(cmd, "--textures", o.textures, kOnOff,
             "Adaptive: refine pixels whose texture, averaged over the pixel, differs from what the corners "
             "sampled (emissive and base-colour detail between them)");
  add_choice(cmd, "--footprint", o.footprint, kOnOff,
             "Adaptive: unrefined pixels on one textured surface, or seeing one in a mirror or through glass, take "
             "the texture's mean over the pixel (2x2 points between the corners' texture coordinates, else the "
             "25-point lattice's, each lit at its normal-mapped normal), not the corners' mean; box filter only");
  add_choice(cmd, "--curvature", o.curvature, kOnOff,
             "Adaptive: unrefined pixels corrected for the shading's curvature (reads a ring of corners around "
             "each tile)");
  add_choice(cmd, "--hdr-zones", o.hdr_zones, kOnOff,
             "Adaptive: refined pixels also trace the zones the tables would interpolate between samples whose "
             "radiance differs by more than the display can show (a corner on a light's reflection)");
  add_choice(cmd, "--geo-orient", o.geo_orient, kOnOff,
             "Adaptive: a pixel the visibility map flags, whose corners leave the orientation open (a corner cut "
             "off), is oriented along the edge the map saw (its zones run along a sliver)");
  add_choice(cmd, "--geo-zones", o.geo_zones, kOnOff,
             "Adaptive: a pixel the visibility map flags also traces the zones in which the map's samples saw its "
             "edge, and where no level-2 comparison fired, only those instead of all five");
  add_choice(cmd, "--split-unflagged", o.split_unflagged, kOnOff,
             "Adaptive: a refined pixel the visibility map does not flag also traces the zones the tables would "
             "interpolate between samples that saw different things (what --geo-policy split does for flagged ones)");
  add_choice(cmd, "--fill-gaps", o.fill_gaps, kOnOff,
             "Adaptive: a pixel whose corners all see a mirror's or a glass's image (--eps-specular), left "
             "unrefined between two refined pixels (left and right, or above and below), is refined: the image "
             "varies faster than the corners' spacing");
  group_options_since(cmd, before, kAdaptiveGroup);
}

void apply_adaptive_options(const AdaptiveOptions& o, AdaptiveSettings& s) {
  s.eps = o.eps;
  s.eps_specular = o.eps_specular;
  s.tables = o.tables;
  s.geo_policy = o.geo_policy;
  s.filter = o.filter;
  s.signature = o.signature;
  s.highlights = o.highlights;
  s.textures = o.textures;
  s.footprint = o.footprint;
  s.curvature = o.curvature;
  s.hdr_zones = o.hdr_zones;
  s.geo_orient = o.geo_orient;
  s.geo_zones = o.geo_zones;
  s.split_unflagged = o.split_unflagged;
  s.fill_gaps = o.fill_gaps;
}

void add_render_options(CLI::App* cmd, RenderOptions& o) {
  cmd->add_option("--width", o.width, "Image width (default: the scene's)")->check(CLI::Range(1, kMaxImageSide));
  cmd->add_option("--height", o.height, "Image height (default: the scene's)")->check(CLI::Range(1, kMaxImageSide));
  add_choice(cmd, "--aa", o.aa, kAaModes, "Antialiasing");
  add_adaptive_options(cmd, o.adaptive);
  size_t before = cmd->get_options().size();
  cmd->add_option("--spp", o.spp, "Samples per pixel for --aa uniform (4, 9, 16, 25, ...)")->capture_default_str()->check(CLI::Range(1, 4096));
  add_choice(cmd, "--pattern", o.pattern, kUniformPatterns, "Uniform pattern");
  group_options_since(cmd, before, kUniformGroup);
  add_choice(cmd, "--edges", o.edges, kEdgeModes, "Visibility map of geometric edges");
  before = cmd->get_options().size();
  cmd->add_option("--edge-ss", o.edge_ss, "Visibility map supersampling per axis (4 normal, 6 high quality)")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  cmd->add_option("--edge-angle", o.edge_angle, "Visibility map: normal angle threshold, degrees")
      ->capture_default_str()
      ->check(number_in(0.0, 180.0));
  cmd->add_option("--edge-depth", o.edge_depth, "Visibility map: relative distance threshold")
      ->capture_default_str()
      ->check(number_in(1e-6, 100.0));
  add_choice(cmd, "--edge-material", o.edge_material, kOnOff,
             "Visibility map: samples on different materials are an edge too (material boundaries on flat "
             "surfaces)");
  cmd->add_option("--vk-device", o.vk_device, "Vulkan device index (default: first GPU, else lavapipe)")
      ->check(CLI::Range(0, 1 << 16));
  cmd->add_flag("--vk-validate", o.vk_validate, "Vulkan validation layers; exit non-zero if they report anything");
  cmd->add_flag("--edges-serial", o.edges_serial,
                "Make the visibility map before level-1 tracing, not alongside it (same image; splits the times)");
  group_options_since(cmd, before, kMapGroup);
  cmd->add_option("--threads", o.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  add_assets_option(cmd, o.assets);
  cmd->add_flag("--allow-missing-textures", o.allow_missing_textures,
                "Render a material whose texture image is missing or unreadable without that texture, with a "
                "warning (default: an error naming the image)");
  cmd->add_option("--exposure", o.exposure, "Tone-mapping exposure (default: the scene's)")->check(number_in(kMinExposure, kMaxExposure));
  cmd->add_option("--max-depth", o.max_depth, "Reflection/refraction bounces (default: the scene's)")
      ->check(CLI::Range(kMinTraceDepth, kMaxTraceDepth));
  CLI::Option* frame = cmd->add_option("--frame", o.frame, "Animation frame N: scene time N / fps (default: the "
                                                           "first frame of the scene's range)")
                           ->check(CLI::Range(0, kMaxFrame));
  CLI::Option* time = cmd->add_option("--time", o.time, "Animation time in seconds")->check(number_in(0.0, 1e7));
  frame->excludes(time);
  cmd->add_option("--fps", o.fps, "Frames per second for --frame, and the frame a --time names (default: the rig's \"fps\", else 24)")
      ->check(number_in(kMinFps, kMaxFps));
}

LoadOptions load_options(const RenderOptions& o, bool quiet) {
  LoadOptions load;
  load.assets_dir = o.assets;
  load.allow_missing_textures = o.allow_missing_textures;
  load.quiet = quiet;
  load.frame = o.frame;
  load.time = o.time;
  load.fps = o.fps;
  return load;
}

void validate(const RenderOptions& o) {
  (void)environment_memory_limit();  // a malformed $ZIGZAG_MEMORY_LIMIT is refused before anything loads
  if (o.aa != AaMode::Uniform) return;
  if (o.pattern == UniformPattern::Lattice) {
    if (o.spp != 25) throw Error("--pattern lattice needs --spp 25 (the 25-point lattice)");
    return;
  }
  const int n = int(std::lround(std::sqrt(double(o.spp))));
  if (o.spp < 1 || n * n != o.spp)
    throw Error("--spp must be a perfect square (4, 9, 16, 25, ...) for --pattern " +
                std::string(name_of(kUniformPatterns, o.pattern)));
}

RenderSettings make_render_settings(const RenderOptions& o, const Scene& scene, const Camera& camera) {
  validate(o);
  RenderSettings s;
  const FrameSize size = frame_size(scene, camera, o.width, o.height);
  s.width = size.width;
  s.height = size.height;
  if (s.width < 1 || s.height < 1 || s.width > kMaxImageSide || s.height > kMaxImageSide)
    throw Error("resolution " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                " is out of range (1.." + std::to_string(kMaxImageSide) + " per side)");
  s.threads = o.threads;
  s.tonemap.exposure = o.exposure > 0.0f ? o.exposure : scene.exposure;
  s.aa = o.aa;
  if (o.aa == AaMode::Adaptive) {
    apply_adaptive_options(o.adaptive, s.adaptive);
    s.adaptive.map_crease = map_crease(o);
  } else if (o.aa == AaMode::Uniform) {
    s.uniform = {o.pattern, o.pattern == UniformPattern::Lattice ? 25 : o.spp};
  }
  return s;
}

VisibilitySettings make_visibility_settings(const RenderOptions& o) {
  VisibilitySettings vs;
  vs.supersample = o.edge_ss;
  vs.normal_angle_deg = o.edge_angle;
  vs.depth_rel = o.edge_depth;
  vs.material_edges = o.edge_material;
  return vs;
}

float map_crease(const RenderOptions& o) {
  return wants_visibility_map(o) ? 2.0f * std::sin(0.5f * o.edge_angle * std::numbers::pi_v<float> / 180.0f) : 0.0f;
}

void warn_outside_animation(const Scene& scene, bool quiet) {
  if (quiet || !scene.animated) return;
  const bool outside_range = scene.frame >= 0 && (scene.frame < scene.first_frame || scene.frame > scene.last_frame);
  if (outside_range)
    std::fprintf(stderr, "zigzag: warning: frame %d is outside the scene's frames %d..%d\n", scene.frame,
                 scene.first_frame, scene.last_frame);
  // A frame range ends at the first frame at or after the last keyframe, so only a frame
  // more than one frame past it is outside the animation.
  const double end = double(scene.animation_end) * (1.0 + 1e-6) + 1e-6 + (scene.frame >= 0 ? 1.0 / scene.fps : 0.0);
  if (!outside_range && scene.time > end)
    std::fprintf(stderr, "zigzag: warning: %s %.4g s is past the animation's end (%.4g s): its last pose is held%s\n",
                 scene.frame >= 0 ? ("frame " + std::to_string(scene.frame) + "'s time").c_str() : "--time", scene.time,
                 double(scene.animation_end), scene.frame >= 0 ? " (check --fps)" : "");
}

bool wants_visibility_map(const RenderOptions& o) { return o.edges == EdgeMode::Vulkan && o.aa == AaMode::Adaptive; }

}  // namespace zz
