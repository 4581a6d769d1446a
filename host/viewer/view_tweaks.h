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

  static constexpr float kEpsStep = 1.25f;  // one `[`/`]` press; eps stays in (0, 1]
  void eps_down() { eps = eps / kEpsStep > 1e-4f ? eps / kEpsStep : 1e-4f; }
  void eps_up() { eps = eps * kEpsStep < 1.0f ? eps * kEpsStep : 1.0f; }
};

void apply_tweaks(const ViewTweaks& tweaks, RenderSettings& settings);

}  // namespace zz
