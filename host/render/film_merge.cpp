#include "render/film_merge.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace zz {

namespace {

std::string rect_text(const TileRect& r) {
  return std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," + std::to_string(r.y1);
}

std::string channel_list(const Film& f) {
  std::string names;
  for (const FilmChannel& c : f.channels) names += (names.empty() ? "" : ", ") + c.name;
  return names.empty() ? "none" : names;
}

bool same_channels(const Film& a, const Film& b) {
  if (a.channels.size() != b.channels.size()) return false;
  for (size_t i = 0; i < a.channels.size(); ++i)
    if (a.channels[i].name != b.channels[i].name) return false;
  return true;
}

std::string attribute(const FilmFile& f, const std::string& key) {
  auto it = f.attributes.find(key);
  return it == f.attributes.end() ? std::string() : it->second;
}

// Where two parts' attribute `key` differs, e.g. ": /time is 1.04167 in b.exr, 1 in a.exr"
// for the "settings" (JSON, render_command.cpp image_settings), ": 1 in b.exr, 0 in a.exr"
// for a plain value; empty for text that is not JSON.
std::string setting_difference(const FilmPart& a, const FilmPart& b, const std::string& key) {
  const std::string a_text = attribute(a.file, key), b_text = attribute(b.file, key);
  const nlohmann::json x = nlohmann::json::parse(a_text, nullptr, false);
  const nlohmann::json y = nlohmann::json::parse(b_text, nullptr, false);
  if (x.is_discarded() || y.is_discarded()) {  // plain text (a scene's name): as it is, when short
    if (a_text.size() > 64 || b_text.size() > 64) return "";
    return ": '" + a_text + "' in " + a.name + ", '" + b_text + "' in " + b.name;
  }
  if (x == y) return "";
  if (!x.is_structured() || !y.is_structured()) return ": " + x.dump() + " in " + a.name + ", " + y.dump() + " in " + b.name;
  const std::string path = nlohmann::json::diff(y, x).front().value("path", "");
  const nlohmann::json::json_pointer at(path);
  auto text = [&](const nlohmann::json& j) {
    if (!j.contains(at)) return std::string("absent");
    const nlohmann::json& v = j.at(at);
    if (!v.is_number_float()) return v.dump();
    char number[32];  // the settings' floats are float32: 0.1, not 0.10000000149011612
    std::snprintf(number, sizeof number, "%g", v.get<double>());
    return std::string(number);
  };
  return ": " + path + " is " + text(x) + " in " + a.name + ", " + text(y) + " in " + b.name;
}

// The attributes parts must share: all but the map's device.
FilmAttributes compared(FilmAttributes attributes) {
  attributes.erase(kDeviceAttribute);
  return attributes;
}

}  // namespace

