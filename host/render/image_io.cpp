#include "render/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "render/checked_output.h"

namespace zz {

namespace {

constexpr const char* kAttributePrefix = "zigzag:";

// The first line of a library message: OpenImageIO's can run to several sentences.
std::string first_line(std::string s) {
  const size_t nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

// An image writer for `temporary` (the format by its extension), writing through a
// CheckedFileOutput: a failed write, which the writer itself may not notice, fails the
// image. Errors name `target`, the file the user asked for.
class OpenOutput {
 public:
  OpenOutput(const std::filesystem::path& target, const std::filesystem::path& temporary)
      : target_(target), file_(temporary), out_(OIIO::ImageOutput::create(temporary.string())) {
    if (!out_) throw Error("cannot write " + target.string() + ": " + first_line(OIIO::geterror()));
    if (const std::string why = file_.failure(); !why.empty()) throw Error("cannot write " + target.string() + ": " + why);
    // Only writers that take a proxy (can_write_image_format): one writing by name would
    // leave its write errors unchecked (SGI and FITS published a truncated file, exit 0).
    if (!out_->supports("ioproxy") || !out_->set_ioproxy(&file_)) fail();
  }
  OIIO::ImageOutput* operator->() const { return out_.get(); }
  // Throws with the writer's error, or else the file's.
  [[noreturn]] void fail() {
    std::string why = first_line(out_->geterror());
    if (why.empty()) why = file_.failure();
    throw Error("cannot write " + target_.string() + ": " + (why.empty() ? "the image writer failed" : why));
  }
  void close() {
    const bool closed = out_->close();
    file_.close();
    const std::string why = file_.failure();
    if (!why.empty()) throw Error("cannot write " + target_.string() + ": " + why);
    if (!closed) fail();
  }

 private:
  std::filesystem::path target_;
  CheckedFileOutput file_;
  std::unique_ptr<OIIO::ImageOutput> out_;
};

// Writes through a temporary renamed over `path` (core/atomic_file.h).
// The written temporary must read back as the image meant (its header: size and
// channels), before it may replace anything: a writer can produce a file it cannot read
// (OpenImageIO 2.4's TIFF writer truncated its main directory behind an Exif one).
void check_reads_back(const std::filesystem::path& target, const std::filesystem::path& temporary,
                      const OIIO::ImageSpec& spec) {
  auto in = OIIO::ImageInput::open(temporary.string());
  const std::string why = in ? "" : first_line(OIIO::geterror());
  if (!in) throw Error("cannot write " + target.string() + ": the written file does not read back (" + why + ")");
  const OIIO::ImageSpec& got = in->spec();
  if (got.width != spec.width || got.height != spec.height || got.nchannels != spec.nchannels)
    throw Error("cannot write " + target.string() + ": the written file reads back as " + std::to_string(got.width) +
                "x" + std::to_string(got.height) + "x" + std::to_string(got.nchannels) + ", not " +
                std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" + std::to_string(spec.nchannels));
}

// The name a writer is opened with, which it writes through its proxy and may record (DPX
// does, in its header): the output's own file name, never the hidden temporary's, nor the
// folder, so the same render writes the same bytes.
std::string header_name(const std::filesystem::path& target) { return target.filename().string(); }

// Without a date, the same render writes the same bytes (OpenImageIO stamps the time).
OIIO::ImageSpec undated(OIIO::ImageSpec spec) {
  spec.attribute("DateTime", "");
  return spec;
}

void write_pixels(const std::filesystem::path& path, const OIIO::ImageSpec& given, const void* data, OutputSet* set) {
  if (given.width < 1 || given.height < 1) throw Error("cannot write " + path.string() + ": the image is empty");
  const OIIO::ImageSpec spec = undated(given);
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    {
      OpenOutput out(path, temporary);
      if (!out->open(header_name(path), spec) || !out->write_image(spec.format, data)) out.fail();
      out.close();
    }
    check_reads_back(path, temporary, spec);
  }, set);
}

// An EXR of the radiance plus film.channels, interleaved a band of rows at a time (a
// whole interleaved copy of a large frame would double the output's memory).
void write_layers(const std::filesystem::path& path, OIIO::ImageSpec spec, const Film& film, OutputSet* set) {
  const size_t extra = film.channels.size();
  for (const FilmChannel& c : film.channels)
    if (c.values.size() != film.radiance.size())
      throw Error("cannot write " + path.string() + ": channel " + c.name + " is not the film's size");
  spec.nchannels = int(3 + extra);
  spec.channelnames = {"R", "G", "B"};
  for (const FilmChannel& c : film.channels) spec.channelnames.push_back(c.name);
  spec.alpha_channel = -1;
  spec.z_channel = -1;
  if (spec.width < 1 || spec.height < 1) throw Error("cannot write " + path.string() + ": the image is empty");
  constexpr int kBand = 64;
  const size_t stride = 3 + extra;
  std::vector<float> band(size_t(kBand) * size_t(film.width) * stride);
  spec = undated(spec);
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    OpenOutput out(path, temporary);
    if (!out->open(header_name(path), spec)) out.fail();
    for (int y0 = 0; y0 < film.height; y0 += kBand) {
      const int y1 = std::min(film.height, y0 + kBand);
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < film.width; ++x) {
          const size_t p = size_t(y) * size_t(film.width) + size_t(x);
          float* o = &band[(size_t(y - y0) * size_t(film.width) + size_t(x)) * stride];
          o[0] = film.radiance[p].r;
          o[1] = film.radiance[p].g;
          o[2] = film.radiance[p].b;
          for (size_t c = 0; c < extra; ++c) o[3 + c] = film.channels[c].values[p];
        }
      if (!out->write_scanlines(film.y0 + y0, film.y0 + y1, 0, OIIO::TypeDesc::FLOAT, band.data())) out.fail();
    }
    out.close();
    check_reads_back(path, temporary, spec);
  }, set);
}

