#include "core/address_space.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

namespace zz {

// The soft limit in bytes, and 0 for none: the budget and the Vulkan hints read it so.
TEST(AddressSpace, LimitIsTheSoftRlimitInBytesAndZeroWhenUnlimited) {
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &old), 0);
  EXPECT_EQ(address_space_limit(), old.rlim_cur == RLIM_INFINITY ? 0u : uint64_t(old.rlim_cur));
  rlimit finite = old;
  finite.rlim_cur = old.rlim_max == RLIM_INFINITY ? RLIM_INFINITY - 1 : old.rlim_max;  // too large to bind
  if (finite.rlim_cur == RLIM_INFINITY || setrlimit(RLIMIT_AS, &finite) != 0) GTEST_SKIP() << "no finite limit to set";
  const uint64_t seen = address_space_limit();
  ASSERT_EQ(setrlimit(RLIMIT_AS, &old), 0);
  EXPECT_EQ(seen, uint64_t(finite.rlim_cur));
}

}  // namespace zz