void check_film_parts(const std::vector<FilmPart>& parts) {
  if (parts.empty()) throw Error("merge: no parts");
  const FilmFile& first = parts.front().file;
  const int W = first.film.frame_width, H = first.film.frame_height;
  for (const FilmPart& p : parts) {
    const Film& f = p.file.film;
    if (f.frame_width != W || f.frame_height != H)
      throw Error("merge: " + p.name + " is part of a " + std::to_string(f.frame_width) + "x" +
                  std::to_string(f.frame_height) + " frame but " + parts.front().name + " of a " + std::to_string(W) +
                  "x" + std::to_string(H) + " frame");
    if (!same_channels(f, first.film))
      throw Error("merge: " + p.name + " has the AOV channels " + channel_list(f) + " but " + parts.front().name +
                  " " + channel_list(first.film) + " (render every part with the same --aov)");
    if (std::memcmp(&p.file.tonemap.exposure, &first.tonemap.exposure, sizeof(float)) != 0)
      throw Error("merge: " + p.name + " has exposure " + std::to_string(p.file.tonemap.exposure) + " but " +
                  parts.front().name + " " + std::to_string(first.tonemap.exposure));
    const FilmAttributes mine = compared(p.file.attributes), theirs = compared(first.attributes);
    if (mine != theirs) {
      // The first key whose values differ (or that only one part has); the scene's files
      // only when nothing else does: another scene (zigzag:scene) has other files too.
      std::string key;
      const auto differs = [&key](const std::string& k) {
        if (key.empty() || key == kSceneFilesAttribute) key = k;
      };
      for (const auto& [k, v] : mine)
        if (auto it = theirs.find(k); it == theirs.end() || it->second != v) differs(k);
      for (const auto& [k, v] : theirs)
        if (!mine.count(k)) differs(k);
      if (key == kSceneFilesAttribute)
        throw Error("merge: " + p.name + " and " + parts.front().name +
                    " were rendered from different versions of the scene's files (zigzag:" + key +
                    " differs); render them again from the same files");
      throw Error("merge: " + p.name + " and " + parts.front().name + " come from different renders (zigzag:" + key +
                  " differs" + setting_difference(p, parts.front(), key) + ")");
    }
  }
  // Overlaps: sort by top edge; only parts starting above another's bottom can overlap it.
  std::vector<size_t> order(parts.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto window = [&](size_t i) { return parts[i].file.film.window(); };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::make_pair(window(a).y0, window(a).x0) < std::make_pair(window(b).y0, window(b).x0);
  });
  for (size_t i = 0; i < order.size(); ++i)
    for (size_t j = i + 1; j < order.size() && window(order[j]).y0 < window(order[i]).y1; ++j)
      if (!intersect(window(order[i]), window(order[j])).empty())
        throw Error("merge: " + parts[order[i]].name + " (" + rect_text(window(order[i])) + ") and " +
                    parts[order[j]].name + " (" + rect_text(window(order[j])) + ") overlap");
  // Disjoint parts inside the frame cover it exactly when their areas add up to it.
  uint64_t covered = 0;
  for (size_t i = 0; i < parts.size(); ++i) covered += uint64_t(window(i).width()) * uint64_t(window(i).height());
  if (covered != uint64_t(W) * uint64_t(H))
    throw Error("merge: the parts cover " + std::to_string(covered) + " of the frame's " +
                std::to_string(uint64_t(W) * uint64_t(H)) + " pixels (a region is missing)");

}

std::vector<std::string> devices_of(const std::vector<FilmPart>& parts) {
  std::vector<std::string> devices;
  for (const FilmPart& p : parts) {
    const auto it = p.file.attributes.find(kDeviceAttribute);
    const std::string device = it == p.file.attributes.end() ? "none" : it->second;
    if (std::find(devices.begin(), devices.end(), device) == devices.end()) devices.push_back(device);
  }
  return devices;
}

bool same_film_header(const FilmFile& a, const FilmFile& b) {
  const Film &x = a.film, &y = b.film;
  return x.window() == y.window() && x.frame_width == y.frame_width && x.frame_height == y.frame_height &&
         same_channels(x, y) && std::memcmp(&a.tonemap.exposure, &b.tonemap.exposure, sizeof(float)) == 0 &&
         a.attributes == b.attributes;  // the device included: the same file read twice
}

FilmFile empty_frame(const FilmFile& first) {
  const int W = first.film.frame_width, H = first.film.frame_height;
  FilmFile out;
  out.film = Film(W, H);
  out.tonemap = first.tonemap;
  out.attributes = first.attributes;
  for (const FilmChannel& c : first.film.channels)
    out.film.channels.push_back({c.name, std::vector<float>(size_t(W) * size_t(H))});
  return out;
}

void paste_part(FilmFile& frame, const Film& f) {
  const int W = frame.film.frame_width;
  for (int y = 0; y < f.height; ++y) {
    const size_t from = size_t(y) * f.width, to = size_t(f.y0 + y) * W + f.x0;
    std::copy_n(&f.radiance[from], f.width, &frame.film.radiance[to]);
    for (size_t c = 0; c < f.channels.size(); ++c)
      std::copy_n(&f.channels[c].values[from], f.width, &frame.film.channels[c].values[to]);
  }
}

FilmFile merge_films(const std::vector<FilmPart>& parts) {
  check_film_parts(parts);
  FilmFile out = empty_frame(parts.front().file);
  for (const FilmPart& p : parts) paste_part(out, p.file.film);
  return out;
}

}  // namespace zz
