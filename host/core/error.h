// One exception type for user-facing errors: the message is printed as a single line
// and the process exits non-zero. Programming errors stay asserts.
#pragma once

#include <new>
#include <stdexcept>
#include <string>

namespace zz {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The command line asks for what cannot be done (a bad option combination, an output that
// cannot be written), found before any scene loads. It exits with kUsageExit, CLI11's own
// code for an option that fails validation, so that a script or the render farm tells it
// from a render that failed: run again, it fails the same way.
struct UsageError : Error {
  using Error::Error;
};
inline constexpr int kUsageExit = 105;

// Runs `checks`, turning the zz::Error it throws into a UsageError.
template <class F>
void as_usage_checks(F&& checks) {
  try {
    checks();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

// What an error says to the user: an allocation that failed is said to be out of memory,
// not "std::bad_alloc" (a scene or frame under ulimit -v).
inline std::string error_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e))
    return "out of memory (an allocation failed; the limits are the memory available, ulimit -v and "
           "$ZIGZAG_MEMORY_LIMIT)";
  return e.what();
}

}  // namespace zz
