// Writing images through OpenImageIO, by the writer it picks for the extension: OpenEXR's
// (.exr, .sxr, .mxr) and Radiance's (.hdr, .rgbe) keep linear HDR radiance (float);
// .png/.jpg/.tif etc. get the tone-mapped display image (8-bit).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/tonemap.h"
#include "core/film.h"

namespace zz {

// Whether the path's writer takes linear radiance (float): OpenEXR's and Radiance's.
bool writes_radiance(const std::filesystem::path& path);

// Whether the format holds a film's extra channels (the AOV layers): OpenEXR only.
bool holds_extra_channels(const std::filesystem::path& path);

// Whether OpenImageIO has a writer for the path's extension.
bool can_write_image_format(const std::filesystem::path& path);

// Strings stored in an EXR as "zigzag:KEY" attributes: what `zigzag merge` compares to
// refuse parts of different renders.
using FilmAttributes = std::map<std::string, std::string>;

// Throws zz::Error naming the file when it cannot be written. HDR formats get float32
// radiance; an EXR of a region keeps the frame as its display window with the region as
// its data window, plus the tone map's exposure ("zigzag:exposure", float) and
// `attributes`, so the parts of a frame merge into exactly the full render. Display
// formats (PNG, ...) hold the film's own pixels: a region's PNG is region-sized.
// film.channels go into an EXR after R, G, B as float channels of their own names;
// any other format with channels is an error (holds_extra_channels). With `set`, the file
// is staged in it (core/atomic_file.h), published with the job's other outputs.
void write_film(const std::filesystem::path& path, const Film& film, const ToneMap& tonemap,
                const FilmAttributes& attributes = {}, OutputSet* set = nullptr);

// An EXR written by write_film, read back: radiance with its windows, the exposure and
// the "zigzag:" attributes (keys without the prefix), and every channel besides R, G, B
// in film.channels (in the file's order). Throws zz::Error naming the file when it is
// unreadable, not RGB, or lacks the exposure.
struct FilmFile {
  Film film;
  ToneMap tonemap;
  FilmAttributes attributes;
};
FilmFile read_film(const std::filesystem::path& path);

// The same checks and fields without the pixels: the film's windows are set, its buffers
// empty, and its channels carry their names with no values.
FilmFile read_film_header(const std::filesystem::path& path);

// Display image as 8-bit RGB bytes (the same bytes a PNG would hold).
std::vector<uint8_t> display_bytes(const Film& film, const ToneMap& tonemap);

// Writes an 8-bit RGB image of width*height pixels.
void write_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb,
                OutputSet* set = nullptr);

// Reads any OpenImageIO format as float RGB (linear as stored; PNGs are display values).
std::vector<float> read_rgb_float(const std::filesystem::path& path, int& width, int& height);

}  // namespace zz
