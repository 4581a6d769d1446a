// Scripted input for tests and demos (`zigzag view --script "..."`): the viewer runs
// these through the same handlers as real mouse/keyboard input, so a test can drag the
// camera without an X input tool. Grammar (commands separated by ';'):
//   drag:x0,y0,x1,y1[,button]   button: left (default) | right | middle
//   scroll:steps                wheel steps (positive = zoom in)
//   key:K                       one key: R S F E 1 2 3 4 [ ] or Esc (any case; Escape)
//   resize:w,h                  resize the window
//   wait                        until the current frame is fully rendered
//   sleep:seconds               let the viewer run that long (e.g. to act mid-frame)
//   screenshot:FILE             save the current view as PNG
//   quit
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace zz {

struct ScriptEvent {
  enum class Kind { Drag, Scroll, Key, Resize, Wait, Sleep, Screenshot, Quit } kind = Kind::Wait;
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // drag endpoints (pixels); resize uses x0,y0
  int button = 0;                        // 0 left, 1 right, 2 middle (GLFW numbering)
  float steps = 0;                       // scroll; seconds of a sleep
  std::string text;                      // key name or screenshot path
};

// Throws zz::Error naming the bad command.
std::vector<ScriptEvent> parse_script(std::string_view script);

// The keys a script may press, by the viewer's names for them (viewer.cpp maps each to
// its GLFW key, in this order).
inline constexpr std::array<std::string_view, 11> kScriptKeys = {"R", "S", "F", "E", "1", "2",
                                                                 "3", "4", "[", "]", "Esc"};

// The viewer's name of a key a script may press ("r" -> "R", "escape" -> "Esc"); empty
// for a key the viewer has no use for. A Key event's text is always such a name.
std::string script_key_name(std::string_view given);

}  // namespace zz
