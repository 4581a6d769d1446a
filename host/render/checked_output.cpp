#include "render/checked_output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/file_io.h"

namespace zz {

CheckedFileOutput::CheckedFileOutput(const std::filesystem::path& path) : IOProxy(path.string(), Write) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) fail(std::strerror(errno));
}

CheckedFileOutput::~CheckedFileOutput() { close(); }

void CheckedFileOutput::fail(const std::string& why) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (failure_.empty()) failure_ = why;
}

std::string CheckedFileOutput::failure() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failure_;
}

void CheckedFileOutput::close() {
  if (fd_ >= 0 && ::close(fd_) != 0) fail(std::strerror(errno));  // NFS reports some write errors here
  fd_ = -1;
  m_mode = Closed;
}

bool CheckedFileOutput::seek(int64_t offset) {
  if (offset < 0) return false;
  m_pos = offset;
  return true;
}

size_t CheckedFileOutput::read(void* buf, size_t size) {
  const size_t n = pread(buf, size, m_pos);
  m_pos += int64_t(n);
  return n;
}

size_t CheckedFileOutput::write(const void* buf, size_t size) {
  const size_t n = pwrite(buf, size, m_pos);
  m_pos += int64_t(n);
  return n;
}

size_t CheckedFileOutput::pread(void* buf, size_t size, int64_t offset) {
  char* p = static_cast<char*>(buf);
  size_t done = 0;
  while (fd_ >= 0 && done < size) {
    const ssize_t n = ::pread(fd_, p + done, size - done, off_t(offset) + off_t(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += size_t(n);
  }
  return done;
}

// Reports the whole buffer written, whatever happened: a writer that saw a short write
// might exit the process (libjpeg) or carry on regardless (PNG); failure() tells.
size_t CheckedFileOutput::pwrite(const void* buf, size_t size, int64_t offset) {
  std::string why;
  if (fd_ < 0) fail("the file is not open");
  else if (!pwrite_all(fd_, buf, size, offset, &why)) fail(why);
  return size;
}

size_t CheckedFileOutput::size() const {
  struct stat st;
  if (fd_ < 0 || ::fstat(fd_, &st) != 0) return 0;
  return size_t(st.st_size);
}

}  // namespace zz
