// Where a batch's outputs go: `-o`, `--stats` and `--aov` take patterns with the
// placeholders {scene} (the scene file's stem), {camera} and {frame} ({frame:04} pads
// with zeros to 4 digits). Before anything is loaded, a batch whose jobs would write
// the same file is rejected, naming the placeholder that would tell them apart.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace zz {

// The values one job substitutes into the patterns.
struct OutputKey {
  std::string scene;
  std::string camera;
  int frame = 0;
  // One of two cameras that stand for a scene's cameras under --camera all, before the
  // scene is read (the messages then speak of "every camera", not of cameras 0 and 1).
  bool any_camera = false;
};

// Replaces the placeholders; throws zz::Error for an unknown or malformed one
// (e.g. "{scen}", "{frame:x}"), naming `option`.
std::string expand_output_pattern(const std::string& pattern, const OutputKey& key, const std::string& option = "-o");

// One output pattern of a batch: the option that gave it (for messages) and the pattern.
struct OutputPattern {
  std::string option;   // "-o", "--stats", "--aov rays"
  std::string pattern;
};

// The name outputs are compared by: absolute, the folder's existing part with its links and
// ".." resolved, the file name as given (`-o /abs/dir/x.png` and `x.png`, `link/x.png` with
// link -> . are one file); an output that is itself a link is its target, which is what
// gets written (output_target), and a stream is what it is (stream_identity: /dev/stdout and
// /dev/fd/1 are one pipe).
std::filesystem::path output_identity(const std::filesystem::path& path);

// Throws zz::Error when two jobs (or two outputs of one job) would write the same file:
// "-o out.png: jobs room and glass would both write out.png (add {scene})". Streams
// (/dev/null, /dev/stdout, a FIFO) are written to one job after another, never replaced,
// so jobs may share one; two outputs of one job may not.
void check_distinct_outputs(const std::vector<OutputPattern>& patterns, const std::vector<OutputKey>& jobs);

// The files a batch's jobs write, claimed as each job starts, with its real camera: the
// check before loading saw stand-ins (`--camera front` is camera 0 only once the scene is
// read; `--camera all` has cameras 0 and 1), so `-o {camera}.png --aov rays 0.png`, or
// camera 1's `a1{camera}` against camera 11's `a{camera}`, would replace a file written
// earlier in the batch. claim() throws zz::UsageError, naming both writers, before the
// job renders.
class OutputClaims {
 public:
  void claim(const std::vector<OutputPattern>& patterns, const OutputKey& job, const std::string& job_label);

 private:
  std::map<std::filesystem::path, std::string> writers_;  // output_identity -> "OPTION of JOB"
};

// Before a render, for one expanded output path: the file name is not a directory, an
// image has an extension OpenImageIO can write (`image`), and the nearest existing
// ancestor of its directory is a directory this process can create files in (probed with
// a file created and removed at once), and an existing file is not write-protected; a
// stream (/dev/stdout) must be writable. Links are followed to what gets written. Creates
// nothing. Throws zz::Error starting with "OPTION PATH: ". `formats`: the formats an
// unknown extension's message suggests, when not the renderer's.
void preflight_output(const std::string& option, const std::filesystem::path& path, bool image,
                      const char* formats = nullptr);

// Throws zz::UsageError when an output is one of the files the command reads (a scene's
// rig, its glTF, buffers, images; merge's parts): `--stats {scene}.json` beside room.json
// would replace the scene with its stats. Compared as files (links and other spellings of a
// path included). `inputs_are` names them in the message.
void check_not_an_input(const std::string& option, const std::filesystem::path& output,
                        const std::vector<std::string>& inputs,
                        const std::string& inputs_are = "the scene's own file");

}  // namespace zz
