#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace zz {

namespace {

namespace fs = std::filesystem;

// Temporaries being written, in fixed slots a signal handler can read without locks or
// allocation. state: 0 free, 1 being filled in, 2 holds a path to remove.
struct TemporarySlot {
  std::atomic<int> state{0};
  char path[4096];
};
std::array<TemporarySlot, 32> g_slots;

class RegisteredTemporary {
 public:
  explicit RegisteredTemporary(const fs::path& path) {
    const std::string s = path.string();
    if (s.size() >= sizeof(TemporarySlot::path)) return;  // not removable by a signal; still atomic
    for (TemporarySlot& slot : g_slots) {
      int expected = 0;
      if (!slot.state.compare_exchange_strong(expected, 1)) continue;
      std::memcpy(slot.path, s.c_str(), s.size() + 1);
      slot.state.store(2);
      slot_ = &slot;
      return;
    }
  }
  ~RegisteredTemporary() {
    if (slot_) slot_->state.store(0);
  }
  RegisteredTemporary(const RegisteredTemporary&) = delete;
  RegisteredTemporary& operator=(const RegisteredTemporary&) = delete;

 private:
  TemporarySlot* slot_ = nullptr;
};

fs::path temporary_for(const fs::path& target) {
  static std::atomic<unsigned> serial{0};
  // ".NAME.zz-PID-N.EXT": hidden, unique per process and call, and with the target's
  // extension so that OpenImageIO picks the same format.
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict, PR 105329) on "." + string.
  std::string name = ".";
  name += target.stem().string();
  name += ".zz-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(serial++);
  name += target.extension().string();
  return target.parent_path() / name;
}

std::string errno_text() { return std::strerror(errno); }

void sync_file(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error("cannot write " + path.string() + ": " + errno_text());
  const bool ok = ::fsync(fd) == 0;
  const std::string why = ok ? "" : errno_text();
  ::close(fd);
  if (!ok) throw Error("cannot write " + path.string() + ": " + why);
}

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the rename happened; durability of the entry is best effort
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path dir = target.parent_path();
  std::error_code ec;
  if (!dir.empty()) {
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create directory " + dir.string() + ": " + ec.message());
  }
  const fs::path temporary = temporary_for(target);
  RegisteredTemporary registered(temporary);
  try {
    write(temporary);
    sync_file(temporary);
    if (::rename(temporary.c_str(), target.c_str()) != 0)
      throw Error("cannot write " + target.string() + ": " + errno_text());
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  sync_directory(dir);
}

void write_text_atomically(const fs::path& target, const std::string& text) {
  write_atomically(target, [&](const fs::path& temporary) {
    std::ofstream f(temporary, std::ios::binary);
    f << text;
    f.flush();
    if (!f) throw Error("cannot write " + target.string());
  });
}

void remove_temporaries_from_signal_handler() {
  for (TemporarySlot& slot : g_slots)
    if (slot.state.load() == 2) ::unlink(slot.path);
}

}  // namespace zz
