// Output patterns: placeholder expansion and the batch collision check (issue 13).
#include "app/output_paths.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/error.h"

namespace zz {
namespace {

std::string error_of(const std::vector<OutputPattern>& p, const std::vector<OutputKey>& jobs) {
  try {
    check_distinct_outputs(p, jobs);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(OutputPattern, ExpandsSceneCameraAndFrame) {
  const OutputKey k{"room", "2", 7};
  EXPECT_EQ(expand_output_pattern("out/{scene}_{camera}.png", k), "out/room_2.png");
  EXPECT_EQ(expand_output_pattern("{scene}.{frame}.exr", k), "room.7.exr");
  EXPECT_EQ(expand_output_pattern("{scene}.{frame:04}.exr", k), "room.0007.exr");
  EXPECT_EQ(expand_output_pattern("{frame:1}{frame:3}", OutputKey{"s", "0", 12345}), "1234512345");
  // Every width the syntax allows (two digits), none cut short: frames must stay apart.
  EXPECT_EQ(expand_output_pattern("{frame:70}", OutputKey{"s", "0", 12}), std::string(68, '0') + "12");
  EXPECT_NE(expand_output_pattern("{frame:99}", OutputKey{"s", "0", 3}), expand_output_pattern("{frame:99}", OutputKey{"s", "0", 7}));
  EXPECT_EQ(expand_output_pattern("plain.png", k), "plain.png");
  EXPECT_EQ(expand_output_pattern("{scene}{scene}", k), "roomroom");
}

TEST(OutputPattern, UnknownPlaceholdersAreErrorsNamingThem) {
  const OutputKey k{"room", "0", 0};
  for (const char* bad : {"{scen}.png", "{frame:x}.png", "{frame:}.png", "{scene.png", "{}.png"}) {
    try {
      expand_output_pattern(bad, k, "--stats");
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("--stats"), std::string::npos) << m;
      EXPECT_NE(m.find("unknown placeholder"), std::string::npos) << m;
    }
  }
}

// {frame:NN} takes one or two digits (README: {frame:04} zero-pads); a wider width is an
// unknown placeholder, as is one past int (no std::stoi exception escapes).
TEST(OutputPattern, FrameWidthsHaveAtMostTwoDigits) {
  const OutputKey k{"room", "0", 7};
  for (const char* bad : {"{frame:100}.png", "{frame:004}.png", "{frame:99999999999}.png"}) {
    try {
      expand_output_pattern(bad, k);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("unknown placeholder"), std::string::npos) << e.what();
    }
  }
}

TEST(OutputCollisions, NameTheMissingPlaceholder) {
  const std::vector<OutputKey> scenes = {{"room", "0", 0}, {"glass", "0", 0}};
  const std::string e = error_of({{"-o", "x.png"}}, scenes);
  EXPECT_NE(e.find("room and glass would both write x.png"), std::string::npos) << e;
  EXPECT_NE(e.find("add {scene}"), std::string::npos) << e;

  const std::vector<OutputKey> cameras = {{"room", "0", 0}, {"room", "1", 0}};
  EXPECT_NE(error_of({{"-o", "{scene}.png"}}, cameras).find("add {camera}"), std::string::npos);
  EXPECT_EQ(error_of({{"-o", "{scene}_{camera}.png"}}, cameras), "");

  // --camera all before the scene is read: its two stand-ins are not cameras the user has.
  const std::vector<OutputKey> any = {{"room", "0", 0, true}, {"room", "1", 0, true}};
  EXPECT_EQ(error_of({{"-o", "x.png"}}, any), "-o x.png: with --camera all, every camera of room would write x.png "
                                              "(add {camera})");
  // Two scene files of one name under --camera all still say so.
  const std::vector<OutputKey> twins = {{"room", "0", 0, true}, {"room", "1", 0, true}, {"room", "0", 0, true}};
  const std::string same = error_of({{"-o", "{camera}.png"}}, twins);
  EXPECT_EQ(same, "-o {camera}.png: jobs room and room would both write 0.png (their scene files have the same name)");

  const std::vector<OutputKey> frames = {{"room", "0", 1}, {"room", "0", 2}};
  EXPECT_NE(error_of({{"-o", "{scene}.png"}}, frames).find("add {frame}"), std::string::npos);
  EXPECT_EQ(error_of({{"-o", "{scene}.{frame:04}.png"}}, frames), "");
}

TEST(OutputCollisions, StatsAndAovsAreCheckedToo) {
  const std::vector<OutputKey> scenes = {{"room", "0", 0}, {"glass", "0", 0}};
  const std::string e = error_of({{"-o", "{scene}.png"}, {"--stats", "stats.json"}}, scenes);
  EXPECT_NE(e.find("--stats stats.json"), std::string::npos) << e;
  // Two kinds of output onto one file.
  const std::string same = error_of({{"-o", "{scene}.png"}, {"--aov rays", "{scene}.png"}}, scenes);
  EXPECT_NE(same.find("-o and --aov rays would both write"), std::string::npos) << same;
  // Same stem from two folders: every placeholder is there, the names collide.
  const std::string stems = error_of({{"-o", "{scene}.png"}}, {{"room", "0", 0}, {"room", "0", 0}});
  EXPECT_NE(stems.find("same name"), std::string::npos) << stems;
  // Equal after normalisation.
  EXPECT_NE(error_of({{"-o", "a/./x.png"}, {"--stats", "a/x.png"}}, {{"room", "0", 0}}), "");
}

// One file under two spellings the text does not show: an absolute path and a relative
// one, a symbolic link to the folder. Both would be renamed into place, the last one winning.
TEST(OutputCollisions, SameFileByAbsolutePathOrLink) {
  namespace fs = std::filesystem;
  const std::vector<OutputKey> job = {{"room", "0", 0}};
  const std::string absolute = error_of({{"-o", (fs::current_path() / "x.png").string()}, {"--aov rays", "x.png"}}, job);
  EXPECT_NE(absolute.find("-o and --aov rays would both write"), std::string::npos) << absolute;

  const fs::path dir = fs::temp_directory_path() / ("zz_outputs_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::create_directory_symlink(dir, dir / "here");
  const std::string linked =
      error_of({{"-o", (dir / "here" / "z.png").string()}, {"--stats", (dir / "z.png").string()}}, job);
  EXPECT_NE(linked.find("-o and --stats would both write"), std::string::npos) << linked;
  // Not yet existing folders under the link resolve too.
  EXPECT_NE(error_of({{"-o", (dir / "here" / "new" / "z.png").string()}, {"--stats", (dir / "new" / "z.png").string()}}, job), "");
  EXPECT_EQ(error_of({{"-o", (dir / "here" / "z.png").string()}, {"--stats", (dir / "z.json").string()}}, job), "");
  // "link/.." is the link's target's parent, not the folder the text shows.
  fs::create_directories(dir / "deep" / "er");
  fs::create_directory_symlink(dir / "deep" / "er", dir / "short");
  EXPECT_NE(error_of({{"-o", (dir / "short" / ".." / "q.png").string()}, {"--stats", (dir / "deep" / "q.png").string()}}, job), "");
  // An output that is a link is written through (its target replaced, as cp and a shell's
  // > do): a link and its target, existing or not, are one file.
  fs::create_symlink(dir / "frame.png", dir / "latest.png");
  const std::string through =
      error_of({{"-o", (dir / "latest.png").string()}, {"--aov rays", (dir / "frame.png").string()}}, job);
  EXPECT_NE(through.find("-o and --aov rays would both write"), std::string::npos) << through;
  fs::create_symlink("latest.png", dir / "newest.png");  // relative, and a link to a link
  EXPECT_NE(error_of({{"-o", (dir / "newest.png").string()}, {"--aov rays", (dir / "frame.png").string()}}, job), "");
  fs::remove_all(dir);
}

// One file under two names (glass.png a link to room.png) is named as such, not blamed on
// two scenes of one name (exploratory testing).
TEST(OutputCollisions, OneFileUnderTwoJobsNamesIsSaidToBeOne) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("zz_two_names_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::create_symlink("room.png", dir / "glass.png");
  const std::string pattern = (dir / "{scene}.png").string();
  EXPECT_EQ(error_of({{"-o", pattern}}, {{"room", "0", 0}, {"glass", "0", 0}}),
            "-o " + pattern + ": jobs room and glass would write one file, " + (dir / "room.png").string() + " and " +
                (dir / "glass.png").string() + " being the same file");
  fs::remove_all(dir);
}

// A file cannot also be a folder: an output inside another was refused only by the write
// after the render (exploratory testing: `--dry-run` passed it, the run failed at the end).
TEST(OutputCollisions, AnOutputInsideAnotherIsRefused) {
  const std::vector<OutputKey> one = {{"room", "0", 0}};
  EXPECT_EQ(error_of({{"-o", "out/a.png"}, {"--stats", "out/a.png/s.json"}}, one),
            "-o out/a.png and --stats out/a.png/s.json: the one would have to be a folder holding the other");
  EXPECT_NE(error_of({{"--aov rays", "out/x/../a.png/b/c.png"}, {"-o", "out/a.png"}}, one), "");  // deeper, either order
  // Across jobs: glass's stats inside room's image.
  const std::vector<OutputKey> two = {{"room", "0", 0}, {"glass", "0", 0}};
  EXPECT_NE(error_of({{"-o", "{scene}.png"}, {"--stats", "room.png/{scene}.json"}}, two), "");
  // A name that merely starts with another's is its sibling.
  EXPECT_EQ(error_of({{"-o", "out/a.png"}, {"--stats", "out/a.png2/s.json"}, {"--aov rays", "out/a/b.png"}}, one), "");
  // Claimed as jobs start (their real cameras known), both ways round.
  OutputClaims claims;
  claims.claim({{"-o", "c/a.png"}}, two[0], "job room");
  EXPECT_THROW(claims.claim({{"--stats", "c/a.png/s.json"}}, two[1], "job glass"), UsageError);
  claims.claim({{"--stats", "d/e/s.json"}}, two[1], "job glass");
  EXPECT_THROW(claims.claim({{"-o", "d"}}, two[0], "job room"), UsageError);
  EXPECT_NO_THROW(claims.claim({{"-o", "d/e2.png"}, {"--stats", "c/a.png2"}}, two[0], "job room"));
}

// A stream is written to, not replaced: a batch may send every job's stats to /dev/null
// or /dev/stdout (review: "would both write /dev/null (add {scene})").
TEST(OutputCollisions, JobsMayShareAStream) {
  const std::vector<OutputKey> scenes = {{"room", "0", 0}, {"glass", "0", 0}};
  EXPECT_EQ(error_of({{"-o", "{scene}.png"}, {"--stats", "/dev/null"}}, scenes), "");
  EXPECT_EQ(error_of({{"-o", "{scene}.png"}, {"--stats", "/dev/stdout"}}, scenes), "");
  // Two outputs of one job would mix their bytes in it.
  const std::string mixed = error_of({{"--stats", "/dev/stdout"}, {"--aov rays", "/dev/stdout"}}, scenes);
  EXPECT_NE(mixed.find("--stats and --aov rays would both write /dev/stdout"), std::string::npos) << mixed;
  OutputClaims claims;
  EXPECT_NO_THROW(claims.claim({{"--stats", "/dev/null"}}, scenes[0], "job room"));
  EXPECT_NO_THROW(claims.claim({{"--stats", "/dev/null"}}, scenes[1], "job glass"));
}

// One stream under two names is still one: a link to a FIFO (as /dev/stdout is to the
// shell's pipe) and the FIFO would get both outputs' bytes, one after the other.
TEST(OutputCollisions, OneStreamUnderTwoNamesIsOneStream) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("zz_fifo_" + std::to_string(::getpid()));
  fs::remove_all(dir);  // one an earlier run of this pid left
  fs::create_directories(dir);
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  fs::create_symlink("pipe", dir / "link");
  const std::vector<OutputKey> one = {{"room", "0", 0}};
  const std::string pipe = (dir / "pipe").string(), link = (dir / "link").string();
  const std::string mixed = error_of({{"-o", pipe + ".png"}, {"--stats", pipe}, {"--aov rays", link}}, one);
  EXPECT_EQ(mixed, "--stats " + pipe + " and --aov rays " + link + " are one stream: their bytes would mix in it");
  EXPECT_EQ(output_identity(link), output_identity(pipe));
  EXPECT_EQ(output_identity(link).string().rfind("stream ", 0), 0u);
  // Jobs one after another may still share it, by either name.
  EXPECT_EQ(error_of({{"--stats", "{scene}"}}, {{pipe, "0", 0}, {link, "0", 0}}), "");
  EXPECT_EQ(error_of({{"--stats", pipe}, {"--aov rays", "/dev/null"}}, one), "");  // two streams
  fs::remove_all(dir);
}

// Links that loop name no file: the output is refused before the render, where the
// loop's first link used to be replaced by the image (review).
TEST(OutputPreflight, ALoopOfLinksIsRefused) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("zz_loop_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::create_symlink("l2.png", dir / "l1.png");
  fs::create_symlink("l1.png", dir / "l2.png");
  try {
    preflight_output("-o", dir / "l1.png", true);
    ADD_FAILURE() << "a loop of links was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("symbolic links form a loop"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_symlink(dir / "l1.png"));
  fs::create_symlink("target.png", dir / "fine.png");  // a link to a file yet to be written is fine
  EXPECT_NO_THROW(preflight_output("-o", dir / "fine.png", true));
  fs::remove_all(dir);
}

TEST(OutputCollisions, DistinctBatchesPass) {
  EXPECT_EQ(error_of({{"-o", "out/{scene}_{camera}.png"}, {"--stats", "out/{scene}_{camera}.json"}},
                     {{"room", "0", 0}, {"room", "1", 0}, {"glass", "0", 0}}),
            "");
}

}  // namespace
}  // namespace zz
