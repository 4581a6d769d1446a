#include "app/output_paths.h"

#include <cstdio>
#include <map>

#include "core/error.h"

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
    char buf[64];
    std::snprintf(buf, sizeof buf, "%0*d", std::stoi(width), key.frame);
    return out += buf, true;
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

}  // namespace

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

void check_distinct_outputs(const std::vector<OutputPattern>& patterns, const std::vector<OutputKey>& jobs) {
  struct Writer {
    const OutputPattern* pattern;
    const OutputKey* job;
  };
  std::map<std::filesystem::path, Writer> writers;
  for (const OutputPattern& p : patterns)
    for (const OutputKey& job : jobs) {
      const std::filesystem::path path =
          std::filesystem::path(expand_output_pattern(p.pattern, job, p.option)).lexically_normal();
      const auto [it, inserted] = writers.emplace(path, Writer{&p, &job});
      if (inserted) continue;
      const Writer& first = it->second;
      if (first.pattern == &p) {
        const std::string missing = missing_placeholder(p.pattern, *first.job, job);
        throw Error(p.option + " " + p.pattern + ": jobs " + job_name(*first.job, jobs) + " and " +
                    job_name(job, jobs) + " would both write " + path.string() +
                    (missing.empty() ? " (their scene files have the same name)" : " (add " + missing + ")"));
      }
      throw Error(first.pattern->option + " and " + p.option + " would both write " + path.string());
    }
}

}  // namespace zz
