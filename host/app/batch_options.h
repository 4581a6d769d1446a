// The options of `zigzag render` beyond the shared image options (render_options.h):
// scenes, outputs, stats, AOVs, camera choice.
//
// Adding a render-only option: a field here (with its default), its flag in
// add_batch_options (batch_options.cpp), a check in validate() if it combines with others.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/output_paths.h"
#include "app/render_options.h"
#include "render/aov_layers.h"

namespace zz {

// One --aov: a heatmap image (`--aov rays FILE.png`) or, without a file, the AOV's raw
// channels in the -o EXR (`--aov depth`).
struct AovRequest {
  Aov aov = Aov::Rays;
  std::string name;  // as given (for messages)
  std::string file;  // pattern; empty = layers of the -o EXR
  bool layers() const { return file.empty(); }
};

struct BatchOptions {
  std::vector<std::string> scenes;
  std::string output;  // pattern; empty = default_output_pattern()
  std::string stats;   // pattern; empty = none
  std::string camera = "0";  // an index, a name, or "all"
  std::vector<AovRequest> aovs;
  bool quiet = false;
  RenderOptions render;
  std::string region;  // "X0,Y0,X1,Y1"; empty = the whole frame

  bool all_cameras() const { return camera == "all"; }
  // The AOVs that go into the -o EXR as channels (each once).
  std::vector<Aov> layer_aovs() const;
  bool wants_primary_hits() const;
  std::string output_pattern() const;
};

void add_batch_options(CLI::App* cmd, BatchOptions& o);

// "X0,Y0,X1,Y1" -> a non-empty rect; throws zz::Error. Whether it lies inside the frame
// is checked once the frame size is known (render_region).
TileRect parse_region(const std::string& text);

// Everything that can be checked before a scene is loaded: option combinations, AOV
// names, placeholders, and that no two jobs write the same file. Throws zz::Error.
void validate(const BatchOptions& o);

// Whether the batch asks for --aov geo (an image or the EXR layer).
bool wants_geo_aov(const BatchOptions& o);

// Whether the batch makes the visibility map: adaptive with --edges vulkan, or an --aov geo.
bool wants_geo_map(const BatchOptions& o);

// Options given on the command line that this batch's mode never reads (`--filter` with
// --aa uniform, `--spp` with adaptive, `--edge-ss` without a visibility map), each with
// the reason: warnings, so that a request that does nothing is not silent.
std::vector<std::string> inapplicable_options(const CLI::App& cmd, const BatchOptions& o);

// The jobs' keys as far as they are known before loading (see batch_options.cpp).
std::vector<OutputKey> known_jobs(const BatchOptions& o);

// Every file the batch's scenes are read from (scene_files of each), listed before the
// first loads: one scene's output must not replace a file a later scene reads.
std::vector<std::string> batch_inputs(const BatchOptions& o);

// preflight_output for every output of every known job, and none of them one of `inputs`.
void preflight_outputs(const BatchOptions& o, const std::vector<std::string>& inputs);

// The output patterns of one batch, with the option each came from.
std::vector<OutputPattern> output_patterns(const BatchOptions& o);

}  // namespace zz
