#include "render/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"

namespace zz {

namespace {

constexpr const char* kAttributePrefix = "zigzag:";

void write_pixels(const std::filesystem::path& path, const OIIO::ImageSpec& spec, const void* data) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw Error("cannot write " + path.string() + ": " + OIIO::geterror());
  if (!out->open(path.string(), spec) || !out->write_image(spec.format, data) || !out->close())
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
  write_pixels(path, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8), rgb.data());
}

void write_film(const std::filesystem::path& path, const Film& film, const ToneMap& tonemap,
                const FilmAttributes& attributes) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  if (is_hdr_extension(path)) {
    OIIO::ImageSpec spec(film.width, film.height, 3, OIIO::TypeDesc::FLOAT);
    spec.x = film.x0;
    spec.y = film.y0;
    spec.full_x = 0;
    spec.full_y = 0;
    spec.full_width = film.frame_width;
    spec.full_height = film.frame_height;
    spec.attribute(std::string(kAttributePrefix) + "exposure", tonemap.exposure);
    for (const auto& [key, value] : attributes) spec.attribute(std::string(kAttributePrefix) + key, value);
    write_pixels(path, spec, film.radiance.data());
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

FilmFile read_film(const std::filesystem::path& path) {
  const std::string file = path.string();
  auto in = OIIO::ImageInput::open(file);
  if (!in) throw Error("cannot read " + file + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) throw Error(file + ": not an RGB image");
  if (spec.depth > 1) throw Error(file + ": volume images are not films");
  const float exposure = spec.get_float_attribute(std::string(kAttributePrefix) + "exposure", -1.0f);
  if (!(exposure > 0.0f) || !std::isfinite(exposure))
    throw Error(file + ": no zigzag:exposure attribute (not an EXR written by zigzag render)");
  if (spec.width <= 0 || spec.height <= 0 || spec.full_width <= 0 || spec.full_height <= 0 || spec.full_x != 0 ||
      spec.full_y != 0 || spec.x < 0 || spec.y < 0 || int64_t(spec.x) + spec.width > spec.full_width ||
      int64_t(spec.y) + spec.height > spec.full_height)
    throw Error(file + ": data window is not inside a display window starting at 0,0");
  FilmFile f;
  f.film = Film(spec.full_width, spec.full_height, TileRect{spec.x, spec.y, spec.x + spec.width, spec.y + spec.height});
  f.tonemap.exposure = exposure;
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    const std::string name = p.name().string();
    if (name.rfind(kAttributePrefix, 0) != 0 || p.type() != OIIO::TypeDesc::STRING) continue;
    f.attributes[name.substr(std::strlen(kAttributePrefix))] = p.get_string();
  }
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, f.film.radiance.data()))
    throw Error("cannot read " + file + ": " + in->geterror());
  return f;
}

}  // namespace zz
