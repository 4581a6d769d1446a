#include "core/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "core/file_io.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

class AtomicFile : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("zz_atomic_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path path(const std::string& name) const { return dir_ / name; }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  static void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
  // Entries in the folder (a temporary left behind would be one more).
  size_t files() const { return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }
  fs::path dir_;
};

TEST_F(AtomicFile, ASetPublishesNothingUntilCommitted) {
  put(path("a.json"), "old a");
  put(path("b.json"), "old b");
  {
    OutputSet set;
    write_text_atomically(path("a.json"), "new a", &set);
    write_text_atomically(path("b.json"), "new b", &set);
    write_text_atomically(path("sub/c.json"), "new c", &set);  // its folder is made
    EXPECT_EQ(read(path("a.json")), "old a");
    EXPECT_EQ(read(path("b.json")), "old b");
    EXPECT_FALSE(fs::exists(path("sub/c.json")));
    set.commit();
  }
  EXPECT_EQ(read(path("a.json")), "new a");
  EXPECT_EQ(read(path("b.json")), "new b");
  EXPECT_EQ(read(path("sub/c.json")), "new c");
  EXPECT_EQ(files(), 3u);  // a, b and the folder sub: no temporary left
}

// A name at the file system's limit is valid; its temporary, 20-odd bytes longer, must
// still fit (it failed with "File name too long" after the whole render).
TEST_F(AtomicFile, NamesAtTheFileSystemsLimitAreWritten) {
  const size_t limit = name_max(dir_);
  for (size_t length : {limit, limit - 10, size_t(40)}) {
    const std::string name = std::string(length - 5, 'a') + ".json";
    write_text_atomically(path(name), "text " + std::to_string(length));
    EXPECT_EQ(read(path(name)), "text " + std::to_string(length));
    OutputSet set;  // through a set, whose temporaries live until the commit
    write_text_atomically(path(name), "set " + std::to_string(length), &set);
    set.commit();
    EXPECT_EQ(read(path(name)), "set " + std::to_string(length));
  }
  EXPECT_EQ(files(), 3u);
  // Two-byte characters to the limit (the temporary's cut falls between characters), and
  // two names alike but for their last bytes, in one set: both arrive, each with its text.
  std::string accented;
  while (accented.size() + 2 + 5 <= limit) accented += "\xc3\xa9";
  const std::string a = accented + ".json", b = accented.substr(0, accented.size() - 2) + "xy.json";
  OutputSet set;
  write_text_atomically(path(a), "a", &set);
  write_text_atomically(path(b), "b", &set);
  set.commit();
  EXPECT_EQ(read(path(a)), "a");
  EXPECT_EQ(read(path(b)), "b");
  EXPECT_EQ(files(), 5u);
}

// The form of a cut temporary's name, which the farm's cleanup of killed renders matches
// (farm/zigzag_farm/runner.py; tests/farm/test_runner.py mirrors this rule and this hash):
// "." + the stem's first bytes + "~" + FNV-1a of the target's name + ".zz-PID-RANDOM16-N.EXT",
// exactly NAME_MAX bytes.
TEST_F(AtomicFile, ACutTemporaryNameEndsWithTheTargetsHash) {
  const size_t limit = name_max(dir_);
  if (limit != 255u) GTEST_SKIP() << "the pinned name is for NAME_MAX 255, this file system has " << limit;
  const std::string name = std::string(245, 'a') + ".json";
  OutputSet set;  // its temporary lives until the commit
  write_text_atomically(path(name), "text", &set);
  std::string temporary;
  for (const auto& entry : fs::directory_iterator(dir_)) temporary = entry.path().filename().string();
  const size_t zz = temporary.find(".zz-" + std::to_string(::getpid()) + "-");
  ASSERT_NE(zz, std::string::npos) << temporary;
  EXPECT_EQ(temporary.size(), limit);
  const size_t kept = temporary.size() - (temporary.size() - zz) - 1 - 9;
  EXPECT_EQ(temporary.substr(0, 1 + kept), "." + std::string(kept, 'a'));
  EXPECT_EQ(temporary.substr(1 + kept, 9), "~ba5594dc");
  EXPECT_EQ(temporary.substr(temporary.size() - 5), ".json");
  set.commit();
  EXPECT_EQ(read(path(name)), "text");
}