// The writer OpenImageIO picks for the path's extension (null for none).
std::unique_ptr<OIIO::ImageOutput> writer_for(const std::filesystem::path& path) {
  if (path.extension().empty()) return nullptr;
  return OIIO::ImageOutput::create(path.string());
}

// Its format ("" for none): what decides radiance and layers, not the extension, since the
// EXR writer also answers to .sxr and .mxr, which took the 8-bit display image (stored as
// half floats, tagged linear) when only .exr was radiance.
std::string writer_format(const std::filesystem::path& path) {
  const auto out = writer_for(path);
  return out ? out->format_name() : "";
}

}  // namespace

bool writes_radiance(const std::filesystem::path& path) {
  const std::string format = writer_format(path);
  return format == "openexr" || format == "hdr";
}

bool holds_extra_channels(const std::filesystem::path& path) { return writer_format(path) == "openexr"; }

bool can_write_image_format(const std::filesystem::path& path) {
  const auto out = writer_for(path);
  if (!out || !out->supports("ioproxy")) return false;  // see OpenOutput
  // Writers that take the proxy but do not give the image back, found only after the
  // render by the read-back; by the format OpenImageIO picks, not the extension (the TIFF
  // writer also answers to .tx, .env, .sm, .vsm): GIF quantises to a 256-colour palette
  // (and reads back with alpha); OpenImageIO 2.4's JPEG 2000 writer leaves the proxy empty,
  // its TIFF writer a texture's directory without the image's length; "null" writes nothing.
  const std::string format = out->format_name();
  if (format == "gif" || format == "jpeg2000" || format == "null") return false;
  const std::string ext = lowercase_extension(path);
  // The PNM writer writes colour as P6 whatever the name: a .pgm (grey) or .pbm (bitmap)
  // would hold a pixmap its readers do not expect.
  if (format == "pnm") return ext == ".ppm" || ext == ".pnm";
  return format != "tiff" || ext == ".tif" || ext == ".tiff";
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

void write_rgb8(const std::filesystem::path& path, int width, int height, const std::vector<uint8_t>& rgb,
                OutputSet* set) {
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  // The bytes are sRGB-encoded (render/tonemap.h): say so (PNG: the sRGB, gAMA and cHRM
  // chunks), so colour-managed viewers need not guess.
  // Not in a TIFF: there OpenImageIO 2.4 then adds an Exif directory and, writing
  // through a proxy, truncates the main one (an unreadable file).
  const std::string ext = lowercase_extension(path);
  if (ext != ".tif" && ext != ".tiff") spec.attribute("oiio:ColorSpace", "sRGB");
  write_pixels(path, spec, rgb.data(), set);
}

void write_film(const std::filesystem::path& path, const Film& film, const ToneMap& tonemap,
                const FilmAttributes& attributes, OutputSet* set) {
  if (writes_radiance(path)) {
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
    if (film.channels.empty()) {
      write_pixels(path, spec, static_cast<const void*>(film.radiance.data()), set);
      return;
    }
    if (!holds_extra_channels(path))
      throw Error("cannot write " + path.string() + ": only an .exr holds the AOV channels");
    write_layers(path, spec, film, set);
  } else {
    if (!film.channels.empty())
      throw Error("cannot write " + path.string() + ": only an .exr holds the AOV channels");
    write_rgb8(path, film.width, film.height, display_bytes(film, tonemap), set);
  }
}

namespace {

// OpenImageIO reads whatever it is given: a FIFO or /dev/zero as an image never ends.
void require_regular_file(const std::string& file) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(status)) return;  // OpenImageIO says it is missing
  if (!std::filesystem::is_regular_file(status)) throw Error("cannot read " + file + ": not a regular file");
}

}  // namespace

