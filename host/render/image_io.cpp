#include "render/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace zz {

namespace {

void write_pixels(const std::filesystem::path& path, int width, int height, OIIO::TypeDesc type, const void* data) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw Error("cannot write " + path.string() + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(width, height, 3, type);
  if (!out->open(path.string(), spec) || !out->write_image(type, data) || !out->close())
    throw Error("cannot write " + path.string() + ": " + out->geterror());
}

}  // namespace

bool is_hdr_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

std::vector<uint8_t> display_bytes(const Film& film, const ToneMap& tonemap) {
  std::vector<uint8_t> bytes(size_t(film.width) * film.height * 3);
  const float* src = &film.radiance.data()->x;
  const size_t n = bytes.size();
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    float4 t = tonemap.apply4(float4::loadu(src + i)) * float4(255.0f) + float4(0.5f);
    for (int k = 0; k < 4; ++k) bytes[i + k] = uint8_t(std::clamp(t[k], 0.0f, 255.0f));
  }
  for (; i < n; ++i) bytes[i] = uint8_t(std::clamp(tonemap.apply(src[i]) * 255.0f + 0.5f, 0.0f, 255.0f));
  return bytes;
}

void write_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  write_pixels(path, width, height, OIIO::TypeDesc::UINT8, rgb.data());
}

void write_film(const std::filesystem::path& path, const Film& film, const ToneMap& tonemap) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  if (is_hdr_extension(path)) {
    write_pixels(path, film.width, film.height, OIIO::TypeDesc::FLOAT, film.radiance.data());
  } else {
    write_rgb8(path, film.width, film.height, display_bytes(film, tonemap));
  }
}

std::vector<float> read_rgb_float(const std::filesystem::path& path, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw Error("cannot read " + path.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  std::vector<float> rgb(size_t(width) * height * 3);
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, rgb.data()))
    throw Error("cannot read " + path.string() + ": " + in->geterror());
  return rgb;
}

}  // namespace zz
