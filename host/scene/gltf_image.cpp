#include "scene/gltf_image.h"

#include <tiny_gltf.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <vector>

namespace zz::gltf {
namespace {

float srgb_to_linear(float c) {
  // IEC 61966-2-1 transfer function.
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Width, height and bits per channel from a PNG's IHDR or a JPEG's frame header (the
// formats glTF allows), read before decoding: the decoder allocates what the header
// claims, and a few kB of compressed zeros can claim gigabytes.
struct EncodedSize {
  uint32_t width = 0, height = 0;
  int bits = 8;
  // What stb_image, tinygltf's decoder, reads: any PNG; a JPEG only baseline or progressive
  // (SOF0-2) at 8 bits, not 12-bit, lossless or arithmetic-coded ones.
  bool decoder_reads = true;
};

std::optional<EncodedSize> encoded_size(const std::vector<unsigned char>& b) {
  auto be16 = [&](size_t at) { return uint32_t(b[at]) << 8 | b[at + 1]; };
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 25 && std::equal(kPng, kPng + 8, b.begin()) && std::equal(b.begin() + 12, b.begin() + 16, "IHDR"))
    return EncodedSize{be16(16) << 16 | be16(18), be16(20) << 16 | be16(22), b[24]};
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return std::nullopt;
  for (size_t i = 2; i + 9 < b.size();) {
    if (b[i] != 0xFF) return std::nullopt;
    const unsigned char marker = b[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC)
      return EncodedSize{be16(i + 7), be16(i + 5), b[i + 4],  // SOFn: precision, height, width
                         marker <= 0xC2 && b[i + 4] == 8};
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) i += 2;  // no length
    else i += 2 + be16(i + 2);
  }
  return std::nullopt;
}

// The largest texture: 8-bit images stay 4 bytes a texel (16384^2: 1 GiB), 16-bit ones
// become float RGBA, 16 bytes a texel (8192^2: 1 GiB). Checked from the file's header
// before decoding where it is a PNG or JPEG.
uint64_t max_texels(int bits_per_channel) {
  return bits_per_channel > 8 ? uint64_t(1) << 26 : uint64_t(1) << 28;
}

}  // namespace

// Decoding every image up front would cost seconds on ToyCar (normal, occlusion and
// clearcoat maps we never sample), so the callback only keeps the encoded bytes.
bool keep_encoded(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
  if (image->bufferView >= 0) {
    const auto* model = static_cast<const tinygltf::Model*>(user);
    if (!model) return false;
    const tinygltf::BufferView& view = model->bufferViews[size_t(image->bufferView)];  // tinygltf checked the indices
    const uint64_t buffer_size = model->buffers[size_t(view.buffer)].data.size();
    if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset) {
      if (err)
        *err += "image " + std::to_string(index) + ": bufferView " + std::to_string(image->bufferView) + " (offset " +
                std::to_string(view.byteOffset) + ", " + std::to_string(view.byteLength) + " bytes) exceeds its buffer of " +
                std::to_string(buffer_size) + " bytes\n";
      return false;
    }
  }
  if (size <= 0 || !bytes) {
    if (err) *err += "image " + std::to_string(index) + ": no bytes, or more than 2 GiB\n";
    return false;
  }
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

std::optional<Texture> decode_image(const tinygltf::Image& encoded, int source, bool srgb, std::string* why) {
  const std::string label = "image " + std::to_string(source) +
                            (encoded.uri.empty() ? "" : " '" + encoded.uri + "'");
  auto too_big = [&](uint64_t w, uint64_t h, int bits) {
    if (w * h <= max_texels(bits)) return false;
    *why = label + " is " + std::to_string(w) + "x" + std::to_string(h) + " at " + std::to_string(bits) +
           " bits, above the limit of " + std::to_string(max_texels(bits)) + " texels (" +
           std::to_string(max_texels(bits) >> 20) + " Mi) for that depth";
    return true;
  };
  tinygltf::Image img;
  if (encoded.as_is) {
    const std::optional<EncodedSize> size = encoded_size(encoded.image);
    if (size && too_big(size->width, size->height, size->bits)) return std::nullopt;
    std::string err, warning;
    if (encoded.image.empty() || encoded.image.size() > size_t(INT32_MAX) ||
        !tinygltf::LoadImageData(&img, source, &err, &warning, 0, 0, encoded.image.data(),
                                 int(encoded.image.size()), nullptr)) {
      *why = label + " could not be decoded";
      // A header that reads is a PNG or JPEG whose data is damaged, or whose decode found no
      // memory (under ulimit -v a sound image failed here, said to be undecodable), unless
      // it is a JPEG the decoder does not read.
      const std::string dims = size ? std::to_string(size->width) + "x" + std::to_string(size->height) : "";
      if (size && size->decoder_reads)
        *why += ": a " + dims + " image whose data is damaged, or memory ran out decoding it";
      else if (size)
        *why += ": a " + dims + " JPEG of a kind its decoder (stb_image) does not read (12-bit, lossless or "
                "arithmetic-coded); save it as a baseline JPEG or a PNG";
      return std::nullopt;
    }
  } else {
    img = encoded;  // embedded data decoded by tinygltf itself
  }
  const int w = img.width, h = img.height, comp = img.component;
  const int bytes = img.bits == 16 ? 2 : img.bits == 8 ? 1 : 0;
  if (w > 0 && h > 0 && bytes > 0 && too_big(uint64_t(w), uint64_t(h), 8 * bytes)) return std::nullopt;
  if (w <= 0 || h <= 0 || comp < 1 || comp > 4 || bytes == 0 ||
      img.image.size() < size_t(w) * size_t(h) * size_t(comp) * size_t(bytes)) {
    *why = label + " is missing or has an unsupported layout";
    return std::nullopt;
  }
  Texture t;
  t.width = w;
  t.height = h;
  const size_t count = size_t(w) * size_t(h);
  const bool grey = comp <= 2, has_alpha = comp == 2 || comp == 4;
  const int alpha_channel = comp == 2 ? 1 : 3;
  if (bytes == 1) {
    // Bytes stay bytes; the tables hold exactly the floats a float decode stores per texel
    // (colour: v / 255 or its sRGB decode; alpha: v * (1 / 255), or 1 without an alpha channel).
    for (int i = 0; i < 256; ++i) {
      t.colour_of_byte[size_t(i)] = srgb ? srgb_to_linear(float(i) / 255.0f) : float(i) / 255.0f;
      t.alpha_of_byte[size_t(i)] = has_alpha ? float(i) * (1.0f / 255.0f) : 1.0f;
    }
    t.texels8.resize(count);
    for (size_t p = 0; p < count; ++p) {
      const unsigned char* px = img.image.data() + p * size_t(comp);
      const uint32_t r = px[0], g = grey ? r : px[1], b = grey ? r : px[2];
      const uint32_t a = has_alpha ? px[alpha_channel] : 255u;
      t.texels8[p] = r | (g << 8) | (b << 16) | (a << 24);
    }
    return t;
  }
  t.texels.resize(count);
  const float scale = 1.0f / 65535.0f;
  for (size_t p = 0; p < count; ++p) {
    float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    for (int k = 0; k < comp; ++k) {
      size_t at = (p * size_t(comp) + size_t(k)) * 2;
      bool colour = k < 3 && !(comp == 2 && k == 1);  // grey+alpha: channel 1 is alpha
      float v = float(uint32_t(img.image[at]) | (uint32_t(img.image[at + 1]) << 8)) * scale;
      c[k] = colour && srgb ? srgb_to_linear(v) : v;
    }
    if (grey) {
      float a = comp == 2 ? c[1] : 1.0f;
      c[1] = c[2] = c[0];
      c[3] = a;
    }
    t.texels[p] = glm::vec4(c[0], c[1], c[2], c[3]);
  }
  return t;
}

}  // namespace zz::gltf
