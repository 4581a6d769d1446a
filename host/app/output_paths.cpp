#include "app/output_paths.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_io.h"
#include "render/image_io.h"

namespace zz {

namespace {

// Expands one "{...}" body; returns false if it is not a known placeholder.
bool expand_placeholder(const std::string& body, const OutputKey& key, std::string& out) {
  if (body == "scene") return out += key.scene, true;
  if (body == "camera") return out += key.camera, true;
  if (body == "frame") return out += std::to_string(key.frame), true;
  if (body.rfind("frame:", 0) == 0) {
    const std::string width = body.substr(6);
    if (width.empty() || width.size() > 2 || width.find_first_not_of("0123456789") != std::string::npos) return false;
    const std::string digits = std::to_string(key.frame);
    const size_t pad = size_t(std::stoi(width));
    if (digits.size() < pad) out.append(pad - digits.size(), '0');
    return out += digits, true;
  }
  return false;
}

std::string job_name(const OutputKey& k, const std::vector<OutputKey>& jobs) {
  // Name only what varies across the batch.
  bool scenes = false, cameras = false, frames = false;
  for (const OutputKey& j : jobs) {
    scenes |= j.scene != jobs.front().scene;
    cameras |= j.camera != jobs.front().camera;
    frames |= j.frame != jobs.front().frame;
  }
  cameras &= !k.any_camera;  // a stand-in for --camera all is no camera of the user's
  std::string name = scenes || !(cameras || frames) ? k.scene : "";
  auto add = [&](const std::string& s) { name += (name.empty() ? "" : " ") + s; };
  if (cameras) add("camera " + k.camera);
  if (frames) add("frame " + std::to_string(k.frame));
  return name;
}

// The placeholder whose absence makes jobs a and b collide, or "" if the pattern has them all.
std::string missing_placeholder(const std::string& pattern, const OutputKey& a, const OutputKey& b) {
  if (a.scene != b.scene && pattern.find("{scene}") == std::string::npos) return "{scene}";
  if (a.camera != b.camera && pattern.find("{camera}") == std::string::npos) return "{camera}";
  if (a.frame != b.frame && pattern.find("{frame") == std::string::npos) return "{frame}";
  return "";
}

// What OpenImageIO writes that zigzag's users ask for (any format it has a writer for works).
constexpr const char* kFormats = " (use .png or .exr; .jpg, .tif, .bmp, .tga, .webp, .hdr also work)";

std::string errno_text() { return std::strerror(errno); }

}  // namespace

void preflight_output(const std::string& option, const std::filesystem::path& path, bool image, const char* formats) {
  if (!formats) formats = kFormats;
  namespace fs = std::filesystem;
  const std::string where = option + " " + path.string() + ": ";
  std::error_code ec;
  if (!path.has_filename() || fs::is_directory(path, ec))
    throw Error(where + "is a directory; give a file name");
  if (image) {
    if (path.extension().empty())
      throw Error(where + "no file extension to choose the format" + formats);
    if (!can_write_image_format(path))
      throw Error(where + "unsupported image format '" + path.extension().string() + "'" + formats);
  }
  if (output_is_stream(path)) {  // /dev/stdout, a FIFO: written to, not replaced
    // One of our own descriptors is written through, whatever the file behind it allows.
    if (!own_descriptor(path) && ::access(path.c_str(), W_OK) != 0)
      throw Error(where + "cannot write to it (" + errno_text() + ")");
    return;
  }
  if (write_protected(path))
    throw Error(where + "the file is write-protected (make it writable, chmod u+w, to let zigzag replace it)");
  const fs::path target = output_target(path);  // a link's target is what gets written
  if (fs::is_symlink(target, ec))  // followed 40 times and still a link: the link itself would be replaced
    throw Error(where + "its symbolic links form a loop (or are nested deeper than 40); they name no file to write");
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  fs::path existing = dir;
  while (!fs::exists(existing, ec) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  if (!fs::exists(existing, ec)) existing = ".";
  if (!fs::is_directory(existing, ec))
    throw Error(where + existing.string() + " is a file, not a directory");
  const size_t longest = name_max(existing);
  for (const fs::path& part : target)
    if (part.string().size() > longest)
      throw Error(where + "the name " + part.string().substr(0, 24) + "... is " + std::to_string(part.string().size()) +
                  " bytes long, the file system takes at most " + std::to_string(longest));
  const fs::path probe = existing / (".zz-probe-" + std::to_string(::getpid()) + "-" + random_token());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    const std::string why = errno_text();
    throw Error(where + (existing == dir ? "cannot write into " : "cannot create directories in ") + existing.string() +
                " (" + why + ")");
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

std::string expand_output_pattern(const std::string& pattern, const OutputKey& key, const std::string& option) {
  std::string out;
  for (size_t i = 0; i < pattern.size();) {
    if (pattern[i] != '{') {
      out += pattern[i++];
      continue;
    }
    const size_t close = pattern.find('}', i);
    const std::string body = close == std::string::npos ? "" : pattern.substr(i + 1, close - i - 1);
    if (close == std::string::npos || !expand_placeholder(body, key, out))
      throw Error(option + " " + pattern + ": unknown placeholder '" + pattern.substr(i, close == std::string::npos ? std::string::npos : close - i + 1) +
                  "' (known: {scene}, {camera}, {frame}, {frame:04})");
    i = close + 1;
  }
  return out;
}

void check_not_an_input(const std::string& option, const std::filesystem::path& output,
                        const std::vector<std::string>& inputs, const std::string& inputs_are) {
  for (const std::string& input : inputs) {
    std::error_code ec;
    // The same file under any name; a file not there yet (a later scene's texture an earlier
    // output would create) by its path, as outputs are compared with one another.
    // Both ways always: `equivalent` fails on an output path through a folder not made yet
    // (nodir/../scene.json), which names the input all the same.
    const bool same = output_identity(output) == output_identity(input) ||
                      (std::filesystem::exists(input, ec) && std::filesystem::equivalent(output, input, ec));
    if (same)  // a usage error: a re-run fails the same way
      throw UsageError(option + " " + output.string() + " is " + inputs_are + " " + input +
                       ": writing it would replace it");
  }
}

std::filesystem::path output_identity(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  if (ec) return path.lexically_normal();
  // A stream by what it is; a link named as the output is written through (output_target);
  // the folder resolved (links, ".."), the name kept, which need not exist yet.
  if (const std::optional<std::string> stream = stream_identity(absolute)) return *stream;
  absolute = output_target(absolute);
  const fs::path folder = fs::weakly_canonical(absolute.parent_path(), ec);
  return ec ? absolute.lexically_normal() : folder / absolute.filename();
}

void check_distinct_outputs(const std::vector<OutputPattern>& patterns, const std::vector<OutputKey>& jobs) {
  struct Writer {
    const OutputPattern* pattern;
    const OutputKey* job;
    std::filesystem::path path;  // as given, for messages
  };
  std::map<std::pair<std::filesystem::path, std::ptrdiff_t>, Writer> writers;  // (file, a stream's job or -1)
  for (const OutputPattern& p : patterns)
    for (const OutputKey& job : jobs) {
      const std::filesystem::path given = expand_output_pattern(p.pattern, job, p.option);
      const std::filesystem::path path = given.lexically_normal();  // for messages
      // A stream is written to, not replaced: jobs may share one (/dev/null), one after
      // another, but two outputs of one job in it would mix their bytes.
      const bool stream = output_is_stream(given);
      const auto [it, inserted] =
          writers.emplace(std::pair(output_identity(given), stream ? &job - jobs.data() : -1), Writer{&p, &job, path});
      if (inserted) continue;
      const Writer& first = it->second;
      if (stream && first.path != path)  // /dev/stdout and /dev/fd/1: one pipe
        throw Error(first.pattern->option + " " + first.path.string() + " and " + p.option + " " + path.string() +
                    " are one stream: their bytes would mix in it");
      if (first.pattern == &p) {
        const std::string missing = missing_placeholder(p.pattern, *first.job, job);
        if (missing == "{camera}" && first.job->any_camera && job.any_camera)
          throw Error(p.option + " " + p.pattern + ": with --camera all, every camera of " + job.scene +
                      " would write " + path.string() + " (add {camera})");
        if (first.path != path)  // two names, one file: a link, or a folder reached two ways
          throw Error(p.option + " " + p.pattern + ": jobs " + job_name(*first.job, jobs) + " and " +
                      job_name(job, jobs) + " would write one file, " + first.path.string() + " and " + path.string() +
                      " being the same file");
        throw Error(p.option + " " + p.pattern + ": jobs " + job_name(*first.job, jobs) + " and " +
                    job_name(job, jobs) + " would both write " + path.string() +
                    (missing.empty() ? " (their scene files have the same name)" : " (add " + missing + ")"));
      }
      throw Error(first.pattern->option + " and " + p.option + " would both write " + path.string());
    }
  // A file cannot also be a folder: `-o out/a.png --stats out/a.png/s.json` rendered, then
  // failed writing (found after the render, which a dry run did not see).
  for (const auto& [key, writer] : writers) {
    const std::filesystem::path& id = key.first;
    for (std::filesystem::path folder = id.parent_path(); folder.has_relative_path(); folder = folder.parent_path()) {
      const auto outer = writers.lower_bound(std::pair(folder, std::ptrdiff_t(-1)));
      if (outer == writers.end() || outer->first.first != folder) continue;
      throw Error(outer->second.pattern->option + " " + outer->second.path.string() + " and " + writer.pattern->option +
                  " " + writer.path.string() + ": the one would have to be a folder holding the other");
    }
  }
}

void OutputClaims::claim(const std::vector<OutputPattern>& patterns, const OutputKey& job, const std::string& job_label) {
  try {
    check_distinct_outputs(patterns, {job});
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  std::vector<std::pair<std::filesystem::path, std::string>> mine;
  for (const OutputPattern& p : patterns) {
    const std::filesystem::path given = expand_output_pattern(p.pattern, job, p.option);
    if (output_is_stream(given)) continue;  // jobs may share it (check_distinct_outputs)
    const std::filesystem::path id = output_identity(given);
    const auto it = writers_.find(id);
    if (it != writers_.end())
      throw UsageError(p.option + " " + given.lexically_normal().string() + ": the " + it->second +
                       " writes it too, earlier in this batch");
    // A file of an earlier job as a folder of this one's, or the other way round.
    for (std::filesystem::path folder = id.parent_path(); folder.has_relative_path(); folder = folder.parent_path())
      if (const auto outer = writers_.find(folder); outer != writers_.end())
        throw UsageError(p.option + " " + given.lexically_normal().string() + ": the " + outer->second + " writes " +
                         folder.string() + ", earlier in this batch, a file where this needs a folder");
    for (auto inner = writers_.lower_bound(id); inner != writers_.end(); ++inner) {
      const auto [end, rest] = std::mismatch(id.begin(), id.end(), inner->first.begin(), inner->first.end());
      if (end != id.end()) break;  // sorted: past the paths under id
      throw UsageError(p.option + " " + given.lexically_normal().string() + ": the " + inner->second + " writes " +
                       inner->first.string() + " inside it, earlier in this batch");
    }
    mine.emplace_back(id, p.option + " of " + job_label);
  }
  writers_.insert(mine.begin(), mine.end());
}

}  // namespace zz
