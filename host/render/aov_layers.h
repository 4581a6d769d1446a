// The AOVs by name, and the raw channels each adds to a multi-layer EXR
// (`zigzag render -o out.exr --aov NAME`, no file): 32-bit float, over the film's data
// window, so `--region` parts merge into the full frame bit for bit.
//   rays    rays    the rays the AA sampler traced for the pixel (the heatmap's number;
//                   integers, saturating at 255)
//   level   level   AA level reached: 1, 2 or 3 (the PNG map's orientation is not kept)
//   geo     geo     the visibility map's flag: 1 = geometric discontinuity, else 0
//   depth   depth   camera-ray hit distance, +inf on a miss      } render/primary_hits.h:
//   normal  normal.X normal.Y normal.Z  shading normal, 0 on a miss  } the ray through the
//   albedo  albedo.R albedo.G albedo.B  base colour, 0 on a miss     } pixel's centre
// rays, level and geo also have a heatmap image (`--aov NAME FILE.png`, render/aov.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/film.h"
#include "core/geo_map.h"
#include "render/primary_hits.h"

namespace zz {

enum class Aov { Rays, Level, Geo, Depth, Normal, Albedo };

inline constexpr Aov kAllAovs[] = {Aov::Rays, Aov::Level, Aov::Geo, Aov::Depth, Aov::Normal, Aov::Albedo};

// The name on the command line ("levels" is also accepted for level, its older spelling).
const char* aov_name(Aov aov);
std::optional<Aov> find_aov(std::string_view name);

// "rays, level, geo, depth, normal, albedo": for messages and --help.
std::string aov_names();

// The EXR channels the AOV adds, in order.
std::vector<std::string> aov_channel_names(Aov aov);

// rays, level and geo have a heatmap image; the others exist only as EXR channels.
bool has_heatmap(Aov aov);

// depth, normal and albedo need trace_primary_hits.
bool needs_primary_hits(Aov aov);

// The channels of `aovs` (each once, in kAllAovs order) for `film`'s data window.
// `geo` covers the same window (crop() a region's); `hits` the same window when an AOV
// needs it. Throws zz::Error when geo is asked for without a map.
std::vector<FilmChannel> aov_channels(const std::vector<Aov>& aovs, const Film& film, const GeoMap& geo,
                                      const PrimaryHits& hits);

}  // namespace zz
