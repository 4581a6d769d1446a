// One exception type for user-facing errors: the message is printed as a single line
// and the process exits non-zero. Programming errors stay asserts.
#pragma once

#include <stdexcept>
#include <string>

namespace zz {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace zz
