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

namespace zz {

struct BatchOptions {
  std::vector<std::string> scenes;
  std::string output;  // pattern; empty = default_output_pattern()
  std::string stats;   // pattern; empty = none
  std::string camera = "0";  // an index, or "all"
  std::vector<std::pair<std::string, std::string>> aovs;  // name, file pattern
  bool quiet = false;
  RenderOptions render;
  std::string region;         // "X0,Y0,X1,Y1"; empty = the whole frame
  std::optional<int> frame;   // --frame N (time = N / fps)
  std::optional<double> time; // --time T seconds
  double fps = 0.0;           // --fps; 0 = the rig's, else 24

  bool all_cameras() const { return camera == "all"; }
  std::string output_pattern() const;
};

void add_batch_options(CLI::App* cmd, BatchOptions& o);

// "X0,Y0,X1,Y1" -> a non-empty rect; throws zz::Error. Whether it lies inside the frame
// is checked once the frame size is known (render_region).
TileRect parse_region(const std::string& text);

// Everything that can be checked before a scene is loaded: option combinations, AOV
// names, placeholders, and that no two jobs write the same file. Throws zz::Error.
void validate(const BatchOptions& o);

// The output patterns of one batch, with the option each came from.
std::vector<OutputPattern> output_patterns(const BatchOptions& o);

}  // namespace zz
