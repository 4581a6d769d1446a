#include "core/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "../scratch_dir.h"

namespace zz {
namespace {

using FileIo = test::ScratchDirTest;

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST_F(FileIo, ReadsARegularFileWhole) {
  const std::string text("glTF\0binary\n", 12);
  write_bytes(dir / "a.bin", text);
  const std::vector<unsigned char> bytes = read_regular_file((dir / "a.bin").string(), 12);
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), text);
  write_bytes(dir / "empty", "");
  EXPECT_TRUE(read_regular_file((dir / "empty").string(), 0).empty());
}

// Each failure says why, after the file's name: the scene readers print these as they are.
TEST_F(FileIo, FailuresSayWhy) {
  auto why_not = [](const std::string& path, uintmax_t max_bytes) {
    std::vector<unsigned char> bytes;
    std::string why;
    EXPECT_FALSE(read_regular_file(path, max_bytes, &bytes, &why)) << path;
    return why;
  };
  EXPECT_EQ(why_not((dir / "missing").string(), 100), "cannot open (No such file or directory)");
  EXPECT_EQ(why_not("/dev/zero", 100), "not a regular file");  // would never end
  std::string why;  // the same reasons without reading
  EXPECT_FALSE(readable_regular_file("/dev/zero", 100, &why));
  EXPECT_EQ(why, "not a regular file");
  EXPECT_FALSE(readable_regular_file((dir / "missing").string(), 100, &why));
  EXPECT_EQ(why, "cannot open (No such file or directory)");
  EXPECT_EQ(why_not(dir.string(), 100), "not a regular file");
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  EXPECT_EQ(why_not((dir / "pipe").string(), 100), "not a regular file");  // opened without waiting for a writer
  write_bytes(dir / "big", std::string(65, 'x'));
  EXPECT_EQ(why_not((dir / "big").string(), 64), "larger than 64 bytes");
  EXPECT_EQ(read_regular_file((dir / "big").string(), 65).size(), 65u);  // the limit itself is allowed
  EXPECT_TRUE(readable_regular_file((dir / "big").string(), 65, &why));
  EXPECT_FALSE(readable_regular_file((dir / "big").string(), 64, &why));
  EXPECT_EQ(why, "larger than 64 bytes");
  try {
    read_regular_file((dir / "big").string(), uintmax_t(1) << 5);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "big").string() + ": larger than 32 bytes");
  }
}

TEST(FileIoText, ExtensionsInLowerCase) {
  EXPECT_EQ(lowercase_extension("a/b/Shot.PNG"), ".png");
  EXPECT_EQ(lowercase_extension("scene.GlTf"), ".gltf");
  EXPECT_EQ(lowercase_extension("archive.tar.GZ"), ".gz");
  EXPECT_EQ(lowercase_extension("noext"), "");
  EXPECT_EQ(lowercase_extension(".hidden"), "");
}

TEST(FileIoText, LimitsReadAsUsersWriteThem) {
  EXPECT_EQ(byte_size_text(uintmax_t(1) << 32), "4 GiB");
  EXPECT_EQ(byte_size_text(uintmax_t(64) << 20), "64 MiB");
  EXPECT_EQ(byte_size_text((uintmax_t(64) << 20) + 1), "67108865 bytes");
  EXPECT_EQ(byte_size_text(1000), "1000 bytes");
}

TEST_F(FileIo, WritesEverythingAtTheOffsetOrSaysWhy) {
  const std::string path = (dir / "out").string();
  const FileDescriptor file(::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0666));
  ASSERT_GE(file.fd, 0);
  std::string why;
  const std::string big(1 << 20, 'a');  // more than one write may take
  ASSERT_TRUE(pwrite_all(file.fd, big.data(), big.size(), 0, &why)) << why;
  ASSERT_TRUE(pwrite_all(file.fd, "bc", 2, 1, &why)) << why;
  const std::vector<unsigned char> back = read_regular_file(path, 1 << 21);
  ASSERT_EQ(back.size(), big.size());
  EXPECT_EQ(std::string(back.begin(), back.begin() + 4), "abca");

  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const FileDescriptor read_end(pipe_fds[0]), write_end(pipe_fds[1]);
  EXPECT_FALSE(pwrite_all(write_end.fd, "x", 1, 0, &why));  // a pipe has no offsets
  EXPECT_EQ(why, "Illegal seek");
}

}  // namespace
}  // namespace zz
