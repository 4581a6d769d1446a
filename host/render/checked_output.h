// An OpenImageIO output proxy (Filesystem::IOProxy) that writes a file through its
// descriptor and remembers the first write that failed. OpenImageIO's PNG writer does not
// check its writes (a full disk gave a truncated PNG and success), and libjpeg's exits the
// process on one: this proxy tells the writers every write succeeded and tells us the truth.
#pragma once

#include <OpenImageIO/filesystem.h>

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>

namespace zz {

class CheckedFileOutput final : public OIIO::Filesystem::IOProxy {
 public:
  explicit CheckedFileOutput(const std::filesystem::path& path);  // created or truncated
  ~CheckedFileOutput() override;
  CheckedFileOutput(const CheckedFileOutput&) = delete;
  CheckedFileOutput& operator=(const CheckedFileOutput&) = delete;

  const char* proxytype() const override { return "zigzag-checked-file"; }
  void close() override;
  bool seek(int64_t offset) override;
  size_t read(void* buf, size_t size) override;
  size_t write(const void* buf, size_t size) override;
  size_t pread(void* buf, size_t size, int64_t offset) override;
  size_t pwrite(const void* buf, size_t size, int64_t offset) override;
  size_t size() const override;

  // Empty while every open, write and the close succeeded; else why the first did not.
  std::string failure() const;

 private:
  void fail(const std::string& why);

  int fd_ = -1;
  mutable std::mutex mutex_;  // pwrite is called from several threads by some writers
  std::string failure_;
};

}  // namespace zz
