#include "render/film_merge.h"

#include <algorithm>
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

// Where two parts' "settings" (JSON, render_command.cpp image_settings) differ, e.g.
// ": /time is 1.0417 here, 1 there"; empty when either is not JSON.
std::string setting_difference(const std::string& here, const std::string& there) {
  const nlohmann::json a = nlohmann::json::parse(here, nullptr, false), b = nlohmann::json::parse(there, nullptr, false);
  if (a.is_discarded() || b.is_discarded() || a == b) return "";
  const nlohmann::json patch = nlohmann::json::diff(b, a);
  const std::string path = patch.front().value("path", "");
  const nlohmann::json::json_pointer at(path);
  auto text = [&](const nlohmann::json& j) { return j.contains(at) ? j.at(at).dump() : std::string("absent"); };
  return ": " + path + " is " + text(a) + " here, " + text(b) + " there";
}

}  // namespace

FilmFile merge_films(const std::vector<FilmPart>& parts) {
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
    if (p.file.attributes != first.attributes) {
      std::string key;  // the first key whose values differ (or that only one part has)
      for (const auto& [k, v] : p.file.attributes)
        if (auto it = first.attributes.find(k); it == first.attributes.end() || it->second != v) key = k;
      for (const auto& [k, v] : first.attributes)
        if (!p.file.attributes.count(k)) key = k;
      throw Error("merge: " + p.name + " and " + parts.front().name + " come from different renders (zigzag:" + key +
                  " differs" + setting_difference(attribute(p.file, key), attribute(first, key)) + ")");
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

  FilmFile out;
  out.film = Film(W, H);
  out.tonemap = first.tonemap;
  out.attributes = first.attributes;
  for (const FilmChannel& c : first.film.channels)
    out.film.channels.push_back({c.name, std::vector<float>(size_t(W) * size_t(H))});
  for (const FilmPart& p : parts) {
    const Film& f = p.file.film;
    for (int y = 0; y < f.height; ++y) {
      const size_t from = size_t(y) * f.width, to = size_t(f.y0 + y) * W + f.x0;
      std::copy_n(&f.radiance[from], f.width, &out.film.radiance[to]);
      for (size_t c = 0; c < f.channels.size(); ++c)
        std::copy_n(&f.channels[c].values[from], f.width, &out.film.channels[c].values[to]);
    }
  }
  return out;
}

}  // namespace zz
