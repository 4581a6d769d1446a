// The fingerprint of a scene's files (scene/scene_files.h).
#include "scene/scene_files.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "gltf_fixture.h"

namespace zz {
namespace {

TEST(FilesFingerprint, FollowsTheBytesNotThePaths) {
  const auto dir = test::temp_dir("fingerprint");
  auto file = [&](const char* name, const std::string& text) {
    test::write_text(dir / name, text);
    return (dir / name).string();
  };
  const std::string a = file("a", "ab"), b = file("b", "c"), a2 = file("a2", "a"), b2 = file("b2", "bc");
  const std::string print = files_fingerprint({a, b});
  EXPECT_EQ(print.size(), 16u);
  EXPECT_EQ(files_fingerprint({file("copy_a", "ab"), file("copy_b", "c")}), print);  // another folder's copy
  EXPECT_NE(files_fingerprint({a2, b2}), print);  // "a" + "bc" is not "ab" + "c"
  EXPECT_NE(files_fingerprint({b, a}), print);    // the order counts
  EXPECT_NE(files_fingerprint({a, file("b3", "d")}), print);
  EXPECT_NE(files_fingerprint({}), print);
  // Past the 1 MiB chunk: a change at the very end still counts.
  std::string big(3u << 19, 'x');
  const std::string first = files_fingerprint({file("big", big)});
  big.back() = 'y';
  EXPECT_NE(files_fingerprint({file("big", big)}), first);
  EXPECT_THROW(files_fingerprint({(dir / "missing").string()}), Error);
}

}  // namespace
}  // namespace zz
