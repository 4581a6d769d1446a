// The population and objective behind the "tuned" table set (ALGORITHM.md §9), shared by
// tools/table_tuner and the tests. Each configuration is one pixel (a 1x1 frame) showing
// a synthetic two-colour pattern: a straight edge (any angle, offset, polarity — corner
// cuts are the offsets near a corner), a thin line of sub-pixel width, or two edges
// meeting inside the pixel. It runs through the very same level 1–3 code as the renderer
// (adaptive_pixel.h). Tables only decide which zones a level-2 pixel traces, so each
// configuration is evaluated once for all 32 zone sets; the objective of a table set is
// then a look-up: mean |pixel - fully traced 25-point lattice| + lambda * rays.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "aa/adaptive_settings.h"
#include "aa/table_set.h"

namespace zz {

struct PixelPattern {
  enum Kind : uint8_t { Edge, ThinLine, Wedge } kind = Edge;
  float nx = 1, ny = 0, c = 0.5f;      // edge: inside where nx*x + ny*y >= c
  float nx2 = 0, ny2 = 1, c2 = 0.5f;   // wedge: second half-plane (inside = both)
  float width = 0.3f;                  // thin line: |n.p - c| < width / 2
  float inside = 1, outside = 0;       // grey levels

  bool inside_at(float x, float y) const;
  float eval(float x, float y) const;
};

// Signature (signature.h) with `signatures`: the side of the pattern (1 outside, 2 inside),
// what an object id says at an edge.
struct PixelPatternSource {
  const PixelPattern* pattern;
  bool signatures = false;
  Rgb4 sample4(float4 px, float4 py) const;
  Rgb4 sample4(float4 px, float4 py, int4& sig) const;
};

// One configuration evaluated for every zone set.
struct PatternRecord {
  bool refined = false;          // reached level 2
  uint8_t b = 0, c0 = 0, c1 = 0; // masks
  uint8_t hdr = 0;               // hdr_zones, when the settings trace them
  uint8_t split = 0;             // split_zones, when the settings trace them (split_unflagged)
  std::array<float, 32> error{}; // |box(zone set) - box(all zones)|; error[0] if unrefined
};

struct Population {
  std::vector<PixelPattern> train, held_out;
};

// Deterministic (fixed seed). About n patterns in all, a quarter held out.
Population make_population(int n = 100000, uint32_t seed = 20061);

PatternRecord evaluate_pattern(const PixelPattern& p, const AdaptiveSettings& settings);
std::vector<PatternRecord> evaluate_population(const std::vector<PixelPattern>& patterns,
                                               const AdaptiveSettings& settings);

struct TableScore {
  double error = 0;  // mean |error| vs the 25-point lattice
  double rays = 0;   // mean rays per pixel
  double objective(double lambda) const { return error + lambda * rays; }
};
TableScore score_tables(const TableSet& tables, const std::vector<PatternRecord>& records);

// Coordinate descent over all 48 entries (each a 5-bit zone set), starting from `start`,
// minimising error + lambda * rays on `records`. Returns the tables (name left null).
TableSet tune_tables(const TableSet& start, const std::vector<PatternRecord>& records, double lambda);

}  // namespace zz
