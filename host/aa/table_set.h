// Zone table sets (ALGORITHM.md §5, §9): each maps the three level-2 masks b, c0, c1
// (4 bits each) to a 5-bit set of zones to trace (bit z = zone z); the three results
// are OR-ed. Table sets are data, selected by name (`--tables NAME`):
//   paper  the paper's Table 1, verbatim
//   tuned     derived by tools/table_tuner (mean |error| vs the 25-point lattice + λ rays):
//             the least error within the paper's ray budget
//   tuned-hq  the same, fewest rays within 5 % of tracing every zone
//   all       every zone of every level-2 pixel
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace zz {

inline constexpr uint8_t kAllZones = 0x1F;

struct TableSet {
  const char* name;
  uint8_t b[16];
  uint8_t c0[16];
  uint8_t c1[16];

  uint8_t zones(int mb, int mc0, int mc1) const { return uint8_t(b[mb] | c0[mc0] | c1[mc1]); }
};

// nullptr if unknown.
const TableSet* find_table_set(std::string_view name);
std::vector<std::string_view> table_set_names();

const TableSet& paper_table_set();

}  // namespace zz
