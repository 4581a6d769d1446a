#include "scene/scene_files.h"

#include <OpenImageIO/hash.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace zz {

std::string files_fingerprint(const std::vector<std::string>& files) {
  uint64_t hash = 0x7a7a;  // "zz"
  std::vector<char> chunk(size_t(1) << 20);  // files of any size, read a MiB at a time
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error(file + ": cannot read (" + std::strerror(errno) + ")");
    uint64_t size = 0;
    while (in) {
      in.read(chunk.data(), std::streamsize(chunk.size()));
      const size_t got = size_t(in.gcount());
      if (got == 0) break;
      hash = OIIO::xxhash::XXH64(chunk.data(), got, hash);
      size += got;
    }
    if (in.bad()) throw Error(file + ": read error");
    hash = OIIO::xxhash::XXH64(&size, sizeof size, hash);  // "ab" + "c" is not "a" + "bc"
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace zz
