#include "scene/gltf_image.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstdint>

namespace zz::gltf {
namespace {

float srgb_to_linear(float c) {
  // IEC 61966-2-1 transfer function.
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

// Decoding every image up front would cost seconds on ToyCar (normal, occlusion and
// clearcoat maps we never sample), so the callback only keeps the encoded bytes.
bool keep_encoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void*) {
  if (size <= 0 || !bytes) return false;
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

std::optional<Texture> decode_image(const tinygltf::Image& encoded, int source, bool srgb, std::string* why) {
  const std::string label = "image " + std::to_string(source) +
                            (encoded.uri.empty() ? "" : " '" + encoded.uri + "'");
  tinygltf::Image img;
  if (encoded.as_is) {
    std::string err, warning;
    if (encoded.image.empty() || encoded.image.size() > size_t(INT32_MAX) ||
        !tinygltf::LoadImageData(&img, source, &err, &warning, 0, 0, encoded.image.data(),
                                 int(encoded.image.size()), nullptr)) {
      *why = label + " could not be decoded";
      return std::nullopt;
    }
  } else {
    img = encoded;  // embedded data decoded by tinygltf itself
  }
  const int w = img.width, h = img.height, comp = img.component;
  const int bytes = img.bits == 16 ? 2 : img.bits == 8 ? 1 : 0;
  // At most 2^25 texels (512 MiB as 16-bit float RGBA): bigger is a hostile header, not a texture.
  if (w <= 0 || h <= 0 || comp < 1 || comp > 4 || bytes == 0 || w > 65536 || h > 65536 ||
      uint64_t(w) * uint64_t(h) > (uint64_t(1) << 25) ||
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
