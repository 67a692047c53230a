#pragma once
// The names of glTF 2.0's numeric enums (primitive modes, accessor component types and types), as
// messages quote them: "mode 1 (LINES)", "5123 (UNSIGNED_SHORT)", "VEC3". Internal to the glTF
// reader.

#include <string>

namespace clipray::meshfiles {

const char* modeName(int mode);                    // "TRIANGLES", "unknown"
std::string componentTypeName(int componentType);  // "5126 (FLOAT)", or the number
std::string typeName(int type);                    // "VEC3", or the number

}  // namespace clipray::meshfiles
