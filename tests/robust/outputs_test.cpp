// Issue 13, one black-box case per row: outputs are never lost or corrupt, and bad
// invocations fail before the render with a message naming the real problem.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "core/error.h"
#include "core/file_io.h"
#include "child_process.h"
#include "scratch_scene_dir.h"
#include "render/image_io.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

using robust::kScenes;
using robust::kZigzag;

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class Outputs : public robust::ScratchSceneDir {
 protected:
  Outputs() : ScratchSceneDir("zz_outputs_") {}
  void SetUp() override {
    ScratchSceneDir::SetUp();
    write("other.json", R"({"model": "default.gltf", "width": 24, "height": 16})");
  }
  robust::ChildResult render(std::vector<std::string> args) const {
    args.insert(args.begin(), {kZigzag, "render"});
    for (const char* a : {"--edges", "off", "-q"}) args.push_back(a);
    return robust::run_child(args, {{}, 60.0});
  }
  // A one-line error, exit `code` (1: the job failed; kUsageExit: the command line cannot
  // work, found before any scene loads), mentioning `mention`, well before any render could finish.
  static void expect_error(const robust::ChildResult& r, const std::string& mention, int code = 1) {
    ASSERT_TRUE(r.exited) << "signal " << r.signal << " timed out " << r.timed_out;
    EXPECT_EQ(r.exit_code, code) << r.err;
    EXPECT_EQ(robust::lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
    std::printf("[ message ] exit %d: %s", r.exit_code, r.err.c_str());
  }
};

TEST_F(Outputs, InterruptDuringTheWriteLeavesTheOldOrTheNewImageNeverAPartOne) {
  const fs::path target = path("big.png");
  ASSERT_EQ(render({path("good.json").string(), "--width", "64", "--height", "64", "-o", target.string()}).exit_code, 0);
  std::mt19937 rng(13);
  int interrupted_in_write = 0;
  for (int round = 0; round < 4; ++round) {
    SCOPED_TRACE(round);
    const int sig = std::array{SIGINT, SIGTERM, SIGHUP, SIGQUIT}[size_t(round)];  // a closed terminal too
    const pid_t pid = ::fork();
    if (pid == 0) {
      const std::string scene = path("good.json").string(), out = target.string();
      ::execl(kZigzag.c_str(), kZigzag.c_str(), "render", scene.c_str(), "--width", "2048", "--height", "2048", "--aa",
              "none", "--edges", "off", "--threads", "2", "-q", "-o", out.c_str(), (char*)nullptr);
      ::_exit(127);
    }
    // Wait for the temporary (the write phase), then signal at a random moment inside it.
    bool writing = false;
    const auto start = std::chrono::steady_clock::now();
    while (!writing && std::chrono::steady_clock::now() - start < std::chrono::seconds(120)) {
      for (const auto& e : fs::directory_iterator(dir_))
        writing |= e.path().filename().string().rfind(".big.zz-", 0) == 0;
      if (::waitpid(pid, nullptr, WNOHANG) == pid) FAIL() << "finished before writing";
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_TRUE(writing);
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 150)(rng)));
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    const int code = WEXITSTATUS(status);
    EXPECT_TRUE(code == 128 + sig || code == 0) << code;
    if (code == 128 + sig) ++interrupted_in_write;
    int w = 0, h = 0;
    ASSERT_NO_THROW(read_rgb_float(target, w, h)) << "the target is not a valid image";
    EXPECT_TRUE((w == 64 && h == 64) || (w == 2048 && h == 2048)) << w << "x" << h;
    if (w == 2048) {  // the new image replaced it: start the next round from an old one again
      ASSERT_EQ(render({path("good.json").string(), "--width", "64", "--height", "64", "-o", target.string()}).exit_code, 0);
    }
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".zz-"), std::string::npos) << "temporary left: " << e.path();
  }
  EXPECT_GT(interrupted_in_write, 0) << "no round interrupted the write";
  std::printf("[ race ] %d of 4 rounds interrupted inside the write\n", interrupted_in_write);
}

