#include "core/atomic_file.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <vector>

#include "core/error.h"
#include "core/file_io.h"
#include "core/interrupt.h"

namespace zz {

namespace {

namespace fs = std::filesystem;

}  // namespace

std::string random_token() {
  uint64_t r = 0;
  if (::getrandom(&r, sizeof r, GRND_NONBLOCK) != ssize_t(sizeof r)) {
    static std::atomic<uint64_t> fallback{0x9e3779b97f4a7c15ull};  // no entropy yet: time and address
    r = fallback.fetch_add(0x9e3779b97f4a7c15ull) ^ uint64_t(::time(nullptr)) ^ uint64_t(reinterpret_cast<uintptr_t>(&r));
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(r));
  return hex;
}

namespace {

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

fs::path temporary_name(const fs::path& target) {
  static std::atomic<unsigned> serial{0};
  // ".NAME.zz-PID-RANDOM-N.EXT": hidden, with the target's extension so that OpenImageIO
  // picks the same format. The PID alone is not unique: two containers (each its own PID
  // 1) writing one shared output truncated each other's temporary; 64 random bits are.
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict, PR 105329) on "." + string.
  std::string suffix = ".zz-";
  suffix += std::to_string(::getpid());
  suffix += '-';
  suffix += random_token();
  suffix += '-';
  suffix += std::to_string(serial++);
  suffix += target.extension().string();
  // The stem is cut where the name would pass the file system's limit (a 250-byte target
  // name is valid, its temporary's with 20 more bytes is not): at a UTF-8 character's start,
  // with a hash of the whole name in place of the cut part, so that targets alike in their
  // first 200-odd bytes keep apart beyond the PID (processes in other PID namespaces).
  const size_t limit = name_max(target.parent_path());
  std::string stem = target.stem().string();
  if (1 + stem.size() + suffix.size() > limit) {
    uint32_t hash = 2166136261u;  // FNV-1a of the target's file name
    for (unsigned char c : target.filename().string()) hash = (hash ^ c) * 16777619u;
    char tag[10];
    std::snprintf(tag, sizeof tag, "~%08x", hash);
    size_t keep = limit > 1 + suffix.size() + 9 ? limit - 1 - suffix.size() - 9 : 0;
    while (keep > 0 && (static_cast<unsigned char>(stem[keep]) & 0xC0) == 0x80) --keep;  // not inside a character
    stem.resize(keep);
    stem += tag;
  }
  std::string name = ".";
  name += stem;
  name += suffix;
  return target.parent_path() / name;
}

std::string errno_text() { return std::strerror(errno); }

// Copies the finished temporary's bytes into the stream `target` names.
void copy_to_stream(const fs::path& temporary, const fs::path& target) {
  std::string why;
  std::vector<unsigned char> bytes;
  if (!read_regular_file(temporary.string(), UINTMAX_MAX, &bytes, &why))
    throw Error("cannot write " + target.string() + ": " + why);
  // One of our own descriptors: written through, after what stdio holds for it.
  const std::optional<int> own = own_descriptor(target);
  if (own) std::fflush(nullptr);
  // Else a non-blocking open: a FIFO nobody reads fails (ENXIO) instead of hanging the run;
  // the writes then block as a shell's > does while the reader catches up.
  const FileDescriptor opened(own ? -1 : ::open(target.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC));
  const int out = own ? *own : opened.fd;
  if (out < 0)
    throw Error("cannot write " + target.string() + ": " +
                (errno == ENXIO ? std::string("no process is reading the pipe") : errno_text()));
  if (!own) ::fcntl(out, F_SETFL, ::fcntl(out, F_GETFL) & ~O_NONBLOCK);
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(out, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {  // an inherited descriptor left non-blocking
      pollfd ready{out, POLLOUT, 0};
      ::poll(&ready, 1, -1);
      continue;
    }
    if (n <= 0) throw Error("cannot write " + target.string() + ": " + (n < 0 ? errno_text() : "nothing written"));
    done += size_t(n);
  }
}

// Creates `temporary` empty, with O_EXCL: never another writer's file. `mode` 0600 while
// it will replace a file (whose mode it takes once written: take_mode), else 0666 less
// the umask, as any created file.
void create_temporary(const fs::path& temporary, const fs::path& target, mode_t mode) {
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  if (fd < 0) throw Error("cannot write " + target.string() + ": " + errno_text());
  ::close(fd);
}

// The replaced file's group (best effort: if ours to give) and permission bits, not its
// setuid, setgid or sticky bits: set last, when nothing opens the temporary any more (a
// 0444 image is replaced by a 0444 one, a 0600 one was never readable by others).
void take_mode(const fs::path& temporary, const struct stat& old) {
  (void)::chown(temporary.c_str(), uid_t(-1), old.st_gid);
  (void)::chmod(temporary.c_str(), old.st_mode & 0777);
}

void sync_file(const fs::path& path, const fs::path& target) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error("cannot write " + target.string() + ": " + errno_text());
  const bool ok = ::fsync(fd) == 0;
  const std::string why = ok ? "" : errno_text();
  ::close(fd);
  if (!ok) throw Error("cannot write " + target.string() + ": " + why);
}

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the rename happened; durability of the entry is best effort
  ::fsync(fd);
  ::close(fd);
}

