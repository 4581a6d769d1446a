// Writing images through OpenImageIO, chosen by extension: .exr/.hdr/.pfm keep linear
// HDR radiance (float); .png/.jpg/.tif etc. get the tone-mapped display image (8-bit).
#pragma once

#include <filesystem>
#include <vector>

#include "core/tonemap.h"
#include "core/film.h"

namespace zz {

bool is_hdr_extension(const std::filesystem::path& path);

// Whether OpenImageIO has a writer for the path's extension.
bool can_write_image_format(const std::filesystem::path& path);

// Throws zz::Error naming the file when it cannot be written. Every write goes through a
// temporary renamed over the target (core/atomic_file.h): an old file survives a failure.
void write_film(const std::filesystem::path& path, const Film& film, const ToneMap& tonemap);

// Display image as 8-bit RGB bytes (the same bytes a PNG would hold).
std::vector<uint8_t> display_bytes(const Film& film, const ToneMap& tonemap);

// Writes an 8-bit RGB image of width*height pixels.
void write_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb);

// Reads any OpenImageIO format as float RGB (linear as stored; PNGs are display values).
std::vector<float> read_rgb_float(const std::filesystem::path& path, int& width, int& height);

}  // namespace zz
