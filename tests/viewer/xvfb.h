// A private X server for the viewer tests: Xvfb on the first free display in :97..:120,
// started by the test and stopped (by its PID) at the end.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace zz::test {

class Xvfb {
 public:
  Xvfb() {
    for (int n = 97; n <= 120 && display_.empty(); ++n) {
      const std::string number = std::to_string(n);
      const std::string socket = "/tmp/.X11-unix/X" + number;
      if (std::filesystem::exists("/tmp/.X" + number + "-lock") || std::filesystem::exists(socket)) continue;
      std::string name(1, ':');
      name += number;
      const pid_t pid = fork();
      if (pid == 0) {
        execlp("Xvfb", "Xvfb", name.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp", (char*)nullptr);
        _exit(127);
      }
      if (pid < 0) return;
      // Ready when its socket appears; gone early = the number was taken meanwhile.
      const auto start = std::chrono::steady_clock::now();
      bool lost = false;
      while (std::chrono::steady_clock::now() - start < std::chrono::seconds(30)) {  // a loaded machine
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) {
          lost = true;  // exited: the number was taken
          break;
        }
        const pid_t owner = lock_owner(number);
        if (owner > 0 && owner != pid) break;  // another server owns it
        // Ours only when the lock file names our child: two tests racing for the same
        // number would otherwise share (and one would kill) the other's server.
        if (std::filesystem::exists(socket) && lock_owner(number) == pid) {
          pid_ = pid;
          display_ = name;
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      if (display_.empty() && !lost) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
      }
    }
  }
  ~Xvfb() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;

  // The PID in /tmp/.X<n>-lock (written by the X server that owns display n), or -1.
  static pid_t lock_owner(const std::string& number) {
    std::ifstream lock("/tmp/.X" + number + "-lock");
    long pid = -1;
    if (!(lock >> pid)) return -1;
    return pid_t(pid);
  }

  bool ok() const { return !display_.empty(); }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
};

}  // namespace zz::test
