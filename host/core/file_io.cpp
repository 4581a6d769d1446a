#include "core/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.h"

namespace zz {

FileDescriptor::~FileDescriptor() {
  if (fd >= 0) ::close(fd);
}

size_t name_max(const std::filesystem::path& dir) {
  const long n = ::pathconf(dir.empty() ? "." : dir.c_str(), _PC_NAME_MAX);
  return n > 0 ? size_t(n) : 255;
}

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

std::string byte_size_text(uintmax_t bytes) {
  constexpr uintmax_t kMiB = uintmax_t(1) << 20, kGiB = uintmax_t(1) << 30;
  if (bytes >= kGiB && bytes % kGiB == 0) return std::to_string(bytes / kGiB) + " GiB";
  if (bytes >= kMiB && bytes % kMiB == 0) return std::to_string(bytes / kMiB) + " MiB";
  return std::to_string(bytes) + " bytes";
}

namespace {

std::string errno_reason(const char* what) { return std::string(what) + " (" + std::strerror(errno) + ")"; }

// Opens `path` if it is a regular file of at most max_bytes: its descriptor and size, or -1
// and *why.
int open_regular(const std::string& path, uintmax_t max_bytes, size_t* size, std::string* why) {
  // O_NONBLOCK: opening a named pipe would wait for a writer; fstat then refuses it.
  FileDescriptor file(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK));
  struct stat st {};
  if (file.fd < 0) *why = errno_reason("cannot open");
  else if (::fstat(file.fd, &st) != 0) *why = errno_reason("cannot read");
  else if (!S_ISREG(st.st_mode)) *why = "not a regular file";
  else if (uintmax_t(st.st_size) > max_bytes) *why = "larger than " + byte_size_text(max_bytes);
  else {
    *size = size_t(st.st_size);
    return std::exchange(file.fd, -1);
  }
  return -1;
}

}  // namespace

bool readable_regular_file(const std::string& path, uintmax_t max_bytes, std::string* why) {
  size_t size = 0;
  return FileDescriptor(open_regular(path, max_bytes, &size, why)).fd >= 0;
}

bool read_regular_file(const std::string& path, uintmax_t max_bytes, std::vector<unsigned char>* out,
                       std::string* why) {
  size_t size = 0;
  const FileDescriptor file(open_regular(path, max_bytes, &size, why));
  if (file.fd < 0) return false;
  out->resize(size);
  size_t done = 0;
  while (done < out->size()) {
    const ssize_t n = ::read(file.fd, out->data() + done, out->size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      *why = n < 0 ? errno_reason("cannot read") : "the file shrank while being read";
      return false;
    }
    done += size_t(n);
  }
  return true;
}

std::vector<unsigned char> read_regular_file(const std::string& path, uintmax_t max_bytes) {
  std::vector<unsigned char> bytes;
  std::string why;
  if (!read_regular_file(path, max_bytes, &bytes, &why)) throw Error(path + ": " + why);
  return bytes;
}

bool pwrite_all(int fd, const void* data, size_t size, int64_t offset, std::string* why) {
  const char* p = static_cast<const char*>(data);
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pwrite(fd, p + done, size - done, off_t(offset) + off_t(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      *why = n < 0 ? std::strerror(errno) : "nothing was written";
      return false;
    }
    done += size_t(n);
  }
  return true;
}

}  // namespace zz
