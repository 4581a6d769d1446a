#include "render/aov_layers.h"

#include <algorithm>

#include "core/error.h"

namespace zz {

namespace {

struct AovInfo {
  Aov aov;
  const char* name;
  std::vector<std::string> channels;
};

const std::vector<AovInfo>& aov_table() {
  static const std::vector<AovInfo> table = {
      {Aov::Rays, "rays", {"rays"}},
      {Aov::Level, "level", {"level"}},
      {Aov::Geo, "geo", {"geo"}},
      {Aov::Depth, "depth", {"depth"}},
      {Aov::Normal, "normal", {"normal.X", "normal.Y", "normal.Z"}},
      {Aov::Albedo, "albedo", {"albedo.R", "albedo.G", "albedo.B"}},
  };
  return table;
}

const AovInfo& info(Aov aov) { return aov_table()[size_t(aov)]; }

}  // namespace

const char* aov_name(Aov aov) { return info(aov).name; }

std::optional<Aov> find_aov(std::string_view name) {
  if (name == "levels") return Aov::Level;  // the heatmap's name before the EXR layers
  for (const AovInfo& i : aov_table())
    if (name == i.name) return i.aov;
  return std::nullopt;
}

std::string aov_names() {
  std::string names;
  for (const AovInfo& i : aov_table()) names += (names.empty() ? "" : ", ") + std::string(i.name);
  return names;
}

std::vector<std::string> aov_channel_names(Aov aov) { return info(aov).channels; }

bool has_heatmap(Aov aov) { return aov == Aov::Rays || aov == Aov::Level || aov == Aov::Geo; }

bool needs_primary_hits(Aov aov) { return !has_heatmap(aov); }

std::vector<FilmChannel> aov_channels(const std::vector<Aov>& aovs, const Film& film, const GeoMap& geo,
                                      const PrimaryHits& hits) {
  const size_t pixels = size_t(film.width) * size_t(film.height);
  std::vector<FilmChannel> out;
  auto add = [&](const std::string& name, auto&& value_of) {
    FilmChannel c{name, std::vector<float>(pixels)};
    for (size_t i = 0; i < pixels; ++i) c.values[i] = value_of(i);
    out.push_back(std::move(c));
  };
  for (Aov aov : kAllAovs) {
    if (std::find(aovs.begin(), aovs.end(), aov) == aovs.end()) continue;
    if (needs_primary_hits(aov) && (hits.width != film.width || hits.height != film.height))
      throw Error(std::string("--aov ") + aov_name(aov) + ": the primary hits were not traced for this film");
    switch (aov) {
      case Aov::Rays:
        add("rays", [&](size_t i) { return float(film.rays[i]); });
        break;
      case Aov::Level:
        add("level", [&](size_t i) { return float(film.level[i] & 3); });
        break;
      case Aov::Geo:
        if (geo.width != film.width || geo.height != film.height)
          throw Error("--aov geo needs the visibility map (--edges vulkan)");
        add("geo", [&](size_t i) { return geo.flags[i] ? 1.0f : 0.0f; });
        break;
      case Aov::Depth:
        add("depth", [&](size_t i) { return hits.depth[i]; });
        break;
      case Aov::Normal:
        for (int c = 0; c < 3; ++c) add(info(aov).channels[size_t(c)], [&](size_t i) { return hits.normal[i][c]; });
        break;
      case Aov::Albedo:
        for (int c = 0; c < 3; ++c) add(info(aov).channels[size_t(c)], [&](size_t i) { return hits.albedo[i][c]; });
        break;
    }
  }
  return out;
}

}  // namespace zz