// Whether a line of /proc/PID/status satisfies `test` (given the text after the field's
// name) within `seconds`.
template <class Test>
bool status_within(pid_t pid, const std::string& field, double seconds, Test test) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind(field, 0) == 0 && test(line.substr(field.size()))) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

TEST_F(Outputs, InterruptDuringTheRenderExitsPromptlyWithOneLine) {
  const std::string err = path("stderr.txt").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string scene = path("good.json").string(), out = path("x.png").string();
    const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    ::execl(kZigzag.c_str(), kZigzag.c_str(), "render", scene.c_str(), "--width", "4096", "--height", "4096",
            "--edges", "off", "-q", "-o", out.c_str(), (char*)nullptr);
    ::_exit(127);
  }
  // Signal only once the render runs: the 4096^2 film (radiance + 2 AOV bytes, 235 MB) is
  // made inside the cancellable section, so a resident set past 200 MiB means the tiles
  // are being traced. A signal before that leaves at once, the path of another test.
  const bool rendering = status_within(pid, "VmRSS:", 60.0, [](const std::string& kib) {
    return std::stoull(kib) > (200ull << 10);
  });
  if (!rendering) ::kill(pid, SIGKILL);
  ASSERT_TRUE(rendering) << "zigzag never reached the render";
  const auto t = std::chrono::steady_clock::now();
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_LT(s, 5.0) << "the render did not stop promptly";
  EXPECT_FALSE(fs::exists(path("x.png")));
  std::ifstream in(err);
  const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(said, "zigzag: interrupted (SIGINT); no output was left half-written\n");
}

TEST_F(Outputs, JobsThatWouldWriteOneFileAreRefusedNamingThePlaceholder) {
  expect_error(render({path("good.json").string(), path("other.json").string(), "-o", path("x.png").string()}),
               "add {scene}", kUsageExit);
  EXPECT_FALSE(fs::exists(path("x.png")));
  expect_error(render({path("good.json").string(), "--camera", "all", "-o", path("{scene}.png").string()}),
               "add {camera}", kUsageExit);
  expect_error(render({path("good.json").string(), path("other.json").string(), "-o", path("{scene}.png").string(),
                       "--stats", path("s.json").string()}),
               "--stats", kUsageExit);
}

// `--stats {scene}.json` beside the scene would replace room.json with its stats: every
// output is compared with the files the scene is read from, the rig, its glTF, buffers
// and images, listed before anything loads (links and other spellings included). (An
// image output is already refused a .json/.gltf/.bin name by its format.)
TEST_F(Outputs, NoOutputReplacesAFileTheSceneIsReadFrom) {
  const std::string good = path("good.json").string();
  const std::string rig = contents(path("good.json")), gltf = contents(path("default.gltf")),
                    bin = contents(path("default.bin"));
  fs::create_symlink(path("default.gltf"), path("link.gltf"));
  const struct {
    std::vector<std::string> args;
    std::string named;
  } cases[] = {
      {{good, "-o", path("x.png").string(), "--stats", path("{scene}.json").string()}, "good.json"},
      {{good, "-o", path("x.png").string(), "--stats", (dir_ / "." / "good.json").string()}, "good.json"},
      {{good, "-o", path("x.png").string(), "--stats", path("default.gltf").string()}, "default.gltf"},
      {{good, "-o", path("x.png").string(), "--stats", path("link.gltf").string()}, "default.gltf"},
      {{good, "-o", path("x.png").string(), "--stats", path("default.bin").string()}, "default.bin"},
  };
  for (const auto& c : cases) {
    const robust::ChildResult r = render(c.args);
    SCOPED_TRACE(r.err);
    EXPECT_TRUE(r.exited);
    EXPECT_EQ(r.exit_code, kUsageExit);  // refused, before or after the load: not worth a retry
    EXPECT_NE(r.err.find("is a file of the batch's scenes"), std::string::npos);
    EXPECT_NE(r.err.find(c.named), std::string::npos);
    EXPECT_EQ(contents(path("good.json")), rig);
    EXPECT_EQ(contents(path("default.gltf")), gltf);
    EXPECT_EQ(contents(path("default.bin")), bin);
    EXPECT_FALSE(fs::exists(path("x.png")));
  }
}

