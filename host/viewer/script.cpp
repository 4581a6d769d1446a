#include "viewer/script.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "scene/scene.h"

namespace zz {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  for (size_t start = 0;;) {
    const size_t end = s.find(sep, start);
    parts.push_back(trim(s.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

float number(std::string_view s, std::string_view command) {
  const std::string text(s);
  char* end = nullptr;
  const float v = std::strtof(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size())
    throw Error("--script: '" + std::string(command) + "': '" + text + "' is not a number");
  // nan, inf and 1e39 (inf as a float) made the orbit camera NaN: zoom's clamp keeps a NaN.
  if (!std::isfinite(v)) throw Error("--script: '" + std::string(command) + "': '" + text + "' is not a finite number");
  return v;
}

}  // namespace

std::string script_key_name(std::string_view given) {
  auto upper = [](std::string_view text) {
    std::string u(text);
    for (char& c : u) c = char(std::toupper(static_cast<unsigned char>(c)));
    return u;
  };
  const std::string wanted = upper(given) == "ESCAPE" ? "ESC" : upper(given);
  for (std::string_view key : kScriptKeys)
    if (upper(key) == wanted) return std::string(key);
  return "";
}

std::vector<ScriptEvent> parse_script(std::string_view script) {
  std::vector<ScriptEvent> events;
  for (std::string_view command : split(script, ';')) {
    if (command.empty()) continue;
    const size_t colon = command.find(':');
    const std::string_view name = trim(command.substr(0, colon));
    const std::string_view arg = colon == std::string_view::npos ? std::string_view() : trim(command.substr(colon + 1));
    ScriptEvent e;
    auto args = [&](size_t min, size_t max) {
      std::vector<std::string_view> a = split(arg, ',');
      if (arg.empty() || a.size() < min || a.size() > max)
        throw Error("--script: '" + std::string(command) + "' needs " + std::to_string(min) +
                    (min == max ? "" : ".." + std::to_string(max)) + " comma-separated values");
      return a;
    };
    if (name == "drag") {
      const auto a = args(4, 5);
      e.kind = ScriptEvent::Kind::Drag;
      e.x0 = number(a[0], command);
      e.y0 = number(a[1], command);
      e.x1 = number(a[2], command);
      e.y1 = number(a[3], command);
      if (a.size() == 5) {
        if (a[4] == "left") e.button = 0;
        else if (a[4] == "right") e.button = 1;
        else if (a[4] == "middle") e.button = 2;
        else throw Error("--script: '" + std::string(command) + "': button must be left, right or middle");
      }
    } else if (name == "scroll") {
      e.kind = ScriptEvent::Kind::Scroll;
      e.steps = number(args(1, 1)[0], command);
    } else if (name == "key") {
      e.kind = ScriptEvent::Kind::Key;
      e.text = script_key_name(args(1, 1)[0]);
      if (e.text.empty()) {  // here, not when played: a typo must not leave the window open
        std::string keys;
        for (std::string_view k : kScriptKeys) {
          if (!keys.empty()) keys += ' ';
          keys += k;
        }
        throw Error("--script: '" + std::string(command) + "': unknown key (" + keys + ")");
      }
    } else if (name == "resize") {
      const auto a = args(2, 2);
      e.kind = ScriptEvent::Kind::Resize;
      e.x0 = number(a[0], command);
      e.y0 = number(a[1], command);
      if (!(e.x0 >= 1 && e.y0 >= 1 && e.x0 <= kMaxImageSide && e.y0 <= kMaxImageSide))
        throw Error("--script: '" + std::string(command) + "': size must be 1.." + std::to_string(kMaxImageSide) +
                    " per side");
    } else if (name == "wait" && arg.empty()) {
      e.kind = ScriptEvent::Kind::Wait;
    } else if (name == "sleep") {
      e.kind = ScriptEvent::Kind::Sleep;
      e.steps = number(args(1, 1)[0], command);
      if (!(e.steps >= 0.0f && e.steps <= 3600.0f))
        throw Error("--script: '" + std::string(command) + "': seconds must be 0..3600");
    } else if (name == "screenshot") {
      e.kind = ScriptEvent::Kind::Screenshot;
      e.text = std::string(arg);
      if (e.text.empty()) throw Error("--script: 'screenshot' needs a file name (screenshot:FILE)");
    } else if (name == "quit" && arg.empty()) {
      e.kind = ScriptEvent::Kind::Quit;
    } else {
      throw Error("--script: unknown command '" + std::string(command) +
                  "' (drag, scroll, key, resize, wait, sleep, screenshot, quit)");
    }
    events.push_back(std::move(e));
  }
  return events;
}

}  // namespace zz
