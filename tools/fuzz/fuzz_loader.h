// The body shared by the loader fuzzers and their regression replay (tests/robust):
// write the input as a scene file of the given format into a private work directory
// (the loader reads files; its models and buffers are placed next to it), load it, and
// check what a loaded scene promises. The contract under test (scene/loader.h): every
// failure is a zz::Error; anything else escaping, a sanitizer report, a hang or a broken
// invariant is a bug. A scene that loads is also traced (BVH + a 4x4 packet grid through
// the Whitted shader) so that hostile but accepted values reach the renderer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace zz::fuzz {

// ext: "gltf", "glb" or "json". Returns 0 (libFuzzer's convention); aborts on a bug.
int load_input(const uint8_t* data, size_t size, const std::string& ext);

// The directory the inputs are written to (created on first use, removed at exit).
const std::filesystem::path& work_dir();

}  // namespace zz::fuzz
