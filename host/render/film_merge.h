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

struct FilmPart {
  std::string name;  // for messages (the file)
  FilmFile file;
};

// Throws zz::Error naming the offending part(s). The result has the parts' frame as
// both windows, their tone map and attributes.
FilmFile merge_films(const std::vector<FilmPart>& parts);

}  // namespace zz
