// Runs a program as a child process with a time limit and optional address-space limit,
// capturing its stderr and peak RSS: how the CLI tests tell an error exit from a crash
// (a signal) or a hang (the timeout).
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <future>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace zz::robust {

// ASan reserves terabytes of address space for its shadow memory and inflates RSS: an
// address-space limit or an RSS bound means nothing in a sanitizer build.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

struct ChildResult {
  bool exited = false;   // normal exit (else: signal or timeout)
  int exit_code = -1;
  int signal = 0;        // terminating signal, 0 if none
  bool timed_out = false;
  std::string err;       // stderr
  long max_rss_kb = 0;   // peak resident set size
  double seconds = 0.0;      // wall clock
  double cpu_seconds = 0.0;  // user + system: what the child itself spent, whatever else runs
};

struct ChildOptions {
  std::vector<std::pair<std::string, std::string>> env;  // added to the environment
  double timeout_s = 60.0;
  size_t address_space_limit = 0;  // RLIMIT_AS in bytes; 0 = none
  size_t file_size_limit = 0;      // RLIMIT_FSIZE in bytes (ulimit -f): writes past it fail; 0 = none
};

inline ChildResult run_child(const std::vector<std::string>& argv, const ChildOptions& opt = {}) {
  namespace fs = std::filesystem;
  static std::atomic<int> serial{0};
  const fs::path err_file = fs::temp_directory_path() / ("zz_robust_child_" + std::to_string(::getpid()) + "_" +
                                                         std::to_string(serial++) + "_stderr.txt");
  ChildResult r;
  // Everything the child needs is prepared before fork(): after it only async-signal-safe
  // calls (the test process has other threads).
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e) {
    const std::string kv(*e);
    bool replaced = false;
    for (const auto& [k, v] : opt.env) replaced |= kv.rfind(k + "=", 0) == 0;
    if (!replaced) env_strings.push_back(kv);
  }
  for (const auto& [k, v] : opt.env) env_strings.push_back(k + "=" + v);
  std::vector<char*> envp, args;
  for (std::string& e : env_strings) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_copy = argv;
  for (std::string& a : argv_copy) args.push_back(a.data());
  args.push_back(nullptr);
  const std::string err_path = err_file.string();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) ::dup2(fd, 2);
    const int devnull = ::open("/dev/null", O_RDWR);
    if (devnull >= 0) ::dup2(devnull, 0), ::dup2(devnull, 1);
    if (opt.address_space_limit) {
      rlimit lim{opt.address_space_limit, opt.address_space_limit};
      ::setrlimit(RLIMIT_AS, &lim);
    }
    if (opt.file_size_limit) {
      rlimit lim{opt.file_size_limit, opt.file_size_limit};
      ::setrlimit(RLIMIT_FSIZE, &lim);
    }
    ::execve(args[0], args.data(), envp.data());
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  for (;;) {
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) break;
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (t > opt.timeout_s) {
      r.timed_out = true;
      ::kill(pid, SIGKILL);
      ::wait4(pid, &status, 0, &usage);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!r.timed_out && WIFEXITED(status)) r.exited = true, r.exit_code = WEXITSTATUS(status);
  if (!r.timed_out && WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.max_rss_kb = usage.ru_maxrss;
  r.cpu_seconds = double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                  1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  std::error_code ec;
  fs::remove(err_file, ec);
  return r;
}

// Several children at once (each start costs ~1 s of dynamic loading on a busy machine).
inline std::vector<ChildResult> run_children(const std::vector<std::vector<std::string>>& argvs,
                                             const ChildOptions& opt = {}) {
  std::vector<std::future<ChildResult>> running;
  for (const auto& argv : argvs) running.push_back(std::async(std::launch::async, [&argv, &opt] { return run_child(argv, opt); }));
  std::vector<ChildResult> out;
  for (auto& f : running) out.push_back(f.get());
  return out;
}

// Non-empty lines of a text.
inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

}  // namespace zz::robust
