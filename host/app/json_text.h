// JSON as the commands print and write it.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace zz {

// A string that is not valid UTF-8 (a path's own bytes, which Linux allows) is written with
// U+FFFD for its bad bytes: nlohmann's dump threw there, failing `info --json` and every
// job whose --stats names such a path.
inline std::string json_text(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace zz
