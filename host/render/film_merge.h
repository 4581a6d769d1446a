// `zigzag merge`: the region parts of one frame (EXRs from `zigzag render --region`)
// assembled by their data windows into the whole frame. The parts must tile the frame
// exactly (no overlap, no gap) and come from the same render (display window, exposure
// and "zigzag:" attributes equal, the same AOV channels), so the result is the
// full-frame render bit for bit, its AOV layers included.
#pragma once

#include <string>
#include <vector>

#include "render/image_io.h"

namespace zz {

// The Vulkan device that made a part's visibility map. Not compared like the other
// attributes: another device may flag a few edge pixels differently (its rasteriser's
// rounding), which moves rays, not what the render is, so parts of a farm with GPU and
// lavapipe workers still merge; `devices_of` names them for a warning.
inline constexpr const char* kDeviceAttribute = "vulkan_device";
// The fingerprint of the scene's files (scene/scene_files.h): parts rendered from another
// version of the scene (a light moved between two regions' renders) do not merge.
inline constexpr const char* kSceneFilesAttribute = "scene_files";

struct FilmPart {
  std::string name;  // for messages (the file)
  FilmFile file;
};

// Throws zz::Error naming the offending part(s) unless they tile one frame of one render.
// Reads the films' windows, channel names, exposure and attributes only, so the parts may
// be headers (read_film_header): a bad set is refused before any pixel is read.
void check_film_parts(const std::vector<FilmPart>& parts);

// The distinct devices the parts' maps were made on (kDeviceAttribute), in order; "none" for
// a part made without a map.
std::vector<std::string> devices_of(const std::vector<FilmPart>& parts);

// Whether two films agree in all check_film_parts reads (windows, channel names, exposure,
// attributes): a part read whole against its header.
bool same_film_header(const FilmFile& a, const FilmFile& b);

// The whole frame of the parts `first` belongs to, zeroed: both windows the frame, the
// part's tone map, attributes and channels.
FilmFile empty_frame(const FilmFile& first);

// Copies a part's pixels (radiance and channels) into its window of `frame`.
void paste_part(FilmFile& frame, const Film& part);

// All three at once, for parts already read whole. The result has the parts' frame as
// both windows, their tone map and attributes.
FilmFile merge_films(const std::vector<FilmPart>& parts);

}  // namespace zz
