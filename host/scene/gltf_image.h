// glTF images -> linear float textures. Decoding is lazy: tinygltf's image callback only
// keeps the encoded bytes (keep_encoded) and decode_image() runs stb through
// tinygltf::LoadImageData (Debian's libtinygltf links libstb) for the images we sample.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "scene/texture.h"

namespace tinygltf {
struct Image;
}

namespace zz::gltf {

// The largest texture: 8-bit images stay 4 bytes a texel (16384^2: 1 GiB), 16-bit ones
// become float RGBA, 16 bytes a texel (8192^2: 1 GiB). Checked from the file's header
// before decoding where it is a PNG or JPEG.
inline constexpr uint64_t kMaxTexels8 = uint64_t(1) << 28;
inline constexpr uint64_t kMaxTexels16 = uint64_t(1) << 26;
uint64_t max_texels(int bits_per_channel);

// tinygltf image-loader callback (signature of tinygltf::LoadImageDataFunction). `user`
// is the tinygltf::Model being loaded: tinygltf hands over a bufferView's bytes without
// checking that the view lies inside its buffer, so this checks it before reading them.
bool keep_encoded(tinygltf::Image* image, const int index, std::string* err, std::string* warn,
                  int req_width, int req_height, const unsigned char* bytes, int size, void* user);

// Decodes image `source` (8/16-bit, 1-4 channels) to linear RGBA; `srgb` applies the sRGB
// transfer function to the colour channels. nullopt (with a reason in *why) when the
// image is missing, undecodable or implausibly large.
std::optional<Texture> decode_image(const tinygltf::Image& image, int source, bool srgb, std::string* why);

}  // namespace zz::gltf