std::vector<float> read_rgb_float(const std::filesystem::path& path, int& width, int& height) {
  require_regular_file(path.string());
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

namespace {

// An EXR written by write_film, opened: its spec checked, the windows, exposure, attributes
// and channel names read into *f (no pixel buffers); `rgb` gets R, G, B's channel indices.
std::unique_ptr<OIIO::ImageInput> open_film(const std::string& file, FilmFile* f, int rgb[3]) {
  require_regular_file(file);
  auto in = OIIO::ImageInput::open(file);
  if (!in) throw Error("cannot read " + file + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) throw Error(file + ": not an RGB image");
  if (spec.depth > 1) throw Error(file + ": volume images are not films");
  const std::string exposure_key = std::string(kAttributePrefix) + "exposure";
  if (!spec.find_attribute(exposure_key))
    throw Error(file + ": no zigzag:exposure attribute (not an EXR written by zigzag render)");
  const float exposure = spec.get_float_attribute(exposure_key, -1.0f);
  if (!(exposure > 0.0f) || !std::isfinite(exposure))
    throw Error(file + ": its zigzag:exposure attribute is not a positive float (" +
                spec.metadata_val(*spec.find_attribute(exposure_key)) + "; zigzag render writes one)");
  if (spec.width <= 0 || spec.height <= 0 || spec.full_width <= 0 || spec.full_height <= 0 || spec.full_x != 0 ||
      spec.full_y != 0 || spec.x < 0 || spec.y < 0 || int64_t(spec.x) + spec.width > spec.full_width ||
      int64_t(spec.y) + spec.height > spec.full_height)
    throw Error(file + ": data window is not inside a display window starting at 0,0");
  // Every channel as zigzag render writes it: a part converted to half (oiiotool -d half)
  // merged without a word into a frame that no longer matched the render.
  for (int c = 0; c < spec.nchannels; ++c)
    if (spec.channelformat(c) != OIIO::TypeDesc::FLOAT)
      throw Error(file + ": channel " + std::string(spec.channel_name(c)) + " is " + spec.channelformat(c).c_str() +
                  ", not the float zigzag render writes (the parts would not merge into the render's values)");
  Film& film = f->film;
  film.width = spec.width;
  film.height = spec.height;
  film.x0 = spec.x;
  film.y0 = spec.y;
  film.frame_width = spec.full_width;
  film.frame_height = spec.full_height;
  f->tonemap.exposure = exposure;
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    const std::string name = p.name().string();
    if (name.rfind(kAttributePrefix, 0) != 0 || p.type() != OIIO::TypeDesc::STRING) continue;
    f->attributes[name.substr(std::strlen(kAttributePrefix))] = p.get_string();
  }
  // R, G, B by name (any order in the file), else the first three; the rest are layers.
  for (int c = 0; c < 3; ++c) {
    const int found = spec.channelindex(c == 0 ? "R" : c == 1 ? "G" : "B");
    rgb[c] = found >= 0 ? found : c;
  }
  for (int c = 0; c < spec.nchannels; ++c)
    if (c != rgb[0] && c != rgb[1] && c != rgb[2]) film.channels.push_back({spec.channel_name(c), {}});
  return in;
}

}  // namespace

FilmFile read_film_header(const std::filesystem::path& path) {
  FilmFile f;
  int rgb[3];
  open_film(path.string(), &f, rgb);
  return f;
}

FilmFile read_film(const std::filesystem::path& path) {
  const std::string file = path.string();
  FilmFile header;
  int rgb[3];
  const std::unique_ptr<OIIO::ImageInput> in = open_film(file, &header, rgb);
  const Film& h = header.film;
  FilmFile f{Film(h.frame_width, h.frame_height, TileRect{h.x0, h.y0, h.x0 + h.width, h.y0 + h.height}),
             header.tonemap, std::move(header.attributes)};
  const int nch = in->spec().nchannels;
  if (nch == 3 && rgb[0] == 0 && rgb[1] == 1 && rgb[2] == 2) {
    if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, f.film.radiance.data()))
      throw Error("cannot read " + file + ": " + first_line(in->geterror()));
    return f;
  }
  std::vector<float> all(size_t(h.width) * size_t(h.height) * size_t(nch));
  if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, all.data()))
    throw Error("cannot read " + file + ": " + first_line(in->geterror()));
  const size_t pixels = f.film.radiance.size();
  for (size_t p = 0; p < pixels; ++p)
    f.film.radiance[p] = glm::vec3(all[p * size_t(nch) + size_t(rgb[0])], all[p * size_t(nch) + size_t(rgb[1])],
                                   all[p * size_t(nch) + size_t(rgb[2])]);
  for (int c = 0; c < nch; ++c) {
    if (c == rgb[0] || c == rgb[1] || c == rgb[2]) continue;
    FilmChannel channel{in->spec().channel_name(c), std::vector<float>(pixels)};
    for (size_t p = 0; p < pixels; ++p) channel.values[p] = all[p * size_t(nch) + size_t(c)];
    f.film.channels.push_back(std::move(channel));
  }
  return f;
}

}  // namespace zz
