// glTF images -> linear float textures. Decoding is lazy: tinygltf's image callback only
// keeps the encoded bytes (keep_encoded) and decode_image() runs stb through
// tinygltf::LoadImageData (Debian's libtinygltf links libstb) for the images we sample.
#pragma once

#include <optional>
#include <string>

#include "scene/texture.h"

namespace tinygltf {
struct Image;
}

namespace zz::gltf {

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
