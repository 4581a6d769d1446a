#include "aa/table_set.h"

#include <array>

namespace zz {
namespace {

constexpr uint8_t Z0 = 1, Z1 = 2, Z2 = 4, Z3 = 8, Z4 = 16, ALL = kAllZones;

// The paper's Table 1 (ALGORITHM.md §5), rows by mask 0000..1111 (bit3 bit2 bit1 bit0).
constexpr TableSet kPaper = {
    "paper",
    // b
    {0, Z1 | Z2, Z3, Z2 | Z3, Z1, Z1, Z1 | Z2 | Z3, Z1 | Z2 | Z3,
     Z2 | Z3, Z2, Z3, Z1 | Z2 | Z3, Z1 | Z2, Z1 | Z2, Z1 | Z2 | Z3, ALL},
    // c0
    {0, Z0, Z3, Z0 | Z3, Z1, Z0, Z1 | Z3, Z0 | Z3,
     Z4, Z0 | Z4, Z4, Z0 | Z4, Z1 | Z4, Z0 | Z4, Z1 | Z4, ALL},
    // c1
    {0, Z1 | Z2, Z4, Z1 | Z2 | Z4, Z0, Z0, Z0 | Z4, Z0 | Z4,
     Z2 | Z3, Z2, Z4, Z2 | Z4, Z0 | Z2 | Z3, Z0 | Z2, Z0 | Z4, ALL},
};

constexpr TableSet kAll = {
    "all",
    {ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL},
    {ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL},
    {ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL},
};

// Written by tools/table_tuner (see tools/table_tuner/README.md and pareto.csv).
#include "aa/tuned_tables.inc"

constexpr std::array<const TableSet*, 4> kRegistry = {&kPaper, &kTuned, &kTunedHq, &kAll};

}  // namespace

const TableSet* find_table_set(std::string_view name) {
  for (const TableSet* t : kRegistry)
    if (name == t->name) return t;
  return nullptr;
}

std::vector<std::string_view> table_set_names() {
  std::vector<std::string_view> names;
  for (const TableSet* t : kRegistry) names.emplace_back(t->name);
  return names;
}

const TableSet& paper_table_set() { return kPaper; }

}  // namespace zz
