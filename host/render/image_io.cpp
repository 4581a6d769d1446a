#include "render/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/atomic_file.h"
#include "core/error.h"

namespace zz {

namespace {

constexpr const char* kAttributePrefix = "zigzag:";

// The first line of a library message: OpenImageIO's can run to several sentences.
std::string first_line(std::string s) {
  const size_t nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

// Writes through a temporary renamed over `path` (core/atomic_file.h).
void write_pixels(const std::filesystem::path& path, const OIIO::ImageSpec& spec, const void* data) {
  if (spec.width < 1 || spec.height < 1) throw Error("cannot write " + path.string() + ": the image is empty");
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    auto out = OIIO::ImageOutput::create(temporary.string());
    if (!out) throw Error("cannot write " + path.string() + ": " + first_line(OIIO::geterror()));
    if (!out->open(temporary.string(), spec) || !out->write_image(spec.format, data) || !out->close())
      throw Error("cannot write " + path.string() + ": " + first_line(out->geterror()));
  });
}

}  // namespace

bool is_hdr_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

bool can_write_image_format(const std::filesystem::path& path) {
  if (path.extension().empty()) return false;
  return OIIO::ImageOutput::create(path.string()) != nullptr;
}

std::vector<uint8_t> display_bytes(const Film& film, const ToneMap& tonemap) {
  // Tone-mapped 4 floats at a time, in the order the RGB bytes are laid out: 4 pixels are
  // 12 floats, copied out of the glm::vec3 array (not indexed through it) into a buffer.
  std::vector<uint8_t> bytes(film.radiance.size() * 3);
  const size_t pixels = film.radiance.size();
  alignas(16) float buf[12];
  size_t p = 0;
  for (; p + 4 <= pixels; p += 4) {
    std::memcpy(buf, &film.radiance[p], sizeof buf);
    for (int k = 0; k < 12; k += 4) {
      const float4 t = tonemap.apply4(float4::load(buf + k)) * float4(255.0f) + float4(0.5f);
      for (int j = 0; j < 4; ++j) bytes[3 * p + size_t(k + j)] = uint8_t(std::clamp(t[j], 0.0f, 255.0f));
    }
  }
  // The last 0..3 pixels: whole groups of 4 floats, then one float at a time.
  const size_t rest = (pixels - p) * 3;
  if (rest > 0) std::memcpy(buf, &film.radiance[p], rest * sizeof(float));
  size_t i = 0;
  for (; i + 4 <= rest; i += 4) {
    const float4 t = tonemap.apply4(float4::load(buf + i)) * float4(255.0f) + float4(0.5f);
    for (int j = 0; j < 4; ++j) bytes[3 * p + i + size_t(j)] = uint8_t(std::clamp(t[j], 0.0f, 255.0f));
  }
  for (; i < rest; ++i) bytes[3 * p + i] = uint8_t(std::clamp(tonemap.apply(buf[i]) * 255.0f + 0.5f, 0.0f, 255.0f));
  return bytes;
}

void write_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  write_pixels(path, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8), rgb.data());
}

void write_film(const std::filesystem::path& path, const Film& film, const ToneMap& tonemap,
                const FilmAttributes& attributes) {
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
    // OpenImageIO copies the bytes: a glm::vec3 is three packed floats.
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
    write_pixels(path, spec, static_cast<const void*>(film.radiance.data()));
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
