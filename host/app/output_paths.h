// Where a batch's outputs go: `-o`, `--stats` and `--aov` take patterns with the
// placeholders {scene} (the scene file's stem), {camera} and {frame} ({frame:04} pads
// with zeros to 4 digits). Before anything is loaded, a batch whose jobs would write
// the same file is rejected, naming the placeholder that would tell them apart.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace zz {

// The values one job substitutes into the patterns.
struct OutputKey {
  std::string scene;
  std::string camera;
  int frame = 0;
};

// Replaces the placeholders; throws zz::Error for an unknown or malformed one
// (e.g. "{scen}", "{frame:x}"), naming `option`.
std::string expand_output_pattern(const std::string& pattern, const OutputKey& key, const std::string& option = "-o");

// One output pattern of a batch: the option that gave it (for messages) and the pattern.
struct OutputPattern {
  std::string option;   // "-o", "--stats", "--aov rays"
  std::string pattern;
};

// Throws zz::Error when two jobs (or two outputs of one job) would write the same file:
// "-o out.png: jobs room and glass would both write out.png (add {scene})".
void check_distinct_outputs(const std::vector<OutputPattern>& patterns, const std::vector<OutputKey>& jobs);

}  // namespace zz
