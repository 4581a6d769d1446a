// One exception type for user-facing errors: the message is printed as a single line
// and the process exits non-zero. Programming errors stay asserts.
#pragma once

#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

namespace zz {

// A line break or carriage return in what a message quotes (a file name, a --camera
// value) is written as \n or \r, so the message stays one line.
inline std::string one_line(std::string text) {
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n' || text[i] == '\r') text.replace(i, 1, text[i] == '\n' ? "\\n" : "\\r"), ++i;
  return text;
}

struct Error : std::runtime_error {
  explicit Error(const std::string& what) : std::runtime_error(one_line(what)) {}
  explicit Error(const char* what) : Error(std::string(what)) {}
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

// The machine ran out of what the process may use (memory, or a thread it could not start:
// std::async under ulimit -v threw "Resource temporarily unavailable"): not a bug of ours.
inline bool out_of_resources(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e)) return true;
  const auto* system = dynamic_cast<const std::system_error*>(&e);
  return system && system->code() == std::errc::resource_unavailable_try_again;
}

// What an error says to the user: out of resources in so many words, not "std::bad_alloc"
// (a scene or frame under ulimit -v).
inline std::string error_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e))
    return "out of memory (an allocation failed; see ulimit -v and the memory available)";
  if (out_of_resources(e))
    return std::string("out of resources: ") + e.what() + " (a thread could not start; see ulimit -v and ulimit -u)";
  return e.what();
}

}  // namespace zz
