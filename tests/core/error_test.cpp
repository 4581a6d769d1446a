// What errors say to the user (core/error.h).
#include "core/error.h"

#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>

namespace zz {
namespace {

// A job that ran out of memory said "car.json: std::bad_alloc".
TEST(ErrorText, AFailedAllocationIsOutOfMemory) {
  EXPECT_EQ(error_text(std::bad_alloc()).rfind("out of memory (an allocation failed;", 0), 0u);
  EXPECT_NE(error_text(std::bad_array_new_length()).find("out of memory"), std::string::npos);
  EXPECT_EQ(error_text(Error("scene.json: no triangles")), "scene.json: no triangles");
  EXPECT_EQ(error_text(std::runtime_error("x")), "x");
}

TEST(ErrorText, UsageChecksTurnErrorsIntoUsageErrors) {
  EXPECT_THROW(as_usage_checks([] { throw Error("bad"); }), UsageError);
  EXPECT_THROW(as_usage_checks([] { throw std::runtime_error("internal"); }), std::runtime_error);
  try {
    as_usage_checks([] { throw Error("bad option"); });
  } catch (const UsageError& e) {
    EXPECT_STREQ(e.what(), "bad option");
  }
}

}  // namespace
}  // namespace zz
