// User settings of the adaptive sampler (ALGORITHM.md §2, §5, §8, §9).
#pragma once

#include <string_view>

#include "aa/signature.h"
#include "aa/table_set.h"
#include "core/tonemap.h"

namespace zz {

// What a pixel with the visibility map's geo flag traces (§9):
//   Paper: the zone tables; every zone only when no level-2 mask fired.
//   Split: as Paper, and the zones whose interpolation sources saw different things
//          (signatures differ: split_zones in adaptive_pixel.h). Ours, beyond §9.
//   All:   every zone.
enum class GeoPolicy { Paper, Split, All };
enum class Filter { Box, Mitchell };

struct AdaptiveSettings {
  float eps = 0.1f;  // on tone-mapped display values; rho <= eps is no discontinuity
  // Levels 1-2 of a pixel whose four corners see a mirror's or a glass's image, or
  // through a BLEND surface of alpha below 1/2 (specular_corners, aa/hidden_detail.h),
  // compare colours with this threshold instead; < 0: eps. The visibility map sees the
  // mirror, not the edges in its image, so the colour test is their only detector there.
  // Only sources with probes tell such pixels.
  float eps_specular = -1.0f;
  const TableSet* tables = &paper_table_set();
  GeoPolicy geo_policy = GeoPolicy::Paper;
  Filter filter = Filter::Box;
  ToneMap tonemap;
  // Parts of the sample signatures the sources return (signature.h, ALGORITHM.md §11);
  // kSignatureNone is the paper's colour-only predicate.
  unsigned signature = kSignatureNone;
  // Flags for detail between the corners (hidden_detail.h, §11): pixels whose corners may
  // have missed a highlight (highlights) or texture detail (textures) that shows go on to
  // level 2. Only sources with probes flag.
  bool highlights = false;
  bool textures = false;
  // Unrefined pixels take the texture's mean over the pixel instead of at its corners
  // (FootprintSource in hidden_detail.h); only sources with probes can, and only under the
  // box filter (footprint_applies).
  bool footprint = false;
  // Unrefined pixels take the box integral to second order (curvature_corrected in
  // adaptive_pixel.h) instead of the corners' mean; needs a ring of corners around the tile.
  bool curvature = false;
  // Level-2 pixels also trace every zone the tables left to interpolation between samples
  // whose radiance differs by more than the display can show (hdr_zones in adaptive_pixel.h).
  bool hdr_zones = false;
  // A geo pixel whose corners leave the orientation open takes it from the way the map says
  // its edge runs (decide_level1 in adaptive_pixel.h; the map's ZZ_GEO_ALONG_X bit).
  bool geo_orient = false;
  // A geo pixel traces the zones the map saw its edge meet (in the map's frame, when it is the
  // pixel's), and, where no level-2 mask fired, those instead of all five (decide_zones).
  bool geo_zones = false;
  // Refined pixels the map does not flag trace the zones whose interpolation sources saw
  // different things too, as GeoPolicy::Split makes geo pixels do (decide_zones).
  bool split_unflagged = false;
  // An unrefined pixel whose corners all see an image (eps_specular's pixels) between two
  // refined ones, left and right or above and below, refines (fills_gap in adaptive_pixel.h);
  // needs eps_specular >= 0 and a source with probes.
  bool fill_gaps = false;
  // The visibility map's normal angle as a distance between unit normals, 2 sin(angle / 2);
  // 0 without a map. The highlight flag leaves steps of the shading normal wider than this
  // to the map (normal_interpolation_error in render/specular_peak.h).
  float map_crease = 0.0f;
  // Every pixel traces all 25 lattice points: the uniform 25-point lattice reference,
  // run through the same level 1–3 code (orientation and sums as the adaptive path).
  bool refine_all = false;
};

// Whether the footprint correction runs: it corrects an unrefined pixel's box mean of its
// corners, and Mitchell weighs the corners as they are (the delta went unread there, its
// probes and texture reads spent for nothing).
inline bool footprint_applies(const AdaptiveSettings& s) {
  return s.footprint && s.filter == Filter::Box && !s.refine_all;
}

// Parse user-facing names; throw zz::Error listing the valid names.
GeoPolicy parse_geo_policy(std::string_view name);
Filter parse_filter(std::string_view name);
const TableSet& parse_table_set(std::string_view name);
const char* to_string(GeoPolicy p);
const char* to_string(Filter f);

}  // namespace zz
