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
      *why = label + " could not be decoded, ignored";
      return std::nullopt;
    }
  } else {
    img = encoded;  // embedded data decoded by tinygltf itself
  }
  const int w = img.width, h = img.height, comp = img.component;
  const int bytes = img.bits == 16 ? 2 : img.bits == 8 ? 1 : 0;
  // At most 2^25 texels (512 MiB as float RGBA): bigger is a hostile header, not a texture.
  if (w <= 0 || h <= 0 || comp < 1 || comp > 4 || bytes == 0 || w > 65536 || h > 65536 ||
      uint64_t(w) * uint64_t(h) > (uint64_t(1) << 25) ||
      img.image.size() < size_t(w) * size_t(h) * size_t(comp) * size_t(bytes)) {
    *why = label + " is missing or has an unsupported layout, ignored";
    return std::nullopt;
  }
  Texture t;
  t.width = w;
  t.height = h;
  t.texels.resize(size_t(w) * size_t(h));
  const float scale = bytes == 2 ? 1.0f / 65535.0f : 1.0f / 255.0f;
  // 8-bit sRGB decode through a table: 256 pow() calls instead of one per texel.
  float lut[256];
  for (int i = 0; i < 256; ++i) lut[i] = srgb ? srgb_to_linear(float(i) / 255.0f) : float(i) / 255.0f;
  for (size_t p = 0; p < t.texels.size(); ++p) {
    float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    for (int k = 0; k < comp; ++k) {
      size_t at = (p * size_t(comp) + size_t(k)) * size_t(bytes);
      bool colour = k < 3 && !(comp == 2 && k == 1);  // grey+alpha: channel 1 is alpha
      if (bytes == 1) {
        uint8_t v = img.image[at];
        c[k] = colour ? lut[v] : float(v) * scale;
      } else {
        float v = float(uint32_t(img.image[at]) | (uint32_t(img.image[at + 1]) << 8)) * scale;
        c[k] = colour && srgb ? srgb_to_linear(v) : v;
      }
    }
    if (comp <= 2) {  // grey (+ alpha)
      float a = comp == 2 ? c[1] : 1.0f;
      c[1] = c[2] = c[0];
      c[3] = a;
    }
    t.texels[p] = glm::vec4(c[0], c[1], c[2], c[3]);
  }
  return t;
}

}  // namespace zz::gltf
