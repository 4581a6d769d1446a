// The seam between the antialiasing code and everything that produces colours
// (DESIGN.md): a sample source returns linear radiance for 4 image-plane points at once.
// It is a template parameter, never a virtual call, so the packet loop inlines.
// Image-plane points are in pixels: pixel (x, y) covers [x, x+1] x [y, y+1], y down.
// Contract: each lane's colour depends only on that lane's point (never on the other
// lanes or on call order), so a point traced by two tiles gets the same value and the
// image is bit-identical for any tiling (ALGORITHM.md §1).
// Implementations: the renderer's SceneSource (render/scene_source.h) traces and shades
// a packet; the analytic harness evaluates a 2D image; the table tuner uses an edge.
#pragma once

#include <concepts>

#include "core/color.h"
#include "core/simd.h"

namespace zz {

template <class S>
concept SampleSource = requires(S& source, float4 px, float4 py) {
  { source.sample4(px, py) } -> std::same_as<Rgb4>;
};

}  // namespace zz
