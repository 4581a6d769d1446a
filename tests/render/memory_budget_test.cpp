// The memory budget a frame is checked against, and $ZIGZAG_MEMORY_LIMIT's reading.
#include "render/memory_budget.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "core/error.h"

namespace zz {
namespace {

TEST(MemoryLimit, BytesOrAWholeNumberOfBinaryUnits) {
  EXPECT_EQ(parse_memory_limit("1073741824"), 1ull << 30);
  EXPECT_EQ(parse_memory_limit("64M"), 64ull << 20);
  EXPECT_EQ(parse_memory_limit("4G"), 4ull << 30);
  EXPECT_EQ(parse_memory_limit("4GiB"), 4ull << 30);
  EXPECT_EQ(parse_memory_limit("512K"), 512ull << 10);
  EXPECT_EQ(parse_memory_limit("2T"), 2ull << 40);
  EXPECT_EQ(parse_memory_limit("18446744073709551615"), ~0ull);
  EXPECT_EQ(parse_memory_limit("0"), 0u);  // no limit, as it always was
  EXPECT_EQ(parse_memory_limit("0G"), 0u);
}

// strtoull read "4G" as 4 bytes (every render then failed for want of memory), "2e9" as 2,
// and took "abc", "-5" (a huge number) and "100000000x" without a word.
TEST(MemoryLimit, AnythingElseIsRefusedNamingTheVariable) {
  for (const char* bad : {"4GB", "8gb", "2e9", "1.5G", "abc", "-5", "+5", " 5", "5 ", "100000000x", "", "G",
                          "99999999999999999999", "17179869184G"}) {
    SCOPED_TRACE(bad);
    try {
      (void)parse_memory_limit(bad);
      ADD_FAILURE() << "accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("ZIGZAG_MEMORY_LIMIT=") + bad + ": not a memory size"),
                std::string::npos)
          << e.what();
    }
  }
}

// The need is compared with the smallest bound, and the message says which one it is.
TEST(MemoryLimit, TheRefusalSaysWhatSetsTheBudget) {
  const char* saved = std::getenv("ZIGZAG_MEMORY_LIMIT");
  const std::string keep = saved ? saved : "";
  // The limit is the process's: what it holds already counts against it (review: a 12M
  // limit let a process of 200 MB through, its frame's own 10 MB being all it was checked for).
  setenv("ZIGZAG_MEMORY_LIMIT", "1T", 1);
  const uint64_t held = resident_bytes();
  const MemoryBudget budget = memory_budget();
  ASSERT_GT(held, 0u);
  if (budget.bound_by.rfind("ZIGZAG", 0) == 0) {  // a machine with less than 1 TiB to spare
    EXPECT_NEAR(double(budget.bytes), double((uint64_t(1) << 40) - held), 64.0 * 1024 * 1024);
    EXPECT_NE(budget.bound_by.find("ZIGZAG_MEMORY_LIMIT=1T, less the "), std::string::npos) << budget.bound_by;
    EXPECT_NE(budget.bound_by.find(" the process holds"), std::string::npos) << budget.bound_by;
  }
  // A limit below what the process holds leaves nothing: any frame is refused, naming it.
  setenv("ZIGZAG_MEMORY_LIMIT", "100K", 1);
  EXPECT_EQ(memory_budget().bytes, 1u);
  try {
    check_memory(3u << 19, "merging these parts");
    ADD_FAILURE() << "a need over the budget passed";
  } catch (const Error& e) {
    // In a unit the numbers show in (a 100K limit was "0.00 GiB ... only 0.00 GiB").
    EXPECT_NE(std::string(e.what()).find("merging these parts needs about 1.50 MiB of memory but none is available "
                                         "(ZIGZAG_MEMORY_LIMIT=100K, less the "),
              std::string::npos)
        << e.what();
  }
  const uint64_t limit = resident_bytes() + (uint64_t(8) << 20);  // 8 MiB beyond what it holds
  setenv("ZIGZAG_MEMORY_LIMIT", std::to_string(limit).c_str(), 1);
  EXPECT_NO_THROW(check_memory(uint64_t(4) << 20, "a frame"));
  EXPECT_THROW(check_memory(uint64_t(16) << 20, "a frame"), Error);
  setenv("ZIGZAG_MEMORY_LIMIT", "4GB", 1);
  EXPECT_THROW((void)memory_budget(), UsageError);
  // Set empty (VAR=, as docker -e and Kubernetes leave it) or 0: no limit of its own.
  for (const char* none : {"", "0"}) {
    setenv("ZIGZAG_MEMORY_LIMIT", none, 1);
    EXPECT_EQ(memory_budget().bound_by.find("ZIGZAG"), std::string::npos) << none;
  }
  if (saved) setenv("ZIGZAG_MEMORY_LIMIT", keep.c_str(), 1);
  else unsetenv("ZIGZAG_MEMORY_LIMIT");
  if (!saved) {
    EXPECT_EQ(memory_budget().bound_by.find("ZIGZAG"), std::string::npos);
  }
}

}  // namespace
}  // namespace zz
