#pragma once
// What `clipray check` is told about an app, as the user wrote it: the command line's values or
// a check file's fields (keys in camelCase, matrices as 16 numbers or a string of them), and how
// they become the checker's input. Every mistake is an InputError naming the field and the value.

#include <string>

#include "clipray/check/ConventionCheck.hpp"

namespace clipray {

struct CheckFields {
  std::string clipFromWorld, projection, view;
  std::string layout = "column-major";  // column-major, row-major, xmmatrix
  std::string declaredDepth;            // no, zo, zo-reversed (any case)
  bool reversed = false;
  std::string depthRange;  // "NEAR,FAR"
  std::string origin;      // lower-left, upper-left
  std::string viewport = "1920x1080";
  std::string depthBits = "24";  // 16, 24, 32f
  std::string sceneExtent;       // "minx miny minz maxx maxy maxz"
  std::string precision;         // float, double
  std::string nearPlane, farPlane;
  std::string cull;         // none, back, front (glCullFace with GL_CULL_FACE enabled)
  std::string frontFace;    // ccw, cw (glFrontFace)
  bool depthClamp = false;  // glEnable(GL_DEPTH_CLAMP)
};

// A check file's JSON text; `file` names it in messages. Unknown keys and wrong types are refused.
CheckFields parseCheckFile(const std::string& text, const std::string& file);

// The checker's input. `where` prefixes every message ("app.json: ", or "" for the command line).
CheckInput checkInputFrom(const CheckFields& fields, const std::string& where);

}  // namespace clipray
