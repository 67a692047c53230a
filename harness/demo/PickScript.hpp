#pragma once
// `clipray-pick --script FILE`: clicks, drags, wheel steps, keys and resizes replayed through the
// same handlers as the mouse and keyboard. One command a line; '#' starts a comment.
//
//   resize W H               window size in screen units
//   click X Y                cursor position in window coordinates (top-left origin)
//   drag left|right X0 Y0 X1 Y1
//   scroll STEPS             wheel steps, positive zooms in
//   key K                    one of the demo's keys (c o d m v t r h p)

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace clipray::demo {

struct ScriptCommand {
  enum class Kind { Resize, Click, Drag, Scroll, Key };
  Kind kind = Kind::Click;
  int line = 0;
  glm::dvec2 a{0.0}, b{0.0};  // resize: a = size; click: a; drag: a -> b
  bool rightButton = false;   // drag
  double steps = 0.0;         // scroll
  char key = 0;               // lower-case letter
};

// The keys a script may press (the demo's key bindings, lower case).
inline constexpr const char* kScriptKeys = "codmvtrhp";

// Throws InputError "FILE:LINE: ..." for anything it does not understand.
std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& path);
std::vector<ScriptCommand> loadScript(const std::string& path);

}  // namespace clipray::demo