// `path`, then each name its symbolic links lead to in turn (at most 40 followed: the
// kernel's own limit); the last is what gets written.
std::vector<fs::path> link_chain(const fs::path& path) {
  std::vector<fs::path> chain{path};
  std::error_code ec;
  for (int hops = 0; hops < 40 && fs::is_symlink(chain.back(), ec); ++hops) {
    const fs::path to = fs::read_symlink(chain.back(), ec);
    if (ec) break;
    chain.push_back(to.is_absolute() ? to : chain.back().parent_path() / to);
  }
  return chain;
}

}  // namespace

fs::path output_target(const fs::path& path) { return link_chain(path).back(); }

bool write_protected(const fs::path& target) {
  struct stat st {};
  const fs::path real = output_target(target);
  if (::stat(real.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  if (::geteuid() == 0) return (st.st_mode & 0222) == 0;
  return ::faccessat(AT_FDCWD, real.c_str(), W_OK, AT_EACCESS) != 0 && errno == EACCES;
}

std::optional<int> own_descriptor(const fs::path& target) {
  const auto descriptor = [](const std::string& name, const std::string& folder) -> std::optional<int> {
    if (name.size() <= folder.size() || name.size() > folder.size() + 9 || name.compare(0, folder.size(), folder) != 0 ||
        !std::all_of(name.begin() + ptrdiff_t(folder.size()), name.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return std::nullopt;
    return std::stoi(name.substr(folder.size()));
  };
  std::error_code ec;
  const std::string mine = "/proc/" + std::to_string(::getpid()) + "/fd/";
  for (const fs::path& p : link_chain(target)) {  // each name along the links, as output_target follows them
    const std::string name = fs::absolute(p, ec).lexically_normal().string();
    std::optional<int> fd = name == "/dev/stdout" ? 1 : name == "/dev/stderr" ? 2 : std::optional<int>();
    for (const std::string& folder : {std::string("/dev/fd/"), std::string("/proc/self/fd/"), mine})
      if (!fd) fd = descriptor(name, folder);
    if (fd) {  // open, and for writing
      const int flags = ::fcntl(*fd, F_GETFL);
      return flags >= 0 && (flags & O_ACCMODE) != O_RDONLY ? fd : std::nullopt;
    }
  }
  return std::nullopt;
}

std::optional<std::string> stream_identity(const fs::path& target) {
  struct stat st {};  // stat follows every link, /proc/self/fd's to pipes too (not paths read_symlink can follow)
  if (const std::optional<int> fd = own_descriptor(target)) {
    if (::fstat(*fd, &st) != 0) return std::nullopt;
  } else if (::stat(target.c_str(), &st) != 0 || !(S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode) || S_ISSOCK(st.st_mode))) {
    return std::nullopt;
  }
  return "stream " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
}

bool output_is_stream(const fs::path& target) { return stream_identity(target).has_value(); }

struct OutputSet::Staged {
  fs::path target, temporary;
  bool stream;  // target is a device or pipe: it receives the temporary's bytes
  RegisteredTemporary registered;
  Staged(fs::path t, fs::path tmp, bool s)
      : target(std::move(t)), temporary(std::move(tmp)), stream(s), registered(temporary) {}
};

OutputSet::OutputSet() = default;

OutputSet::~OutputSet() {
  std::error_code ec;
  for (const auto& s : staged_) fs::remove(s->temporary, ec);
}

void OutputSet::stage(const fs::path& given, const std::function<void(const fs::path&)>& write) {
  const bool stream = output_is_stream(given);
  const fs::path target = stream ? given : output_target(given);
  const fs::path dir = target.parent_path();
  std::error_code ec;
  if (!dir.empty() && !stream) {
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create directory " + dir.string() + ": " + ec.message());
  }
  if (!stream && write_protected(target))  // a stream is written into, never replaced
    throw Error("cannot write " + given.string() + ": the file is write-protected (make it writable to replace it)");
  struct stat old {};
  const bool replaces = !stream && ::stat(target.c_str(), &old) == 0 && S_ISREG(old.st_mode);
  // A stream's temporary goes where temporaries go: /dev is no place for one.
  const fs::path temporary = temporary_name(stream ? fs::temp_directory_path(ec) / given.filename() : target);
  // Registered for a signal's clean-up before the file exists: no moment leaves it behind.
  auto staged = std::make_unique<Staged>(target, temporary, stream);
  bool created = false;  // a name taken by another process is not ours to remove
  try {
    create_temporary(staged->temporary, target, replaces ? 0600 : 0666);
    created = true;
    write(staged->temporary);
    sync_file(staged->temporary, target);
    if (replaces) take_mode(staged->temporary, old);
  } catch (...) {
    if (created) fs::remove(staged->temporary, ec);
    throw;
  }
  staged_.push_back(std::move(staged));
}

void OutputSet::commit() {
  // Streams first: writing to a pipe or device can fail (no reader, a full /dev/full, a
  // closed pipe), a rename hardly ever, and a failed stream must leave the files unreplaced.
  std::stable_partition(staged_.begin(), staged_.end(), [](const auto& s) { return s->stream; });
  std::vector<fs::path> dirs;
  {
    const CancellableScope publishing;  // a first SIGINT / SIGTERM waits for every rename
    while (!staged_.empty()) {
      const Staged& s = *staged_.front();
      if (s.stream) {
        copy_to_stream(s.temporary, s.target);
        std::error_code ec;
        fs::remove(s.temporary, ec);
      } else {
        if (::rename(s.temporary.c_str(), s.target.c_str()) != 0)
          throw Error("cannot write " + s.target.string() + ": " + errno_text());
        if (std::find(dirs.begin(), dirs.end(), s.target.parent_path()) == dirs.end())
          dirs.push_back(s.target.parent_path());
      }
      staged_.erase(staged_.begin());
    }
  }
  for (const fs::path& dir : dirs) sync_directory(dir);
  throw_if_interrupted();  // every output published: now the signal ends the run
}

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write, OutputSet* set) {
  if (set) return set->stage(target, write);
  OutputSet one;
  one.stage(target, write);
  one.commit();
}

void write_text_atomically(const fs::path& target, const std::string& text, OutputSet* set) {
  write_atomically(
      target,
      [&](const fs::path& temporary) {
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        if (fd < 0) throw Error("cannot write " + target.string() + ": " + errno_text());
        std::string why;
        if (!pwrite_all(fd, text.data(), text.size(), 0, &why)) {
          ::close(fd);
          throw Error("cannot write " + target.string() + ": " + why);
        }
        if (::close(fd) != 0) throw Error("cannot write " + target.string() + ": " + errno_text());
      },
      set);
}

void remove_temporaries_from_signal_handler() {
  for (TemporarySlot& slot : g_slots)
    if (slot.state.load() == 2) ::unlink(slot.path);
}

}  // namespace zz
