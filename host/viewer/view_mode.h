// What the viewer window shows (keys 1-4).
#pragma once

namespace zz {

enum class ViewMode { Image, Rays, Level, Geo };

inline const char* to_string(ViewMode m) {
  switch (m) {
    case ViewMode::Image: return "image";
    case ViewMode::Rays: return "rays/px";
    case ViewMode::Level: return "level";
    case ViewMode::Geo: return "geo";
  }
  return "?";
}

}  // namespace zz