// An output path through a folder not made yet still names the input it resolves to:
// `equivalent` cannot compare a path that does not exist, and the stats replaced the rig.
TEST_F(Outputs, AnOutputThroughAFolderNotMadeYetIsComparedWithTheInputsToo) {
  const std::string rig = contents(path("good.json"));
  const auto r = render({path("good.json").string(), "-o", path("x.png").string(), "--stats",
                         (dir_ / "nodir" / ".." / "good.json").string()});
  expect_error(r, "is a file of the batch's scenes", kUsageExit);
  EXPECT_EQ(contents(path("good.json")), rig);
  EXPECT_FALSE(fs::exists(path("nodir")));
}

// Every image format zigzag accepts reads back as the image written (OpenImageIO 2.4's
// TIFF writer made unreadable files through a proxy with the sRGB tag); the same render
// writes the same bytes (no date stamped in the EXR header); a replaced file keeps its
// permission bits (a private image stays private).
TEST_F(Outputs, ImagesReadBackSameBytesSameMode) {
  const std::string good = path("good.json").string();
  // Every format the README says is written.
  for (const char* ext : {"png", "exr", "tif", "jpg", "bmp", "tga", "hdr", "webp", "pnm", "dpx", "iff"}) {
    SCOPED_TRACE(ext);
    const fs::path out = path(std::string("img.") + ext), again = path("again") / out.filename();
    ASSERT_EQ(render({good, "--width", "40", "--height", "24", "-o", out.string()}).exit_code, 0);
    int w = 0, h = 0;
    ASSERT_NO_THROW(read_rgb_float(out, w, h));
    EXPECT_EQ(w, 40);
    EXPECT_EQ(h, 24);
    // The same bytes from another run: no hidden temporary's name in a header (DPX stored
    // the file name the writer was opened with: exploratory testing).
    ASSERT_EQ(render({good, "--width", "40", "--height", "24", "-o", again.string()}).exit_code, 0);
    EXPECT_EQ(contents(out), contents(again));
  }
  const fs::path a = path("a.exr"), b = path("b.exr");
  ASSERT_EQ(render({good, "--width", "40", "--height", "24", "--aov", "depth", "-o", a.string()}).exit_code, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // a date would differ by a second
  ASSERT_EQ(render({good, "--width", "40", "--height", "24", "--aov", "depth", "-o", b.string()}).exit_code, 0);
  EXPECT_EQ(contents(a), contents(b));
  // The permission bits carry over, never setuid, setgid or sticky (a read-only file is
  // refused: AWriteProtectedOutputIsRefusedAndKept).
  for (const mode_t mode : {mode_t(0600), mode_t(0640), mode_t(04755)}) {
    ASSERT_EQ(::chmod(a.c_str(), mode), 0);
    ASSERT_EQ(render({good, "--width", "40", "--height", "24", "-o", a.string(), "--stats", path("s.json").string()}).exit_code, 0);
    struct stat st {};
    ASSERT_EQ(::stat(a.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, mode & 0777u) << std::oct << mode;
  }
}

// A file made read-only to protect it (a studio's finals) is refused before the render,
// not replaced by the rename, which the directory's permission allows; as root, which
// may write anything, a file with no write bit at all (as rm asks about it).
TEST_F(Outputs, AWriteProtectedOutputIsRefusedAndKept) {
  const fs::path final = path("final.png");
  write("final.png", "FINAL");
  ASSERT_EQ(::chmod(final.c_str(), 0444), 0);
  expect_error(render({path("good.json").string(), "-o", final.string()}), "the file is write-protected", kUsageExit);
  EXPECT_EQ(contents(final), "FINAL");
  write("s.json", "STATS");
  ASSERT_EQ(::chmod(path("s.json").c_str(), 0444), 0);
  expect_error(render({path("good.json").string(), "-o", path("x.png").string(), "--stats", path("s.json").string()}),
               "--stats " + path("s.json").string() + ": the file is write-protected", kUsageExit);
  EXPECT_EQ(contents(path("s.json")), "STATS");
  EXPECT_FALSE(fs::exists(path("x.png")));
}

// An output named by a symbolic link is written through, as cp, a shell's > and image
// writers do: the link stays, its target gets the image (made if it does not exist yet);
// the render used to replace the link with a plain file and leave the target as it was.
TEST_F(Outputs, AnOutputThatIsALinkWritesItsTarget) {
  fs::create_directories(path("shots"));
  fs::create_symlink("shots/v1.png", path("latest.png"));  // dangling: the target is made
  ASSERT_EQ(render({path("good.json").string(), "-o", path("latest.png").string()}).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(path("latest.png")));
  int w = 0, h = 0;
  EXPECT_NO_THROW(read_rgb_float(path("shots/v1.png"), w, h));
  write("shots/v1.png", "OLD");  // an existing target is replaced whole
  ASSERT_EQ(render({path("good.json").string(), "-o", path("latest.png").string()}).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(path("latest.png")));
  EXPECT_NO_THROW(read_rgb_float(path("shots/v1.png"), w, h));
  EXPECT_EQ(std::distance(fs::directory_iterator(path("shots")), fs::directory_iterator()), 1);  // no temporary left
}

// A device or pipe (--stats /dev/stdout, a FIFO) receives the finished output's bytes:
// the render used to rename a plain file over the link that named it, or fail in /dev.
TEST_F(Outputs, AStreamReceivesTheFinishedOutput) {
  const fs::path fifo = path("stats.json");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // the pipe's buffer holds it all
  ASSERT_GE(reader, 0);
  const robust::ChildResult r = render({path("good.json").string(), "-o", path("x.png").string(), "--stats", fifo.string()});
  std::string bytes;
  char buffer[4096];
  for (ssize_t n; (n = ::read(reader, buffer, sizeof buffer)) > 0;) bytes.append(buffer, size_t(n));
  ::close(reader);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(bytes).value("aa", ""), "adaptive") << bytes;
  EXPECT_TRUE(fs::exists(path("x.png")));
  // Two outputs to one stream would interleave: refused as any two outputs of one file.
  expect_error(render({path("good.json").string(), "-o", path("y.png").string(), "--stats", "/dev/stdout", "--aov",
                       "rays", "/dev/stdout"}),
               "would both write /dev/stdout", kUsageExit);
}

// `--stats /dev/stdout >> log`: the stats go through the descriptor the shell opened,
// after what the log held, as a batch's jobs share a pipe (exploratory testing: the file
// behind /dev/stdout was replaced, the log's lines lost, and a batch was refused as two
// writers of one file). The same for /dev/stderr with 2>>.
TEST_F(Outputs, AFileBehindOurStdoutIsAppendedToNotReplaced) {
  const fs::path log = path("log.txt"), err = path("err.txt");
  write("log.txt", "PREVIOUS\n");
  write("err.txt", "EARLIER\n");
  const std::string batch = kZigzag + " render " + path("good.json").string() + " " + path("other.json").string() +
                            " --edges off -q -o " + path("{scene}.png").string();
  for (int run = 0; run < 2; ++run) {
    const robust::ChildResult r =
        robust::run_child({"/bin/sh", "-c", batch + " --stats /dev/stdout >> " + log.string()}, {{}, 60.0});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const robust::ChildResult r =
      robust::run_child({"/bin/sh", "-c", batch + " --stats /dev/fd/2 2>> " + err.string()}, {{}, 60.0});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto documents = [](const std::string& text) {
    size_t n = 0;
    for (size_t at = text.find("\"aa\""); at != std::string::npos; at = text.find("\"aa\"", at + 1)) ++n;
    return n;
  };
  const std::string logged = contents(log), errors = contents(err);
  EXPECT_EQ(logged.rfind("PREVIOUS\n{", 0), 0u) << logged;
  EXPECT_EQ(documents(logged), 4u) << logged;  // two runs of two jobs
  EXPECT_EQ(errors.rfind("EARLIER\n{", 0), 0u) << errors;
  EXPECT_EQ(documents(errors), 2u) << errors;
}

// `nohup zigzag ...`: a hang-up the parent chose to ignore stays ignored, and the render
// finishes (a SIGHUP handler installed over SIG_IGN ended it with 129).
TEST_F(Outputs, AnIgnoredHangUpStaysIgnored) {
  const fs::path out = path("nohup.png");
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::signal(SIGHUP, SIG_IGN);
    const std::string scene = path("good.json").string(), o = out.string();
    ::execl(kZigzag.c_str(), kZigzag.c_str(), "render", scene.c_str(), "--width", "4096", "--height", "4096",
            "--aa", "none", "--edges", "off", "-q", "-o", o.c_str(), (char*)nullptr);
    ::_exit(127);
  }
  // Once the render runs (its 4096^2 film is past 200 MiB; see the test above).
  const bool rendering = status_within(pid, "VmRSS:", 60.0, [](const std::string& kib) {
    return std::stoull(kib) > (200ull << 10);
  });
  if (!rendering) ::kill(pid, SIGKILL);
  ASSERT_TRUE(rendering) << "zigzag never reached the render";
  ::kill(pid, SIGHUP);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(fs::exists(out));
}

// A scene earlier in the batch must not replace a file of a later one: its image would
// become the later scene's texture, or its stats the later scene's buffer, with no word.
TEST_F(Outputs, NoOutputReplacesAFileOfALaterSceneInTheBatch) {
  fs::create_directories(path("later"));
  std::string gltf = contents(path("default.gltf"));
  const size_t uri = gltf.find("\"default.bin\"");
  ASSERT_NE(uri, std::string::npos);
  gltf.replace(uri, 13, "\"good.bin\"");
  write("later/later.gltf", gltf);
  fs::copy_file(path("default.bin"), path("later/good.bin"));
  const std::string bin = contents(path("later/good.bin"));
  const robust::ChildResult r = render({path("good.json").string(), path("later/later.gltf").string(), "-o",
                                        path("{scene}.png").string(), "--stats", path("later/{scene}.bin").string()});
  expect_error(r, "is a file of the batch's scenes", kUsageExit);
  EXPECT_NE(r.err.find("good.bin"), std::string::npos);
  EXPECT_EQ(contents(path("later/good.bin")), bin);
  EXPECT_FALSE(fs::exists(path("good.png")));
  // A file the later scene names but that is not there yet: the earlier output would
  // create it, and the later scene would load it as its own.
  fs::remove(path("later/good.bin"));
  const robust::ChildResult missing =
      render({path("good.json").string(), path("later/later.gltf").string(), "-o", path("later/{scene}.bin.png").string(),
              "--stats", path("later/{scene}.bin").string()});
  expect_error(missing, "is a file of the batch's scenes", kUsageExit);
  EXPECT_FALSE(fs::exists(path("later/good.bin")));
}

// Listing a batch's files reads each scene's JSON before anything loads: a FIFO named as a
// scene must fail as a load does ("not a regular file"), not block that read.
TEST_F(Outputs, AFifoNamedAsASceneFailsWithoutBlocking) {
  for (const char* name : {"pipe.glb", "pipe.gltf", "pipe.json"}) {
    SCOPED_TRACE(name);
    ASSERT_EQ(::mkfifo(path(name).c_str(), 0600), 0);
    const robust::ChildResult r = render({path(name).string(), "-o", path("x.png").string()});
    ASSERT_TRUE(r.exited) << "timed out " << r.timed_out;
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    EXPECT_LT(r.seconds, 10.0);
  }
}

TEST_F(Outputs, UnwritableOutputsFailBeforeTheRender) {
  write("plain", "x");
  const std::string good = path("good.json").string();
  const auto a = render({good, "-o", path("plain/out.png").string()});
  expect_error(a, "plain is a file, not a directory", kUsageExit);
  expect_error(render({good, "-o", "/proc/zz_no_such_dir/out.png"}), "/proc", kUsageExit);
  expect_error(render({good, "-o", path("out").string()}), "no file extension", kUsageExit);
  expect_error(render({good, "-o", path("out.xyz").string()}), "unsupported image format", kUsageExit);
  // Writers that cannot write through a checked stream: their write errors would go unseen
  // (a truncated SGI published, exit 0).
  expect_error(render({good, "-o", path("out.sgi").string()}), "unsupported image format", kUsageExit);
  // Writers whose files do not read back as the image: refused before the render, not
  // after it (review: GIF's palette, JPEG 2000's empty proxy, the TIFF writer's texture
  // names' incomplete TIFF, the null writer; a farm retried them twice).
  // The PNM writer's grey and bitmap names (it writes a colour P6 under either).
  for (const char* name : {"out.gif", "out.GIF", "out.jp2", "out.j2k", "out.tx", "out.env", "out.sm", "out.vsm", "out.null",
                           "out.nul", "out.pgm", "out.pbm"})
    expect_error(render({good, "-o", path(name).string()}), "unsupported image format", kUsageExit);
  expect_error(render({good, "-o", path("a.png").string(), "--stats", path("plain/s.json").string()}), "--stats",
               kUsageExit);
  // A name the file system cannot hold, of the file or of a folder to make.
  const size_t limit = name_max(dir_);
  expect_error(render({good, "-o", path(std::string(limit, 'n') + ".png").string()}), "bytes long", kUsageExit);
  expect_error(render({good, "-o", path(std::string(limit + 1, 'd') + "/x.png").string()}), "bytes long", kUsageExit);
  EXPECT_LT(a.seconds, 10.0);
}

// One file named two ways (absolute and relative, or through a link to its folder): the
// second output would replace the first without a word. Refused before the render.
TEST_F(Outputs, OneFileUnderTwoNamesIsRefused) {
  const std::string good = path("good.json").string();
  fs::create_directory_symlink(dir_, path("here"));
  const auto linked = render({good, "-o", path("here/z.png").string(), "--stats", path("z.png").string()});
  expect_error(linked, "would both write", kUsageExit);
  EXPECT_FALSE(fs::exists(path("z.png")));
}

// The batch's check expands {frame} as 0; the job's own frame can take the name past the
// limit. Refused when the job starts, before its render, naming the option.
TEST_F(Outputs, AFrameNumberThatTakesTheNamePastTheLimitFailsBeforeTheRender) {
  const std::string prefix = std::string(name_max(dir_) - 8, 'f');  // "_0.png" fits, "_12345678.png" does not
  const auto r = robust::run_child({kZigzag, "render", (kScenes / "animated.json").string(), "--width", "16",
                                    "--height", "16", "--frame", "12345678", "-o", path(prefix + "_{frame}.png").string(),
                                    "--edges", "off", "-q"});
  expect_error(r, "bytes long");
  EXPECT_NE(r.err.find("-o"), std::string::npos) << r.err;
  for (const fs::directory_entry& e : fs::directory_iterator(dir_))  // no image, no temporary
    EXPECT_EQ(e.path().filename().string().find("fff"), std::string::npos) << e.path();
}

// A name just below the file system's limit is valid: the render writes it (its temporary,
// longer, used to fail after the whole render).
TEST_F(Outputs, ANameAtTheLimitIsWritten) {
  const std::string name = std::string(name_max(dir_) - 4, 'n') + ".png";
  const auto r = render({path("good.json").string(), "-o", path(name).string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(path(name)));
}

size_t entries(const fs::path& dir) {
  return size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// A write that fails half-way through the file (a full disk; here the file-size limit,
// ulimit -f, past which the renderer's writes fail with EFBIG): OpenImageIO's PNG writer
// did not notice (a truncated PNG, exit 0) and libjpeg's exited the process. The old file
// stays, the one line says why, and no temporary is left.
TEST_F(Outputs, AWriteThatFailsMidFileLeavesTheOldImageAndSaysWhy) {
  const size_t before = entries(dir_);
  robust::ChildOptions limited;
  limited.file_size_limit = 4096;  // room at 256^2 takes 18 kB (JPEG) to 760 kB (EXR)
  for (const char* ext : {"png", "jpg", "exr", "tif"}) {
    SCOPED_TRACE(ext);
    const fs::path target = path(std::string("old.") + ext);
    write(target.filename().string(), "the old image");
    const auto r = robust::run_child({kZigzag, "render", (kScenes / "room.json").string(), "--width", "256", "--height",
                                      "256", "-o", target.string(), "--edges", "off", "-q"},
                                     limited);
    expect_error(r, target.string() + ": File too large");
    EXPECT_EQ(contents(target), "the old image");
  }
  EXPECT_EQ(entries(dir_), before + 4);  // the four old images, no temporary
}

// A job's files are published together: its stats failing (the file-size limit between the
// image's size and theirs) leaves the image it wrote before them as it was.
TEST_F(Outputs, AJobWhoseLaterOutputFailsLeavesItsEarlierOnesAlone) {
  const std::vector<std::string> job = {kZigzag,   "render", (kScenes / "room.json").string(), "--width", "24",
                                        "--height", "16",     "-o", path("out.png").string(),  "--stats",
                                        path("stats.json").string(), "--edges", "off", "-q"};
  ASSERT_EQ(robust::run_child(job).exit_code, 0);
  const size_t image = fs::file_size(path("out.png")), stats = fs::file_size(path("stats.json"));
  ASSERT_LT(image + 256, stats) << "the test needs stats larger than the image";
  write("out.png", "the old image");
  write("stats.json", "the old stats");
  const size_t before = entries(dir_);
  robust::ChildOptions limited;
  limited.file_size_limit = (image + stats) / 2;
  expect_error(robust::run_child(job, limited), path("stats.json").string() + ": File too large");
  EXPECT_EQ(contents(path("out.png")), "the old image");
  EXPECT_EQ(contents(path("stats.json")), "the old stats");
  EXPECT_EQ(entries(dir_), before);
}

TEST_F(Outputs, ADirectoryNamedLikeASceneIsNamedAsOne) {
  fs::create_directories(path("x.glb"));
  expect_error(render({path("x.glb").string(), "-o", path("x.png").string()}), "is a directory");
}

TEST_F(Outputs, RigCyclesNameTheChain) {
  write("self.json", R"({"model": "self.json"})");
  write("a.json", R"({"model": "b.json"})");
  write("b.json", R"({"model": "a.json"})");
  expect_error(render({path("self.json").string(), "-o", path("{scene}.png").string()}), "rig cycle");
  const auto r = render({path("a.json").string(), "-o", path("{scene}.png").string()});
  expect_error(r, "rig cycle");
  EXPECT_NE(r.err.find("a.json -> " + path("b.json").string() + " -> " + path("a.json").string()), std::string::npos)
      << r.err;
}

TEST_F(Outputs, JsonErrorsGiveFileLineColumn) {
  write("empty.json", "");
  expect_error(render({path("empty.json").string(), "-o", path("{scene}.png").string()}),
               path("empty.json").string() + ":1:1: invalid JSON");
  write("bad.json", "{\"model\": \"default.gltf\",\n  \"width\": }");
  expect_error(render({path("bad.json").string(), "-o", path("{scene}.png").string()}),
               path("bad.json").string() + ":2:12: invalid JSON");
  // A number out of double's range has no parser position of its own: the number's, not
  // where its digits first appear inside a string (review).
  write("huge.json", "{\"model\": \"default.gltf\", \"description\": \"1e400 \\\" 1e400\",\n \"exposure\": 1e400}");
  expect_error(render({path("huge.json").string(), "-o", path("{scene}.png").string()}),
               path("huge.json").string() + ":2:14: invalid JSON: number overflow parsing '1e400'");
}

TEST_F(Outputs, NoTrianglesIsAnError) {
  write("none.gltf", R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[]}],"scene":0})");
  expect_error(render({path("none.gltf").string(), "-o", path("{scene}.png").string()}), "no triangles");
  EXPECT_FALSE(fs::exists(path("none.png")));
}

