#include "clipray/scene/loaders/GltfNames.hpp"

#include <tiny_gltf.h>

namespace clipray::meshfiles {

const char* modeName(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLES:
      return "TRIANGLES";
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN:
      return "TRIANGLE_FAN";
    default:
      return "unknown";
  }
}

std::string componentTypeName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "5120 (BYTE)";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "5121 (UNSIGNED_BYTE)";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "5122 (SHORT)";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "5123 (UNSIGNED_SHORT)";
    case TINYGLTF_COMPONENT_TYPE_INT:
      return "5124 (INT)";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "5125 (UNSIGNED_INT)";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "5126 (FLOAT)";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE:
      return "5130 (DOUBLE)";
    default:
      return std::to_string(componentType);
  }
}

std::string typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return std::to_string(type);
  }
}

}  // namespace clipray::meshfiles
