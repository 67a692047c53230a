// Checks on a glTF file's bytes and JSON made before tinygltf reads them (GltfPrechecks.hpp).

#include "clipray/scene/loaders/GltfPrechecks.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "clipray/io/InputFile.hpp"
#include "clipray/scene/loaders/MeshFileCommon.hpp"

namespace clipray::meshfiles {

namespace {

std::string indexText(const std::string& array, std::size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

std::uint32_t littleEndianU32(std::string_view bytes, std::size_t offset) {
  const auto byte = [&](std::size_t i) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[offset + i]));
  };
  return byte(0) | byte(1) << 8 | byte(2) << 16 | byte(3) << 24;
}

// tinygltf 2.7.0 copies a GLB buffer with `data.at(0)`, which throws std::out_of_range for a
// buffer whose byteLength is 0 (found by fuzz_glb). glTF requires byteLength >= 1, so that is
// checked on the JSON before tinygltf sees it. The JSON is parsed the way tinygltf parses it
// (nlohmann, later duplicate keys win), so both see the same buffers.
// What tinygltf would misreport: a glTF 1.0 file (tinygltf reads 2.0 only: "asset not found" or
// an empty model), compressed geometry a required extension names (tinygltf then fails on the
// accessors that have no buffer view), and primitives that are not an array (read as none).
void checkWhatClipraySupports(const nlohmann::json& document, const std::string& path) {
  const auto asset = document.find("asset");
  const auto meshes = document.find("meshes");
  // 1.0 wrote its version as "1.0", or as the number 1 (collada2gltf), and kept meshes, nodes
  // and the rest in dictionaries, where 2.0 has arrays.
  const nlohmann::json* version = nullptr;
  if (asset != document.end() && asset->is_object() && asset->contains("version")) {
    version = &(*asset)["version"];
  }
  const bool version1 =
      (version != nullptr && version->is_string() &&
       version->get<std::string>().starts_with("1")) ||
      (version != nullptr && version->is_number() && version->get<double>() < 2.0) ||
      (meshes != document.end() && meshes->is_object());
  if (version1) {
    fail(path, "asset.version",
         "glTF 1.0 is not supported; clipray reads glTF 2.0 (convert the file, e.g. with Blender "
         "or gltf-pipeline)");
  }
  const auto required = document.find("extensionsRequired");
  if (required != document.end() && required->is_array()) {
    for (const nlohmann::json& extension : *required) {
      if (!extension.is_string()) continue;
      const std::string name = extension.get<std::string>();
      const GltfExtensionUse use = gltfExtensionUse(name);
      if (use == GltfExtensionUse::Compressed || use == GltfExtensionUse::Unsupported) {
        fail(path, "extensionsRequired", unreadExtensionMessage(name));
      }
    }
  }
  if (meshes != document.end() && meshes->is_array()) {
    for (std::size_t i = 0; i < meshes->size(); ++i) {
      const nlohmann::json& mesh = (*meshes)[i];
      if (!mesh.is_object()) continue;
      const auto primitives = mesh.find("primitives");
      if (primitives != mesh.end() && !primitives->is_array()) {
        std::string found = primitives->dump();
        if (found.size() > 40) found = found.substr(0, 37) + "...";
        fail(path, indexText("meshes", i) + ".primitives",
             "expected an array of primitives, got " + found);
      }
    }
  }
}

// tinygltf reads offsets, lengths, strides and counts into unsigned integers: a negative one
// becomes 0 (or wraps), and the file would be read as something it does not say.
void checkSizesAreNonNegative(const nlohmann::json& document, const std::string& path) {
  static constexpr std::array<std::pair<const char*, std::array<const char*, 3>>, 3> kFields{{
      {"buffers", {"byteLength", nullptr, nullptr}},
      {"bufferViews", {"byteOffset", "byteLength", "byteStride"}},
      {"accessors", {"byteOffset", "count", nullptr}},
  }};
  for (const auto& [arrayName, fields] : kFields) {
    const auto array = document.find(arrayName);
    if (array == document.end() || !array->is_array()) continue;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const nlohmann::json& element = (*array)[i];
      if (!element.is_object()) continue;
      for (const char* field : fields) {
        if (field == nullptr) continue;
        const auto value = element.find(field);
        if (value == element.end() || !value->is_number()) continue;
        if (value->is_number_float() || value->get<double>() < 0.0) {
          fail(path, indexText(arrayName, i) + "." + field,
               "expected a non-negative integer, got " + value->dump());
        }
      }
    }
  }
}

}  // namespace

