#include "viewer/script.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace zz {
namespace {

TEST(Script, ParsesEveryCommand) {
  const auto e = parse_script(" drag:10,20,30.5,40 ; drag:1,2,3,4,right;scroll:-2;key:R;resize:300,200;"
                              "wait;screenshot:out/a b.png;quit;sleep:1.5");
  ASSERT_EQ(e.size(), 9u);
  EXPECT_EQ(e[0].kind, ScriptEvent::Kind::Drag);
  EXPECT_EQ(e[0].x0, 10.0f);
  EXPECT_EQ(e[0].y1, 40.0f);
  EXPECT_EQ(e[0].x1, 30.5f);
  EXPECT_EQ(e[0].button, 0);
  EXPECT_EQ(e[1].button, 1);
  EXPECT_EQ(e[2].kind, ScriptEvent::Kind::Scroll);
  EXPECT_EQ(e[2].steps, -2.0f);
  EXPECT_EQ(e[3].kind, ScriptEvent::Kind::Key);
  EXPECT_EQ(e[3].text, "R");
  EXPECT_EQ(e[4].kind, ScriptEvent::Kind::Resize);
  EXPECT_EQ(e[4].x0, 300.0f);
  EXPECT_EQ(e[5].kind, ScriptEvent::Kind::Wait);
  EXPECT_EQ(e[6].kind, ScriptEvent::Kind::Screenshot);
  EXPECT_EQ(e[6].text, "out/a b.png");
  EXPECT_EQ(e[7].kind, ScriptEvent::Kind::Quit);
  EXPECT_EQ(e[8].kind, ScriptEvent::Kind::Sleep);
  EXPECT_EQ(e[8].steps, 1.5f);
  EXPECT_TRUE(parse_script("").empty());
}

TEST(Script, RejectsBadCommandsWithTheCommandInTheMessage) {
  for (const char* bad : {"drag:1,2,3", "drag:1,2,3,x", "drag:1,2,3,4,up", "jump", "wait:3", "screenshot:",
                          "resize:0,10", "scroll:",
                          "sleep:", "sleep:-1", "sleep:nan", "sleep:1e9",
                          // a NaN or infinite drag or zoom turned the orbit camera NaN until R
                          "scroll:nan", "scroll:inf", "scroll:1e39", "drag:nan,0,10,10", "drag:0,0,-inf,0"}) {
    try {
      parse_script(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--script"), std::string::npos) << e.what();
    }
  }
}

// Each value is checked on its own: middle is GLFW's button 2; resize wants both sides in
// 1..kMaxImageSide; a command takes no more values than it has; a number is a number
// to its end ("4e" is not 4).
TEST(Script, EachValueIsCheckedOnItsOwn) {
  EXPECT_EQ(parse_script("drag:1,2,3,4,middle")[0].button, 2);
  EXPECT_EQ(parse_script("drag:1,2,3,4,left")[0].button, 0);
  EXPECT_EQ(parse_script("resize:1,16384")[0].y0, 16384.0f);
  for (const char* bad : {"resize:10,0", "resize:10,-3", "scroll:1,2", "key:R,S", "sleep:1,2", "resize:1,2,3",
                          "drag:1,2,3,4,left,6", "scroll:2x", "drag:1,2,3,4e", "resize:10,20px"}) {
    try {
      parse_script(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--script"), std::string::npos) << e.what();
    }
  }
}

// Keys are checked when the script is read, not when played (a typo left the window
// open until killed), in any case, with the README's spelling of Escape.
TEST(Script, KeysAreNamedAsTheViewerKnowsThem) {
  EXPECT_EQ(parse_script("key:r")[0].text, "R");
  EXPECT_EQ(parse_script("key:]")[0].text, "]");
  for (const char* esc : {"key:Esc", "key:ESC", "key:esc", "key:Escape"}) EXPECT_EQ(parse_script(esc)[0].text, "Esc") << esc;
  for (const char* bad : {"key:Q", "key:Enter", "key:RS", "key:1.5"}) {
    try {
      parse_script(std::string("wait;") + bad + ";quit");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("unknown key"), std::string::npos) << bad << ": " << e.what();
    }
  }
}

}  // namespace
}  // namespace zz
