#include "aa/adaptive_settings.h"

#include <string>

#include "core/error.h"

namespace zz {

GeoPolicy parse_geo_policy(std::string_view name) {
  if (name == "paper") return GeoPolicy::Paper;
  if (name == "split") return GeoPolicy::Split;
  if (name == "all") return GeoPolicy::All;
  throw Error("unknown geo policy '" + std::string(name) + "' (expected paper, split or all)");
}

Filter parse_filter(std::string_view name) {
  if (name == "box") return Filter::Box;
  if (name == "mitchell") return Filter::Mitchell;
  throw Error("unknown filter '" + std::string(name) + "' (expected box or mitchell)");
}

const TableSet& parse_table_set(std::string_view name) {
  if (const TableSet* t = find_table_set(name)) return *t;
  std::string names;
  for (std::string_view n : table_set_names()) names += (names.empty() ? "" : ", ") + std::string(n);
  throw Error("unknown table set '" + std::string(name) + "' (expected one of: " + names + ")");
}

const char* to_string(GeoPolicy p) {
  switch (p) {
    case GeoPolicy::Paper: return "paper";
    case GeoPolicy::Split: return "split";
    case GeoPolicy::All: return "all";
  }
  return "?";
}
const char* to_string(Filter f) { return f == Filter::Box ? "box" : "mitchell"; }

}  // namespace zz
