#include "app/batch_options.h"

#include <cstdio>
#include <filesystem>

#include "core/error.h"

namespace zz {

std::string BatchOptions::output_pattern() const {
  if (!output.empty()) return output;
  return all_cameras() ? "{scene}_{camera}.png" : "{scene}.png";
}

void add_batch_options(CLI::App* cmd, BatchOptions& o) {
  cmd->add_option("scenes", o.scenes, "Scene files")->required();
  cmd->add_option("-o,--output", o.output,
                  "Output image; {scene}, {camera}, {frame} (or {frame:04}) are replaced "
                  "(.png = display, .exr = linear HDR)");
  cmd->add_option("--stats", o.stats, "Write JSON stats per job (same placeholders as -o)");
  cmd->add_option("--camera", o.camera, "Camera index, or 'all'");
  cmd->add_option("--aov", o.aovs, "Write an AOV image: --aov rays|levels|geo FILE.png (repeatable)");
  add_render_options(cmd, o.render);
  cmd->add_option("--region", o.region,
                  "Render only pixels X0,Y0,X1,Y1 (half-open): an EXR keeps the frame as display window, a PNG "
                  "is region-sized; parts merge with `zigzag merge`");
  CLI::Option* frame = cmd->add_option("--frame", o.frame, "Animation frame N: scene time N / fps (default: the "
                                                           "first frame of the scene's range)")
                           ->check(CLI::Range(0, 100000000));
  CLI::Option* time = cmd->add_option("--time", o.time, "Animation time in seconds")->check(CLI::Range(0.0, 1e7));
  frame->excludes(time);
  cmd->add_option("--fps", o.fps, "Frames per second for --frame (default: the rig's \"fps\", else 24)")
      ->check(CLI::Range(1e-3, 1000.0));
  cmd->add_flag("-q,--quiet", o.quiet, "No progress or summary on stderr");
}

TileRect parse_region(const std::string& text) {
  TileRect r;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d,%d,%d,%d%c", &r.x0, &r.y0, &r.x1, &r.y1, &tail) != 4)
    throw Error("--region " + text + ": expected X0,Y0,X1,Y1 (integer pixel bounds, half-open)");
  if (r.empty()) throw Error("--region " + text + ": the region is empty (need X0 < X1 and Y0 < Y1)");
  return r;
}

std::vector<OutputPattern> output_patterns(const BatchOptions& o) {
  std::vector<OutputPattern> p = {{"-o", o.output_pattern()}};
  if (!o.stats.empty()) p.push_back({"--stats", o.stats});
  for (const auto& [name, file] : o.aovs) p.push_back({"--aov " + name, file});
  return p;
}

void validate(const BatchOptions& o) {
  validate(o.render);
  if (!o.region.empty()) (void)parse_region(o.region);
  // The jobs as far as they are known before loading: with --camera all, every scene may
  // have several cameras, so two stand-in cameras make a pattern without {camera} collide.
  std::vector<OutputKey> jobs;
  for (const std::string& scene : o.scenes) {
    const std::string stem = std::filesystem::path(scene).stem().string();
    if (o.all_cameras()) {
      jobs.push_back({stem, "0", 0});
      jobs.push_back({stem, "1", 0});
    } else {
      jobs.push_back({stem, o.camera, 0});
    }
  }
  check_distinct_outputs(output_patterns(o), jobs);
}

}  // namespace zz
