// A fingerprint of the bytes of the files a scene was loaded from (Scene::source_files):
// rig, glTF, buffers, images. Stored in each EXR a render writes, so `zigzag merge` can
// refuse parts rendered from different versions of a scene (a light moved between two
// regions' renders), wherever each part's copy of the files lay.
#pragma once

#include <string>
#include <vector>

namespace zz {

// 16 hex digits: XXH64 (OpenImageIO's) over each file's size and bytes in order, chained
// through its seed; paths do not count. Throws zz::Error naming a file it cannot read.
std::string files_fingerprint(const std::vector<std::string>& files);

}  // namespace zz
