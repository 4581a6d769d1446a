#include "core/prefault.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace zz {
namespace {

// Pages of [data, data + bytes) that are resident, by mincore.
size_t resident_pages(void* mapping, size_t bytes) {
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  std::vector<unsigned char> in_core((bytes + page - 1) / page);
  EXPECT_EQ(::mincore(mapping, bytes, in_core.data()), 0);
  size_t n = 0;
  for (unsigned char c : in_core) n += c & 1;
  return n;
}

struct Mapping {
  explicit Mapping(size_t bytes) : bytes(bytes) {
    data = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  }
  ~Mapping() { ::munmap(data, bytes); }
  char* bytes_at(size_t offset) const { return static_cast<char*>(data) + offset; }
  void* data;
  size_t bytes;
};

TEST(Prefault, MakesAFreshMappingResident) {
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  Mapping m(64 * page);
  ASSERT_NE(m.data, MAP_FAILED);
  ASSERT_EQ(resident_pages(m.data, m.bytes), 0u);  // nothing touched yet
  prefault(m.data, m.bytes);
  EXPECT_EQ(resident_pages(m.data, m.bytes), 64u);
}

// A buffer need not start or end on a page: the partial pages at both ends are mapped in
// too. (Pages beyond may be as well where the kernel maps anonymous memory in larger folios,
// mTHP: only the range is checked.)
TEST(Prefault, CoversUnalignedEnds) {
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  Mapping m(16 * page);
  ASSERT_NE(m.data, MAP_FAILED);
  prefault(m.bytes_at(2 * page + 100), 5 * page);  // pages 2..7, partly 2 and 7
  std::vector<unsigned char> in_core(16);
  ASSERT_EQ(::mincore(m.data, m.bytes, in_core.data()), 0);
  for (size_t i = 2; i <= 7; ++i) EXPECT_EQ(in_core[i] & 1, 1) << "page " << i;
}

// Writable afterwards, and small ranges inside one page work (no whole page to advise).
TEST(Prefault, SmallRangesAndWritesAfter) {
  const size_t page = size_t(::sysconf(_SC_PAGESIZE));
  Mapping m(4 * page);
  ASSERT_NE(m.data, MAP_FAILED);
  prefault(m.bytes_at(page), 0);
  EXPECT_EQ(resident_pages(m.data, m.bytes), 0u);
  prefault(m.bytes_at(10), 20);
  std::vector<unsigned char> in_core(4);
  ASSERT_EQ(::mincore(m.data, m.bytes, in_core.data()), 0);
  EXPECT_EQ(in_core[0] & 1, 1);
  prefault(m.data, m.bytes);
  std::memset(m.data, 7, m.bytes);
  EXPECT_EQ(*m.bytes_at(m.bytes - 1), 7);
}

}  // namespace
}  // namespace zz
