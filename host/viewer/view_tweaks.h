// The renderer knobs the viewer's keys change: `[`/`]` eps, F filter, E visibility map.
// apply_tweaks() folds them into RenderSettings, the one place that knows which
// settings fields exist, so new renderer fields are wired here only.
#pragma once

#include "render/renderer.h"

namespace zz {

struct ViewTweaks {
  // The knobs are the adaptive sampler's: with --aa uniform or none the keys change nothing,
  // and the title does not show them.
  bool adaptive = true;
  float eps = 0.1f;       // colour-difference threshold of the adaptive sampler (ALGORITHM.md §2)
  bool mitchell = false;  // F: Mitchell-Netravali filter instead of box
  bool edges = true;      // E: use the visibility (geo) map
  // The map's crease (AdaptiveSettings::map_crease) while E has it on: the highlight flag
  // leaves wider normal steps to the map, so without one it must take them itself.
  float map_crease = 0.0f;

  // One `[`/`]` press scales eps by 1.25 within [0, 1]; below kEpsSmallest the next step
  // down is 0 (every colour difference refines) and the next step up from 0 is kEpsSmallest.
  static constexpr float kEpsStep = 1.25f, kEpsSmallest = 1e-4f;
  void eps_down() { eps = eps / kEpsStep >= kEpsSmallest ? eps / kEpsStep : 0.0f; }
  void eps_up() { eps = eps < kEpsSmallest ? kEpsSmallest : eps * kEpsStep < 1.0f ? eps * kEpsStep : 1.0f; }
};

void apply_tweaks(const ViewTweaks& tweaks, RenderSettings& settings);

}  // namespace zz
