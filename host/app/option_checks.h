// Checks of option values beyond CLI11's own. Its CLI::Range lets NaN through (NaN < min
// and NaN > max are both false): `--eps nan` was accepted and flagged every pixel.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace zz {

// Accepts a number in [lo, hi]; refuses NaN, infinities outside it and text.
inline CLI::Validator number_in(double lo, double hi) {
  const std::string range = "[" + CLI::detail::to_string(lo) + " - " + CLI::detail::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "expected a number, got '" + text + "'";
        if (!(v >= lo && v <= hi)) return "value " + text + " not in range " + range;
        return std::string();
      },
      "NUMBER in " + range);
}

// Refuses an empty value (`-o ''` fell back to the default name without a word).
inline CLI::Validator non_empty(const std::string& what) {
  return CLI::Validator(
      [what](std::string& text) { return text.empty() ? what + " must not be empty" : std::string(); }, "");
}

// The --assets option of the commands that load scenes (render, view, info): the fallback is
// found from the scene file, not the working directory (scene/loader.cpp).
inline void add_assets_option(CLI::App* cmd, std::string& assets) {
  cmd->add_option("--assets", assets,
                  "Directory of third-party models (default $ZIGZAG_ASSETS, else shared/scenes beside the "
                  "checkout: <scene file's folder>/../../shared/scenes)");
}

}  // namespace zz