// The GLB container (header, JSON chunk, optional BIN chunk) is checked here before tinygltf sees
// it, so that lengths in the file never send a reader past the end and messages name the field.
std::string_view checkGlbContainer(std::string_view bytes, const std::string& path) {
  constexpr std::size_t kHeaderBytes = 12;
  constexpr std::size_t kChunkHeaderBytes = 8;
  constexpr std::uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
  constexpr std::uint32_t kBinChunk = 0x004E4942;   // "BIN\0"
  if (bytes.size() < kHeaderBytes + kChunkHeaderBytes) {
    fail(path, "glb header",
         "a GLB needs at least 20 bytes (header and JSON chunk header), got " +
             std::to_string(bytes.size()));
  }
  if (bytes.substr(0, 4) != "glTF") {
    fail(path, "glb header", "expected the magic \"glTF\", got " + quotedText(bytes.substr(0, 4)));
  }
  const std::uint32_t version = littleEndianU32(bytes, 4);
  if (version == 1) {
    fail(path, "glb header",
         "version 1: glTF 1.0 is not supported; clipray reads glTF 2.0 (convert the file, e.g. "
         "with Blender or gltf-pipeline)");
  }
  if (version != 2) fail(path, "glb header", "version must be 2, got " + std::to_string(version));
  const std::uint32_t length = littleEndianU32(bytes, 8);
  if (length != bytes.size()) {
    fail(path, "glb header",
         "length " + std::to_string(length) + " differs from the file size " +
             std::to_string(bytes.size()));
  }
  std::size_t offset = kHeaderBytes;
  for (int chunk = 0; offset < bytes.size(); ++chunk) {
    const std::string element = "glb chunk " + std::to_string(chunk);
    if (bytes.size() - offset < kChunkHeaderBytes) {
      fail(path, element,
           "the chunk header needs 8 bytes, got " + std::to_string(bytes.size() - offset));
    }
    const std::uint32_t chunkLength = littleEndianU32(bytes, offset);
    const std::uint32_t chunkType = littleEndianU32(bytes, offset + 4);
    if (chunk == 0 && chunkType != kJsonChunk) {
      fail(path, element, "the first chunk must be JSON, got type " + std::to_string(chunkType));
    }
    if (chunk == 1 && chunkType != kBinChunk) {
      fail(path, element, "the second chunk must be BIN, got type " + std::to_string(chunkType));
    }
    if (chunkLength > bytes.size() - offset - kChunkHeaderBytes) {
      fail(path, element,
           "length " + std::to_string(chunkLength) + " exceeds the " +
               std::to_string(bytes.size() - offset - kChunkHeaderBytes) + " bytes left");
    }
    offset += kChunkHeaderBytes + chunkLength;
    if (chunk >= 1) break;  // chunks after BIN are extensions' business; tinygltf ignores them
  }
  return bytes.substr(kHeaderBytes + kChunkHeaderBytes, littleEndianU32(bytes, kHeaderBytes));
}

void checkGltfJson(std::string_view jsonText, const std::string& path) {
  // tinygltf copies `extras` and `extensions` recursively: bound the nesting before it does.
  const auto boundedDepth = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
    if ((event == nlohmann::json::parse_event_t::object_start ||
         event == nlohmann::json::parse_event_t::array_start) &&
        depth >= static_cast<int>(kMaxJsonDepth)) {
      fail(
          path, "gltf",
          "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels; glTF needs a few");
    }
    return true;
  };
  const nlohmann::json document = nlohmann::json::parse(jsonText, boundedDepth, false);
  if (!document.is_object()) return;  // tinygltf reports malformed JSON with its own message
  checkWhatClipraySupports(document, path);
  checkSizesAreNonNegative(document, path);
  const auto buffers = document.find("buffers");
  if (buffers == document.end() || !buffers->is_array()) return;
  for (std::size_t i = 0; i < buffers->size(); ++i) {
    const nlohmann::json& buffer = (*buffers)[i];
    if (!buffer.is_object()) continue;
    const auto length = buffer.find("byteLength");
    if (length == buffer.end() || !length->is_number()) continue;  // tinygltf requires a number
    if (!(length->get<double>() >= 1.0)) {
      fail(path, indexText("buffers", i) + ".byteLength",
           "expected an integer of at least 1, got " + length->dump());
    }
  }
}

GltfExtensionUse gltfExtensionUse(std::string_view name) {
  if (name == "KHR_mesh_quantization") return GltfExtensionUse::Read;
  if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" ||
      name == "KHR_meshopt_compression") {
    return GltfExtensionUse::Compressed;
  }
  // Extensions that change how surfaces are shaded, never their positions, so the depth and the
  // ids clipray compares are those of the file without them.
  static constexpr std::array<std::string_view, 4> kShadingPrefixes{
      "KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_"};
  for (std::string_view prefix : kShadingPrefixes) {
    if (name.starts_with(prefix)) return GltfExtensionUse::IgnoredNoDepth;
  }
  if (name == "KHR_lights_punctual" || name == "EXT_lights_image_based" || name == "KHR_xmp" ||
      name == "KHR_xmp_json_ld") {
    return GltfExtensionUse::IgnoredNoDepth;
  }
  return GltfExtensionUse::Unsupported;
}

std::string unreadExtensionMessage(std::string_view name) {
  if (gltfExtensionUse(name) == GltfExtensionUse::Compressed) {
    return "compressed geometry (" + std::string(name) +
           ") is not supported; decompress it first (e.g. gltf-transform or gltfpack)";
  }
  return quotedText(name) +
         " is not supported: it may change what is drawn where (clipray reads "
         "KHR_mesh_quantization and ignores material, texture and light extensions)";
}

}  // namespace clipray::meshfiles
