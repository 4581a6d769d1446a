#include "app/batch_options.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "app/option_checks.h"
#include "core/error.h"
#include "render/image_io.h"

namespace zz {

std::string BatchOptions::output_pattern() const {
  if (!output.empty()) return output;
  return all_cameras() ? "{scene}_{camera}.png" : "{scene}.png";
}

std::vector<Aov> BatchOptions::layer_aovs() const {
  std::vector<Aov> layers;
  for (const AovRequest& a : aovs)
    if (a.layers() && std::find(layers.begin(), layers.end(), a.aov) == layers.end()) layers.push_back(a.aov);
  return layers;
}

bool BatchOptions::wants_primary_hits() const {
  for (Aov a : layer_aovs())
    if (needs_primary_hits(a)) return true;
  return false;
}

namespace {

// `--aov NAME [FILE]` occurrences -> typed requests; an unknown name is an error here,
// while the command line is parsed (before anything is loaded).
std::vector<AovRequest> parse_aovs(const std::vector<std::vector<std::string>>& groups) {
  std::vector<AovRequest> out;
  for (const std::vector<std::string>& g : groups) {
    if (g.empty()) continue;
    const std::optional<Aov> aov = find_aov(g[0]);
    if (!aov) throw UsageError("--aov " + g[0] + ": unknown AOV (valid: " + aov_names() + ")");
    out.push_back({*aov, g[0], g.size() > 1 ? g[1] : std::string()});
  }
  return out;
}

}  // namespace

void add_batch_options(CLI::App* cmd, BatchOptions& o) {
  cmd->add_option("scenes", o.scenes, "Scene files")->required();
  cmd->add_option("-o,--output", o.output,
                  "Output image; {scene}, {camera}, {frame} (or {frame:04}) are replaced "
                  "(.png = display, .exr = linear HDR)")
      ->check(non_empty("the output path"));
  cmd->add_option("--stats", o.stats, "Write JSON stats per job (same placeholders as -o)")
      ->check(non_empty("the stats path"));
  cmd->add_option("--camera", o.camera, "Camera index or name, or 'all'");
  cmd->add_option_function<std::vector<std::vector<std::string>>>(
         "--aov", [&o](const std::vector<std::vector<std::string>>& groups) { o.aovs = parse_aovs(groups); },
         "An AOV (repeatable): with FILE a heatmap image (rays, level, geo); without, raw channels in the -o "
         ".exr (" + aov_names() + ")")
      ->expected(1, 2)
      ->type_name("NAME [FILE]");
  add_render_options(cmd, o.render);
  cmd->add_option("--region", o.region,
                  "Render only pixels X0,Y0,X1,Y1 (half-open): an EXR keeps the frame as display window, a PNG "
                  "is region-sized; parts merge with `zigzag merge`")
      ->check(non_empty("--region"));  // an empty value rendered the whole frame
  cmd->add_flag("-q,--quiet", o.quiet, "No progress or summary on stderr");
}

TileRect parse_region(const std::string& text) {
  // from_chars, not sscanf: "%d" is undefined past INT_MAX (4294967306 read as 10).
  const std::string malformed = "--region " + text + ": expected X0,Y0,X1,Y1 (integer pixel bounds, half-open)";
  int bounds[4] = {};
  const char* p = text.data();
  const char* const end = text.data() + text.size();
  for (int i = 0; i < 4; ++i) {
    if (i > 0 && (p == end || *p++ != ',')) throw Error(malformed);
    const auto [next, ec] = std::from_chars(p, end, bounds[i]);
    if (ec == std::errc::result_out_of_range)
      throw Error("--region " + text + ": bound " + std::string(p, next) + " is out of range");
    if (ec != std::errc()) throw Error(malformed);
    p = next;
  }
  if (p != end) throw Error(malformed);
  const TileRect r{bounds[0], bounds[1], bounds[2], bounds[3]};
  if (r.empty()) throw Error("--region " + text + ": the region is empty (need X0 < X1 and Y0 < Y1)");
  return r;
}

std::vector<OutputPattern> output_patterns(const BatchOptions& o) {
  std::vector<OutputPattern> p = {{"-o", o.output_pattern()}};
  if (!o.stats.empty()) p.push_back({"--stats", o.stats});
  for (const AovRequest& a : o.aovs)
    if (!a.layers()) p.push_back({"--aov " + a.name, a.file});
  return p;
}

std::vector<OutputKey> known_jobs(const BatchOptions& o) {
  // With --camera all, every scene may have several cameras: two stand-in cameras make a
  // pattern without {camera} collide.
  std::vector<OutputKey> jobs;
  for (const std::string& scene : o.scenes) {
    const std::string stem = std::filesystem::path(scene).stem().string();
    if (o.all_cameras()) {
      jobs.push_back({stem, "0", 0, true});
      jobs.push_back({stem, "1", 0, true});
    } else {
      jobs.push_back({stem, o.camera, 0});
    }
  }
  return jobs;
}

void validate(const BatchOptions& o) {
  validate(o.render);
  if (!o.region.empty()) (void)parse_region(o.region);
  if (wants_geo_aov(o) && o.render.edges == EdgeMode::Off) throw Error("--aov geo needs the visibility map (--edges vulkan)");
  for (const AovRequest& a : o.aovs) {
    if (a.layers() && !holds_extra_channels(o.output_pattern()))
      throw Error("--aov " + a.name + " without a file adds channels to the -o image, which must be an .exr (-o " +
                  o.output_pattern() + ")" +
                  (has_heatmap(a.aov) ? "; or give a file: --aov " + a.name + " FILE.png" : std::string()));
    if (!a.layers() && has_heatmap(a.aov) && writes_radiance(a.file))
      throw Error("--aov " + a.name + " " + a.file + ": the heatmap is a display image (8-bit colours), not "
                  "radiance; write it as .png, or give --aov " + a.name + " without a file for the raw channel in "
                  "an -o .exr");
    if (!a.layers() && !has_heatmap(a.aov))
      throw Error("--aov " + a.name + " " + a.file + ": " + a.name +
                  " has no image of its own; give it without a file to add its channels to an -o .exr (scene "
                  "files go before the options, or after --)");
  }
  check_distinct_outputs(output_patterns(o), known_jobs(o));
}

bool wants_geo_aov(const BatchOptions& o) {
  return std::any_of(o.aovs.begin(), o.aovs.end(), [](const AovRequest& a) { return a.aov == Aov::Geo; });
}

bool wants_geo_map(const BatchOptions& o) {
  return wants_visibility_map(o.render) || (wants_geo_aov(o) && o.render.edges == EdgeMode::Vulkan);
}

std::vector<std::string> inapplicable_options(const CLI::App& cmd, const BatchOptions& o) {
  const RenderOptions& r = o.render;
  const std::string mode = std::string("--aa ") + name_of(kAaModes, r.aa);
  const bool map_made = wants_geo_map(o);
  const std::string no_map = r.edges == EdgeMode::Off ? "--edges off" : mode + " (only adaptive or --aov geo make it)";
  const struct {
    const char* group;  // render_options.h
    bool applies;
    std::string why;
  } groups[] = {
      {kAdaptiveGroup, r.aa == AaMode::Adaptive, "applies to --aa adaptive only, not " + mode},
      {kUniformGroup, r.aa == AaMode::Uniform, "applies to --aa uniform only, not " + mode},
      {kMapGroup, map_made, "needs the visibility map, which is not made with " + no_map},
  };
  std::vector<std::string> warnings;
  for (const CLI::Option* opt : cmd.get_options())
    for (const auto& g : groups)
      if (!g.applies && opt->count() > 0 && opt->get_group() == g.group)
        warnings.push_back(opt->get_name(false, true) + " " + g.why + ": ignored");
  return warnings;
}

std::vector<std::string> batch_inputs(const BatchOptions& o) {
  std::vector<std::string> inputs;
  for (const std::string& scene : o.scenes)
    for (std::string& f : scene_files(scene, load_options(o.render, true))) inputs.push_back(std::move(f));
  return inputs;
}

void preflight_outputs(const BatchOptions& o, const std::vector<std::string>& inputs) {
  const std::vector<OutputPattern> patterns = output_patterns(o);
  for (const OutputKey& job : known_jobs(o))
    for (const OutputPattern& p : patterns) {
      const std::filesystem::path path = expand_output_pattern(p.pattern, job, p.option);
      preflight_output(p.option, path, p.option != "--stats");
      check_not_an_input(p.option, path, inputs, "a file of the batch's scenes,");
    }
}

}  // namespace zz