TEST_F(AtomicFile, AFailedOutputLeavesEveryOutputOfItsSetAsItWas) {
  put(path("image.png"), "old image");
  {
    OutputSet set;
    write_atomically(path("image.png"), [](const fs::path& t) { put(t, "new image"); }, &set);
    write_text_atomically(path("fresh.json"), "never published", &set);
    EXPECT_THROW(write_atomically(path("stats.json"),
                                  [](const fs::path& t) {
                                    put(t, "half");
                                    throw Error("disk full");
                                  },
                                  &set),
                 Error);
    // The job gives up: no commit.
  }
  EXPECT_EQ(read(path("image.png")), "old image");
  EXPECT_FALSE(fs::exists(path("fresh.json")));
  EXPECT_FALSE(fs::exists(path("stats.json")));
  EXPECT_EQ(files(), 1u);  // the old image alone: every temporary removed
}

TEST_F(AtomicFile, WithoutASetAnOutputIsPublishedAtOnce) {
  put(path("a.txt"), "old");
  write_text_atomically(path("a.txt"), "new");
  EXPECT_EQ(read(path("a.txt")), "new");
  EXPECT_THROW(write_atomically(path("a.txt"), [](const fs::path&) { throw std::runtime_error("no"); }),
               std::runtime_error);
  EXPECT_EQ(read(path("a.txt")), "new");
  EXPECT_EQ(files(), 1u);
}

// A link chain, relative links included, leads to the file written; a dangling link to
// the file it names, to be made; a plain path is itself.
TEST_F(AtomicFile, OutputTargetFollowsLinksToTheFileWritten) {
  fs::create_directories(path("shots"));
  fs::create_symlink("shots/v1.png", path("latest.png"));
  fs::create_symlink(path("latest.png"), path("newest.png"));
  EXPECT_EQ(output_target(path("newest.png")), path("shots/v1.png"));  // dangling, via an absolute link
  EXPECT_EQ(output_target(path("plain.png")), path("plain.png"));
  write_text_atomically(path("newest.png"), "through");
  EXPECT_TRUE(fs::is_symlink(path("newest.png")));
  EXPECT_EQ(read(path("shots/v1.png")), "through");
  EXPECT_EQ(files(), 3u);  // shots, latest.png, newest.png: no temporary left
}

// Write-protected: no write bit at all refuses whoever runs (root by rm's rule, others as
// access says); an owner-writable file is not; nor is a file not there.
TEST_F(AtomicFile, AReadOnlyFileIsWriteProtectedAndRefused) {
  put(path("final.json"), "FINAL");
  EXPECT_FALSE(write_protected(path("final.json")));
  EXPECT_FALSE(write_protected(path("absent.json")));
  fs::permissions(path("final.json"), fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  EXPECT_TRUE(write_protected(path("final.json")));
  fs::create_symlink("final.json", path("link.json"));
  EXPECT_TRUE(write_protected(path("link.json")));
  EXPECT_THROW(write_text_atomically(path("link.json"), "new"), Error);
  EXPECT_EQ(read(path("final.json")), "FINAL");
  EXPECT_EQ(files(), 2u);
}

// /dev/null is a stream: written to, never renamed over (as root that would replace it).
TEST_F(AtomicFile, AStreamIsWrittenToNotReplaced) {
  EXPECT_TRUE(output_is_stream("/dev/null"));
  EXPECT_FALSE(output_is_stream(path("x.json")));
  fs::create_symlink("/dev/null", path("null.json"));
  EXPECT_TRUE(output_is_stream(path("null.json")));
  write_text_atomically(path("null.json"), "gone");
  EXPECT_TRUE(fs::is_symlink(path("null.json")));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_EQ(files(), 1u);
  // A FIFO nobody reads is an error, not a hang, and leaves no temporary.
  ASSERT_EQ(::mkfifo(path("fifo.json").c_str(), 0600), 0);
  try {
    write_text_atomically(path("fifo.json"), "lost");
    ADD_FAILURE() << "a FIFO without a reader was written";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no process is reading the pipe"), std::string::npos) << e.what();
  }
  EXPECT_EQ(files(), 2u);
}

// A job's streams are written before its files are renamed: a stream that fails (here
// /dev/full, as a --stats sent to a full device or a closed pipe) leaves the image it was
// staged after as it was (review: the image was replaced, then the job failed).
TEST_F(AtomicFile, AFailedStreamLeavesTheFilesOfItsSetAsTheyWere) {
  ASSERT_TRUE(output_is_stream("/dev/full"));
  put(path("image.png"), "old image");
  OutputSet set;
  write_atomically(path("image.png"), [](const fs::path& t) { put(t, "new image"); }, &set);
  write_text_atomically("/dev/full", "stats", &set);
  try {
    set.commit();
    ADD_FAILURE() << "/dev/full took the bytes";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read(path("image.png")), "old image");
}

}  // namespace
}  // namespace zz