TEST_F(Outputs, TraceDepthHasOneRangeAndDeepGlassStaysBounded) {
  // A command-line syntax error: CLI11's exit code (105) and its standard hint line.
  const auto cli = render({path("good.json").string(), "--max-depth", "64", "-o", path("x.png").string()});
  EXPECT_TRUE(cli.exited && cli.exit_code != 0 && cli.exit_code != 2) << cli.err;
  EXPECT_NE(cli.err.find("--max-depth: Value 64 not in range 0 to 16"), std::string::npos) << cli.err;
  std::printf("[ message ] exit %d: %s", cli.exit_code, cli.err.c_str());
  write("deep.json", R"({"model": "default.gltf", "max_depth": 64})");
  expect_error(render({path("deep.json").string(), "-o", path("x.png").string()}), "max_depth");
  // Fresnel splits double the rays per bounce without the throughput cutoff: 3.4 M rays
  // at depth 14 on 32x32 glass before it, ~0.16 M now, and depth 16 adds almost nothing.
  uint64_t rays[2];
  int k = 0;
  for (const char* depth : {"14", "16"}) {
    const auto r = render({(kScenes / "glass.json").string(), "--width", "32", "--height", "32", "--max-depth", depth,
                           "-o", path("g.png").string(), "--stats", path("g.json").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream f(path("g.json"));
    rays[k++] = nlohmann::json::parse(f)["rays"]["total"].get<uint64_t>();
  }
  std::printf("[ depth ] glass 32^2: %llu rays at depth 14, %llu at 16\n", (unsigned long long)rays[0],
              (unsigned long long)rays[1]);
  EXPECT_LT(rays[1], 600000u);
  EXPECT_LT(double(rays[1]), 1.1 * double(rays[0]));
}

TEST_F(Outputs, MemoryEstimateIsWithin15PercentOfThePeakRss) {
  if (robust::kSanitized) GTEST_SKIP() << "ASan inflates RSS: the estimate is for normal builds";
  for (const char* size : {"512", "1024", "2048"}) {
    SCOPED_TRACE(size);
    // --aov geo: the visibility raster runs (lavapipe allocates it in host memory).
    const robust::ChildResult r = robust::run_child(
        {kZigzag, "render", path("good.json").string(), "--aa", "none", "--aov", "geo", path("geo.png").string(),
         "--width", size, "--height", size, "-q", "-o", path("m.png").string(), "--stats", path("m.json").string()},
        {{}, 240.0});
    ASSERT_TRUE(r.exited && r.exit_code == 0) << r.err;
    std::ifstream f(path("m.json"));
    const double estimate = double(nlohmann::json::parse(f)["memory_estimate_bytes"].get<uint64_t>());
    const double peak = double(r.max_rss_kb) * 1024.0;
    std::printf("[ memory ] %s^2: estimate %.1f MiB, peak RSS %.1f MiB (%+.1f %%)\n", size, estimate / 1048576.0,
                peak / 1048576.0, 100.0 * (estimate - peak) / peak);
    EXPECT_NEAR(estimate, peak, 0.15 * peak);
  }
}

TEST_F(Outputs, MemoryEstimateOfARegionHoldsTheFullFrameMap) {
  if (robust::kSanitized) GTEST_SKIP() << "ASan inflates RSS: the estimate is for normal builds";
  // A region of a 16384^2 frame: the visibility pass returns a 256 MiB map of the whole
  // frame beside the region's, which the estimate must count.
  const robust::ChildResult r = robust::run_child(
      {kZigzag, "render", path("good.json").string(), "--aa", "none", "--aov", "geo", path("geo.png").string(),
       "--width", "16384", "--height", "16384", "--region", "8192,8192,8704,8704", "-q", "-o",
       path("m.png").string(), "--stats", path("m.json").string()},
      {{}, 240.0});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << r.err;
  std::ifstream f(path("m.json"));
  const double estimate = double(nlohmann::json::parse(f)["memory_estimate_bytes"].get<uint64_t>());
  const double peak = double(r.max_rss_kb) * 1024.0;
  std::printf("[ memory ] region of 16384^2: estimate %.1f MiB, peak RSS %.1f MiB (%+.1f %%)\n",
              estimate / 1048576.0, peak / 1048576.0, 100.0 * (estimate - peak) / peak);
  EXPECT_NEAR(estimate, peak, 0.15 * peak);
}

}  // namespace
}  // namespace zz
