#pragma once
// What clipray checks in a glTF file before tinygltf reads it (internal to clipray_core): the GLB
// container's lengths, and the JSON fields tinygltf would crash on or misreport (glTF 1.0,
// compressed geometry, primitives that are not an array, empty buffers). Also which glTF
// extensions clipray reads, ignores or refuses.

#include <string>
#include <string_view>

namespace clipray::meshfiles {

// Checks the GLB header and chunk lengths; returns the JSON chunk. Throws InputError naming the
// field ("glb header", "glb chunk 1").
std::string_view checkGlbContainer(std::string_view bytes, const std::string& path);

// Checks the JSON of a .gltf file or a GLB's JSON chunk. Malformed JSON passes: tinygltf reports
// it with its own message.
void checkGltfJson(std::string_view jsonText, const std::string& path);

enum class GltfExtensionUse {
  Read,            // KHR_mesh_quantization: integer positions, decoded as GL decodes them
  IgnoredNoDepth,  // materials, textures, lights: they change colours, never what is drawn where
  Compressed,      // Draco, meshopt: the geometry is in a form clipray does not decode
  Unsupported,     // anything else: it may move or add geometry (instancing, shader techniques)
};
GltfExtensionUse gltfExtensionUse(std::string_view name);

// The message for a required extension clipray does not read (Compressed or Unsupported).
std::string unreadExtensionMessage(std::string_view name);

}  // namespace clipray::meshfiles
