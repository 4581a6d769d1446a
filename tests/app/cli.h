// Running the real `zigzag` binary from tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace zz::test {

struct CommandResult {
  int exit_code = -1;   // -1 if it did not exit normally (signal)
  std::string output;   // stdout + stderr
};

inline std::string zigzag_binary() { return std::string(ZZ_BINARY_DIR) + "/zigzag"; }
inline std::string source_path(const std::string& relative) { return std::string(ZZ_SOURCE_DIR) + "/" + relative; }

inline CommandResult run_command(const std::string& command) {
  CommandResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace zz::test
