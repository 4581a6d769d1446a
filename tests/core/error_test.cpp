// What errors say to the user (core/error.h).
#include "core/error.h"

#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

namespace zz {
namespace {

// A job that ran out of memory said "car.json: std::bad_alloc"; a thread that could not
// start under ulimit -v was an "internal error: Resource temporarily unavailable" (exit 2).
TEST(ErrorText, WhatTheMachineRanOutOfIsSaid) {
  EXPECT_EQ(error_text(std::bad_alloc()), "out of memory (an allocation failed; see ulimit -v and the memory available)");
  EXPECT_NE(error_text(std::bad_array_new_length()).find("out of memory"), std::string::npos);
  const std::system_error no_thread(std::make_error_code(std::errc::resource_unavailable_try_again));
  EXPECT_TRUE(out_of_resources(no_thread));
  EXPECT_EQ(error_text(no_thread).rfind("out of resources: ", 0), 0u);
  EXPECT_NE(error_text(no_thread).find("a thread could not start"), std::string::npos);
  EXPECT_TRUE(out_of_resources(std::bad_alloc()));
  EXPECT_FALSE(out_of_resources(std::system_error(std::make_error_code(std::errc::invalid_argument))));
  EXPECT_FALSE(out_of_resources(std::runtime_error("x")));
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

// A message quoting a name with a line break in it (-o $'a\nb.gif') stays one line.
TEST(ErrorText, AMessageIsOneLineWhateverItQuotes) {
  EXPECT_STREQ(Error("-o a\nb.gif: unsupported").what(), "-o a\\nb.gif: unsupported");
  EXPECT_STREQ(UsageError(std::string("--camera x\r\ny")).what(), "--camera x\\r\\ny");
  EXPECT_STREQ(Error("plain").what(), "plain");
}

}  // namespace
}  // namespace zz
