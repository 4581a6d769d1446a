// The scene and image options `zigzag render` and `zigzag view` share: one set of flags,
// parsed once into typed values with the command line's one set of defaults, turned into
// RenderSettings and VisibilitySettings in one place, so the viewer's screenshot and a
// render with the same arguments are the same image.
//
// Adding an option: a field here (with its default), its flag in add_render_options
// (render_options.cpp), and its use in make_render_settings / make_visibility_settings.
// Render-only options (outputs, stats, cameras) live in batch_options.h.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "aa/adaptive_settings.h"
#include "aa/table_set.h"
#include "aa/uniform.h"
#include "app/option_choices.h"
#include "gpu/visibility.h"
#include "render/renderer.h"
#include "scene/animation.h"
#include "scene/loader.h"
#include "scene/scene.h"

namespace zz {

enum class EdgeMode { Vulkan, Off };

inline constexpr Choice<AaMode> kAaModes[] = {
    {"adaptive", AaMode::Adaptive}, {"none", AaMode::None}, {"uniform", AaMode::Uniform}};
inline constexpr Choice<GeoPolicy> kGeoPolicies[] = {
    {"paper", GeoPolicy::Paper}, {"split", GeoPolicy::Split}, {"all", GeoPolicy::All}};
inline constexpr Choice<Filter> kFilters[] = {{"box", Filter::Box}, {"mitchell", Filter::Mitchell}};
inline constexpr Choice<UniformPattern> kUniformPatterns[] = {
    {"grid", UniformPattern::Grid}, {"stratified", UniformPattern::Stratified}, {"lattice", UniformPattern::Lattice}};
inline constexpr Choice<EdgeMode> kEdgeModes[] = {{"vulkan", EdgeMode::Vulkan}, {"off", EdgeMode::Off}};
inline constexpr Choice<bool> kOnOff[] = {{"on", true}, {"off", false}};

// The adaptive sampler's options, shared with `zigzag analytic`. Defaults chosen by the
// accuracy/time report at 1024² (reports/REPORT.md, "Chosen defaults"): of the settings
// within 1.1x the lattice's display RMSE in room, glass and car, the fewest rays/px.
struct AdaptiveOptions {
  float eps = 0.05f;
  // Pixels whose corners all see a mirror's or a glass's image (or through a thin BLEND
  // surface): their own threshold (AdaptiveSettings::eps_specular); < 0 = eps.
  float eps_specular = 0.01f;
  const TableSet* tables = find_table_set("tuned");  // beats paper on the held-out edge population
  GeoPolicy geo_policy = GeoPolicy::Split;
  Filter filter = Filter::Box;
  // Parts of the sample signatures (aa/signature.h): all of them (object, shadowed lights,
  // what the first reflection and refraction rays hit), with the highlight flag, the
  // curvature correction and the map's material rule, is the most accurate setting within
  // 1.75 rays/px over room, glass, car at 1024², since level 1 is traced once per frame
  // (aa/corner_field.h) (docs/signatures.md, docs/beyond_corners.md).
  unsigned signature = kSignatureAll;
  // Flags for detail between the corners (aa/hidden_detail.h): highlights
  // (render/specular_peak.h) and texture detail (render/texture_detail.h; off: it costs
  // more rays than it removes error on the Khronos scenes).
  bool highlights = true;
  bool textures = false;
  // Unrefined pixels take the texture's mean over the pixel, relit at each sample's
  // normal-mapped normal (render/texture_detail.h): no rays, on because it removes error
  // (car's FLIP most of all) for shading time only; measured in README's option table.
  bool footprint = true;
  // Unrefined pixels corrected for the shading's curvature (aa/adaptive_pixel.h).
  bool curvature = true;
  // Zones interpolated across more radiance than the display shows are traced
  // (aa/adaptive_pixel.h; room's display error most of all, for +0.001 rays/px; measured
  // in README's option table).
  bool hdr_zones = true;
  // Geo pixels whose corners leave the orientation open are oriented by the map's edge
  // direction (aa/adaptive_pixel.h; glass, lamp and vase gain at the same rays/px;
  // measured in README's option table).
  bool geo_orient = true;
  // Geo pixels trace the zones the map saw their edge meet, and only those where no
  // level-2 mask fired (aa/adaptive_pixel.h decide_zones).
  bool geo_zones = true;
  // Refined pixels the map does not flag trace their split zones too (decide_zones).
  bool split_unflagged = true;
  // Image pixels between two refined ones refine (aa/adaptive_pixel.h fills_gap): on, as
  // the report's rule chose against 1024-spp references (without it glass's display RMSE
  // is 1.101x the lattice's, over the 1.1 target; with it 1.079x, mean rays/px 1.7485).
  bool fill_gaps = true;
};

struct RenderOptions {
  int width = 0, height = 0;  // 0 = the scene's
  AaMode aa = AaMode::Adaptive;
  AdaptiveOptions adaptive;
  int spp = 25;
  UniformPattern pattern = UniformPattern::Stratified;
  EdgeMode edges = EdgeMode::Vulkan;
  int edge_ss = VisibilitySettings{}.supersample;
  float edge_angle = VisibilitySettings{}.normal_angle_deg;
  float edge_depth = VisibilitySettings{}.depth_rel;
  // The visibility map's material rule (gpu/visibility.h), the report's choice; the
  // library's VisibilitySettings default stays the paper's geometric rule.
  bool edge_material = true;
  int vk_device = -1;
  bool vk_validate = false;
  bool edges_serial = false;  // the map before level 1 instead of alongside it
  int threads = 0;
  std::string assets;
  bool allow_missing_textures = false;  // LoadOptions::allow_missing_textures
  float exposure = 0.0f;  // 0 = the scene's
  int max_depth = -1;     // -1 = the scene's
  std::optional<int> frame;    // --frame N (time = N / fps)
  std::optional<double> time;  // --time T seconds
  double fps = 0.0;            // --fps; 0 = the rig's, else 24
};

// Option groups: headings of --help, and what inapplicable_options (batch_options.h) warns
// by: an option of a group that the run's mode never reads.
inline constexpr const char* kAdaptiveGroup = "Adaptive antialiasing";
inline constexpr const char* kUniformGroup = "Uniform supersampling (--aa uniform)";
inline constexpr const char* kMapGroup = "Visibility map and Vulkan";

// Registers --eps --eps-specular --tables --geo-policy --filter --signature --highlights --textures --footprint
// --curvature --hdr-zones --geo-orient --geo-zones --split-unflagged --fill-gaps, in kAdaptiveGroup.
void add_adaptive_options(CLI::App* cmd, AdaptiveOptions& o);

// The adaptive sampler's settings from its options (the tone map is the frame's, set apart).
void apply_adaptive_options(const AdaptiveOptions& o, AdaptiveSettings& s);

// Registers the shared flags on a subcommand.
void add_render_options(CLI::App* cmd, RenderOptions& o);

// How to load the scene: assets, textures, the animation time (`quiet`: no warnings).
LoadOptions load_options(const RenderOptions& o, bool quiet);

// Checks the combinations single flags cannot (e.g. --pattern lattice without --spp 25,
// a non-square --spp); throws zz::Error. Call before loading anything.
void validate(const RenderOptions& o);

// Frame settings for a loaded scene (validate() included).
// The frame size follows `camera`'s aspect ratio where neither the options nor the rig set it.
RenderSettings make_render_settings(const RenderOptions& o, const Scene& scene, const Camera& camera);

VisibilitySettings make_visibility_settings(const RenderOptions& o);

// A frame outside the scene's range, or a time past its animation, shows the pose at the
// nearest end: render and view say so, as it is usually a wrong --frame or --fps, not a wish.
void warn_outside_animation(const Scene& scene, bool quiet);

// The adaptive sampler with the visibility map on needs Vulkan; nothing else does.
bool wants_visibility_map(const RenderOptions& o);
// The map's normal angle as a distance between unit normals, 2 sin(angle / 2)
// (AdaptiveSettings::map_crease); 0 when no map is made.
float map_crease(const RenderOptions& o);

}  // namespace zz
