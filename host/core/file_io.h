// Whole-file reads and writes through descriptors, with a reason for every failure: the
// scene readers and the output writers share them, so "Permission denied", a device given
// as a file, a short write on a full disk and EINTR are handled one way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace zz {

// A descriptor closed however its scope is left.
struct FileDescriptor {
  int fd;
  explicit FileDescriptor(int f) : fd(f) {}
  ~FileDescriptor();
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
};

// Reads a regular file whole. A device, pipe or folder is refused ("not a regular file":
// /dev/zero would never end), as is a file over max_bytes ("larger than 64 MiB"). On
// failure returns false and sets *why ("cannot open (Permission denied)" for errno's).
bool read_regular_file(const std::string& path, uintmax_t max_bytes, std::vector<unsigned char>* out,
                       std::string* why);

// The same, or zz::Error "PATH: WHY".
std::vector<unsigned char> read_regular_file(const std::string& path, uintmax_t max_bytes);

// Whether read_regular_file could open `path`, without reading it: false and *why as it
// would give them (a reason after a reader that does not say why it failed).
bool readable_regular_file(const std::string& path, uintmax_t max_bytes, std::string* why);

// Writes all `size` bytes at `offset`, retrying short writes and EINTR. On failure returns
// false and sets *why ("No space left on device", "File too large").
bool pwrite_all(int fd, const void* data, size_t size, int64_t offset, std::string* why);

// The file name's extension in lower case (".PNG" -> ".png"), as formats are chosen by it.
std::string lowercase_extension(const std::filesystem::path& path);

// The longest file name (bytes) the file system of `dir` takes: pathconf's NAME_MAX, 255
// where it does not say (or `dir` does not exist yet).
size_t name_max(const std::filesystem::path& dir);

// "4 GiB", "64 MiB", "1000 bytes": a limit as error messages state it.
std::string byte_size_text(uintmax_t bytes);

}  // namespace zz
