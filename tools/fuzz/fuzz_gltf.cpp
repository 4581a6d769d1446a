// libFuzzer entry: the input is a .gltf scene file (see fuzz_loader.h).
#include "fuzz_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return zz::fuzz::load_input(data, size, "gltf");
}
