// The renderer knobs the viewer's keys change: `[`/`]` eps, F filter, E visibility map.
// apply_tweaks() folds them into RenderSettings, the one place that knows which
// settings fields exist, so new renderer fields are wired here only.
#pragma once

#include "render/renderer.h"

namespace zz {

struct ViewTweaks {
  float eps = 0.1f;       // colour-difference threshold of the adaptive sampler (ALGORITHM.md §2)
  bool mitchell = false;  // F: Mitchell-Netravali filter instead of box
  bool edges = true;      // E: use the visibility (geo) map

  static constexpr float kEpsStep = 1.25f;  // one `[`/`]` press
  void eps_down() { eps = eps / kEpsStep; }
  void eps_up() { eps = eps * kEpsStep; }
};

void apply_tweaks(const ViewTweaks& tweaks, RenderSettings& settings);

}  // namespace zz
