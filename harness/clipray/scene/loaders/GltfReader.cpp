// glTF 2.0 (.gltf with external or data: buffers, and .glb) through tinygltf, compiled in here
// without image support: clipray needs geometry and cameras only. tinygltf parses the JSON and
// loads the buffers but checks little of what they say, so every index, accessor range, type and
// transform is validated here before a byte is read.

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "clipray/scene/loaders/GltfNames.hpp"
#include "clipray/scene/loaders/GltfPrechecks.hpp"
#include "clipray/scene/loaders/MeshFileCommon.hpp"

namespace clipray::meshfiles {

namespace {

constexpr int kDefaultViewportWidth = 320;
constexpr int kDefaultViewportHeight = 240;
constexpr double kMaxViewportDimension = 16384;
// A rotation quaternion shorter than this has no direction to normalise.
constexpr double kMinQuaternionLength = 1e-12;

// ---- File access for external buffers --------------------------------------------------------
// tinygltf's defaults would open anything (devices, FIFOs); only regular files are read here.

bool regularFileExists(const std::string& path, void* /*userData*/) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error);
}

std::string pathUnchanged(const std::string& path, void* /*userData*/) {
  return path;
}

bool readRegularFile(std::vector<unsigned char>* out, std::string* error, const std::string& path,
                     void* /*userData*/) {
  std::error_code fsError;
  const bool regular = std::filesystem::is_regular_file(path, fsError);
  const std::uintmax_t size = regular ? std::filesystem::file_size(path, fsError) : 0;
  // glTF buffers are at most 2^32 bytes here (tinygltf sizes); a bigger "file" is something like
  // /proc/kcore, which must not be read.
  if (!regular || fsError || size > std::numeric_limits<std::uint32_t>::max()) {
    if (error) *error += "cannot open file \"" + path + "\"\n";
    return false;
  }
  std::ifstream stream(path, std::ios::binary);
  out->resize(static_cast<std::size_t>(size));
  if (!stream.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
    if (error) *error += "cannot read file \"" + path + "\"\n";
    return false;
  }
  return true;
}

bool writeNothing(std::string* error, const std::string& /*path*/,
                  const std::vector<unsigned char>& /*contents*/, void* /*userData*/) {
  if (error) *error += "clipray never writes glTF files\n";
  return false;
}

// Images are not geometry: accept them without decoding.
bool ignoreImage(tinygltf::Image* /*image*/, const int /*imageIndex*/, std::string* /*error*/,
                 std::string* /*warning*/, int /*requestedWidth*/, int /*requestedHeight*/,
                 const unsigned char* /*bytes*/, int /*size*/, void* /*userData*/) {
  return true;
}

std::string trimmed(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::replace(text.begin(), text.end(), '\n', ';');
  return text;
}

std::string indexText(const std::string& array, std::size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

// Bytes of one accessor, proven in bounds: element i starts at data + i * stride.
struct AccessorBytes {
  const unsigned char* data = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
};

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, const std::string& path, const glm::dmat4& worldFromFile)
      : model_(model), path_(path), worldFromFile_(worldFromFile) {}

  MeshFileContents read() {
    for (const std::string& extension : model_.extensionsRequired) {
      const GltfExtensionUse use = gltfExtensionUse(extension);
      if (use == GltfExtensionUse::Compressed || use == GltfExtensionUse::Unsupported) {
        fail(path_, "extensionsRequired", unreadExtensionMessage(extension));
      }
    }
    quantizedPositions_ = std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(),
                                    "KHR_mesh_quantization") != model_.extensionsUsed.end();
    meshCache_.resize(model_.meshes.size());
    std::size_t meshInstances = 0;
    for (const auto& [node, world] : placedNodes()) {
      const tinygltf::Node& placed = model_.nodes[node];
      meshInstances += placed.mesh >= 0 ? 1 : 0;
      if (placed.mesh >= 0) addMeshInstance(node, world);
      if (placed.camera >= 0) addCamera(node, world);
    }
    if (contents_.objects.empty() && model_.meshes.empty()) {
      fail(path_, "meshes", "the file has no meshes: nothing to draw");
    }
    if (contents_.objects.empty() && meshInstances == 0) {
      fail(path_, model_.scenes.empty() ? "nodes" : "scene",
           "no node places any of the file's " + std::to_string(model_.meshes.size()) +
               " meshes: nothing to draw");
    }
    warnAboutWhatIsIgnored();
    return std::move(contents_);
  }

 private:
  // clipray compares static geometry: materials, textures and the extensions it does not read
  // (optional ones: the file stays valid without them) do not change depth, and skins, morph
  // targets and animations are read in their bind pose (node transforms, no weights). One warning
  // says which the file has, so that nobody takes the reconcile for the animated asset.
  void warnAboutWhatIsIgnored() {
    std::size_t morphed = 0;
    for (const tinygltf::Mesh& mesh : model_.meshes) {
      for (const tinygltf::Primitive& primitive : mesh.primitives) {
        morphed += primitive.targets.empty() ? 0 : 1;
      }
    }
    std::vector<std::string> parts;
    const auto count = [&](std::size_t n, const char* what) {
      if (n > 0) parts.push_back(std::to_string(n) + " " + what);
    };
    count(model_.textures.size(), "textures");
    count(model_.skins.size(), "skins");
    count(morphed, "primitives with morph targets");
    count(model_.animations.size(), "animations");
    std::string extensions;
    for (const std::string& extension : model_.extensionsUsed) {
      if (gltfExtensionUse(extension) == GltfExtensionUse::Read) continue;
      extensions += (extensions.empty() ? "" : ", ") + extension;
    }
    if (!extensions.empty()) parts.push_back("the extensions " + extensions);
    if (parts.empty()) return;
    std::string list;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      list += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
    }
    contents_.warnings.push_back(path_ + ": " + list +
                                 " ignored: clipray compares the static geometry in its bind pose");
  }

  // ---- Scene graph -----------------------------------------------------------------------------

  void checkNodeIndex(int index, const std::string& element) const {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.nodes.size()) {
      fail(path_, element,
           "node index " + std::to_string(index) + " out of range for " +
               std::to_string(model_.nodes.size()) + " nodes");
    }
  }

  std::vector<int> rootNodes() const {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (static_cast<std::size_t>(scene) >= model_.scenes.size()) {
        fail(path_, "scene",
             "scene index " + std::to_string(scene) + " out of range for " +
                 std::to_string(model_.scenes.size()) + " scenes");
      }
      const std::vector<int>& nodes = model_.scenes[static_cast<std::size_t>(scene)].nodes;
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        checkNodeIndex(nodes[i], indexText("scenes", static_cast<std::size_t>(scene)) +
                                     indexText(".nodes", i));
        roots.push_back(nodes[i]);
      }
      return roots;
    }
    // No scenes: every node that is nobody's child is a root.
    std::vector<char> isChild(model_.nodes.size(), 0);
    for (std::size_t n = 0; n < model_.nodes.size(); ++n) {
      const std::vector<int>& children = model_.nodes[n].children;
      for (std::size_t c = 0; c < children.size(); ++c) {
        checkNodeIndex(children[c], indexText("nodes", n) + indexText(".children", c));
        isChild[static_cast<std::size_t>(children[c])] = 1;
      }
    }
    for (std::size_t n = 0; n < model_.nodes.size(); ++n) {
      if (!isChild[n]) roots.push_back(static_cast<int>(n));
    }
    return roots;
  }

  glm::dmat4 localMatrix(std::size_t nodeIndex) const {
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    const std::string element = indexText("nodes", nodeIndex);
    const bool hasTrs = !node.translation.empty() || !node.rotation.empty() || !node.scale.empty();
    auto checkFinite = [&](const std::vector<double>& values, const char* name) {
      for (std::size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(values[i])) {
          fail(path_, element + "." + name,
               "element " + std::to_string(i) + " is not finite, got " + formatNumber(values[i]));
        }
      }
    };
    glm::dmat4 local(1.0);
    if (!node.matrix.empty()) {
      if (hasTrs) fail(path_, element, "has both \"matrix\" and translation/rotation/scale");
      if (node.matrix.size() != 16) {
        fail(path_, element + ".matrix",
             "expected 16 numbers, got " + std::to_string(node.matrix.size()));
      }
      checkFinite(node.matrix, "matrix");
      for (int column = 0; column < 4; ++column) {
        for (int row = 0; row < 4; ++row) {
          local[column][row] = node.matrix[static_cast<std::size_t>(4 * column + row)];
        }
      }
      const std::string why = whyNotInvertibleAffine(local);
      if (!why.empty()) fail(path_, element + ".matrix", why);
      return local;
    }
    auto checkSize = [&](const std::vector<double>& values, const char* name, std::size_t size) {
      if (!values.empty() && values.size() != size) {
        fail(path_, element + "." + name,
             "expected " + std::to_string(size) + " numbers, got " + std::to_string(values.size()));
      }
      checkFinite(values, name);
    };
    checkSize(node.translation, "translation", 3);
    checkSize(node.rotation, "rotation", 4);
    checkSize(node.scale, "scale", 3);
    glm::dvec3 translation(0.0);
    glm::dvec3 scale(1.0);
    glm::dquat rotation(1.0, 0.0, 0.0, 0.0);  // (w, x, y, z)
    if (!node.translation.empty()) {
      translation = {node.translation[0], node.translation[1], node.translation[2]};
    }
    if (!node.scale.empty()) {
      scale = {node.scale[0], node.scale[1], node.scale[2]};
      if (scale.x == 0.0 || scale.y == 0.0 || scale.z == 0.0) {
        fail(path_, element + ".scale",
             "a zero scale factor makes the transform non-invertible, got " + formatVector(scale));
      }
    }
    if (!node.rotation.empty()) {
      // glTF stores the quaternion as x, y, z, w.
      rotation = glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
      const double length = glm::length(rotation);
      if (!(length >= kMinQuaternionLength) || !std::isfinite(length)) {
        fail(path_, element + ".rotation",
             "expected a unit quaternion, got length " + formatNumber(length));
      }
      rotation /= length;
    }
    glm::dmat4 translate(1.0);
    translate[3] = glm::dvec4(translation, 1.0);
    glm::dmat4 scaleMatrix(1.0);
    scaleMatrix[0][0] = scale.x;
    scaleMatrix[1][1] = scale.y;
    scaleMatrix[2][2] = scale.z;
    local = translate * glm::dmat4(glm::mat3_cast(rotation)) * scaleMatrix;
    const std::string why = whyNotInvertibleAffine(local);
    if (!why.empty()) fail(path_, element, why);
    return local;
  }

  // Every node reachable from the roots with its world matrix (worldFromFile included), parents
  // before children. Iterative, so a deep hierarchy cannot overflow the stack; a node reached
  // twice (a cycle, or a child of two parents) is an error, as glTF requires a forest.
  std::vector<std::pair<std::size_t, glm::dmat4>> placedNodes() const {
    std::vector<std::pair<std::size_t, glm::dmat4>> placed;
    std::vector<char> visited(model_.nodes.size(), 0);
    std::vector<std::pair<std::size_t, glm::dmat4>> pending;
    const std::vector<int> roots = rootNodes();
    for (auto root = roots.rbegin(); root != roots.rend(); ++root) {
      pending.emplace_back(static_cast<std::size_t>(*root), worldFromFile_);
    }
    while (!pending.empty()) {
      const auto [nodeIndex, parentWorld] = pending.back();
      pending.pop_back();
      const std::string element = indexText("nodes", nodeIndex);
      if (visited[nodeIndex]) {
        fail(path_, element,
             "the node is reached twice (a cycle, or a child of two parents, or listed twice)");
      }
      visited[nodeIndex] = 1;
      const glm::dmat4 world = parentWorld * localMatrix(nodeIndex);
      const std::string why = whyNotInvertibleAffine(world);
      if (!why.empty()) fail(path_, element, "world transform: " + why);
      placed.emplace_back(nodeIndex, world);
      const std::vector<int>& children = model_.nodes[nodeIndex].children;
      for (std::size_t c = children.size(); c-- > 0;) {
        checkNodeIndex(children[c], element + indexText(".children", c));
        pending.emplace_back(static_cast<std::size_t>(children[c]), world);
      }
    }
    return placed;
  }

  // ---- Accessors -------------------------------------------------------------------------------

  AccessorBytes accessorBytes(int accessorIndex, const std::string& reference, int wantedType,
                              const std::vector<int>& wantedComponentTypes,
                              bool mayBeNormalized = false) const {
    if (accessorIndex < 0 || static_cast<std::size_t>(accessorIndex) >= model_.accessors.size()) {
      fail(path_, reference,
           "accessor index " + std::to_string(accessorIndex) + " out of range for " +
               std::to_string(model_.accessors.size()) + " accessors");
    }
    const auto index = static_cast<std::size_t>(accessorIndex);
    const tinygltf::Accessor& accessor = model_.accessors[index];
    // "accessors[2] (POSITION of meshes[0].primitives[0])"
    const std::string element = indexText("accessors", index) + " (" + reference + ")";
    if (accessor.sparse.isSparse) fail(path_, element, "sparse accessors are not supported");
    if (accessor.type != wantedType) {
      fail(path_, element,
           "expected type " + typeName(wantedType) + ", got " + typeName(accessor.type));
    }
    if (std::find(wantedComponentTypes.begin(), wantedComponentTypes.end(),
                  accessor.componentType) == wantedComponentTypes.end()) {
      std::string wanted;
      for (int type : wantedComponentTypes) {
        wanted += (wanted.empty() ? "" : " or ") + componentTypeName(type);
      }
      fail(path_, element,
           "expected componentType " + wanted + ", got " +
               componentTypeName(accessor.componentType));
    }
    if (accessor.normalized && !mayBeNormalized) {
      fail(path_, element, "normalized accessors are not supported here");
    }
    if (accessor.count == 0) fail(path_, element, "count must be at least 1, got 0");
    if (accessor.bufferView < 0 ||
        static_cast<std::size_t>(accessor.bufferView) >= model_.bufferViews.size()) {
      fail(path_, element,
           "bufferView index " + std::to_string(accessor.bufferView) + " out of range for " +
               std::to_string(model_.bufferViews.size()) + " bufferViews");
    }
    const auto viewIndex = static_cast<std::size_t>(accessor.bufferView);
    const tinygltf::BufferView& view = model_.bufferViews[viewIndex];
    const std::string viewElement = indexText("bufferViews", viewIndex);
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size()) {
      fail(path_, viewElement,
           "buffer index " + std::to_string(view.buffer) + " out of range for " +
               std::to_string(model_.buffers.size()) + " buffers");
    }
    const auto bufferIndex = static_cast<std::size_t>(view.buffer);
    const std::vector<unsigned char>& buffer = model_.buffers[bufferIndex].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset) {
      fail(path_, viewElement,
           "byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
               std::to_string(view.byteLength) + " exceeds " + indexText("buffers", bufferIndex) +
               " length " + std::to_string(buffer.size()));
    }
    const auto componentSize = static_cast<std::size_t>(
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType)));
    const auto componentCount = static_cast<std::size_t>(
        tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type)));
    const std::size_t elementSize = componentSize * componentCount;
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
    if (stride < elementSize) {
      fail(path_, viewElement,
           "byteStride " + std::to_string(stride) + " is smaller than the element size " +
               std::to_string(elementSize) + " of " + element);
    }
    // offset + stride * (count - 1) + elementSize <= byteLength, without overflowing.
    const bool fits =
        accessor.byteOffset <= view.byteLength &&
        elementSize <= view.byteLength - accessor.byteOffset &&
        accessor.count - 1 <= (view.byteLength - accessor.byteOffset - elementSize) / stride;
    if (!fits) {
      fail(path_, element,
           "count " + std::to_string(accessor.count) + " x stride " + std::to_string(stride) +
               " + offset " + std::to_string(accessor.byteOffset) + " exceeds " + viewElement +
               " length " + std::to_string(view.byteLength));
    }
    return {buffer.data() + view.byteOffset + accessor.byteOffset, stride, accessor.count};
  }

  // ---- Meshes ----------------------------------------------------------------------------------

  // FLOAT, or with KHR_mesh_quantization declared, (UNSIGNED_)BYTE or (UNSIGNED_)SHORT, normalized
  // or not; anything else fails naming the accessor. Out-of-range accessor indices are left to
  // accessorBytes, which names them.
  int positionComponentTypeChecked(int accessorIndex, const std::string& element) const {
    if (accessorIndex < 0 || static_cast<std::size_t>(accessorIndex) >= model_.accessors.size()) {
      return TINYGLTF_COMPONENT_TYPE_FLOAT;
    }
    const auto index = static_cast<std::size_t>(accessorIndex);
    const int type = model_.accessors[index].componentType;
    const bool integer =
        type == TINYGLTF_COMPONENT_TYPE_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
        type == TINYGLTF_COMPONENT_TYPE_SHORT || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if (type == TINYGLTF_COMPONENT_TYPE_FLOAT || (integer && quantizedPositions_)) return type;
    std::string message = "expected componentType 5126 (FLOAT)";
    if (quantizedPositions_) message += " or an 8- or 16-bit integer type (KHR_mesh_quantization)";
    message += ", got " + componentTypeName(type);
    if (integer) message += "; integer positions need KHR_mesh_quantization in extensionsUsed";
    fail(path_, indexText("accessors", index) + " (POSITION of " + element + ")", message);
  }

  // One position as GL's vertex fetch reads it: a float as it is, an integer as its value, or
  // normalized as glTF 2.0 (3.11) and GL 4.6 (2.3.5.1) define it: c / (2^b - 1) unsigned,
  // max(c / (2^(b-1) - 1), -1) signed.
  static glm::dvec3 positionAt(const unsigned char* at, int componentType, bool normalized) {
    glm::dvec3 value;
    for (int axis = 0; axis < 3; ++axis) {
      switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
          std::int8_t c;
          std::memcpy(&c, at + axis, 1);
          value[axis] = normalized ? std::max(c / 127.0, -1.0) : c;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          value[axis] = normalized ? at[axis] / 255.0 : at[axis];
          break;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
          std::int16_t c;
          std::memcpy(&c, at + 2 * axis, 2);
          value[axis] = normalized ? std::max(c / 32767.0, -1.0) : c;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t c;
          std::memcpy(&c, at + 2 * axis, 2);
          value[axis] = normalized ? c / 65535.0 : c;
          break;
        }
        default: {
          float c;
          std::memcpy(&c, at + 4 * axis, 4);
          value[axis] = c;
        }
      }
    }
    return value;
  }

  // The primitives of one mesh in the mesh's own frame, validated once however often it is placed.
  const std::vector<MeshObject>& meshPrimitives(std::size_t meshIndex) {
    std::optional<std::vector<MeshObject>>& cached = meshCache_[meshIndex];
    if (cached) return *cached;
    const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
    std::vector<MeshObject> primitives;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      primitives.push_back(readPrimitive(meshIndex, p));
    }
    cached = std::move(primitives);
    return *cached;
  }

  MeshObject readPrimitive(std::size_t meshIndex, std::size_t primitiveIndex) const {
    const tinygltf::Primitive& primitive = model_.meshes[meshIndex].primitives[primitiveIndex];
    const std::string element =
        indexText("meshes", meshIndex) + indexText(".primitives", primitiveIndex);
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      fail(path_, element + ".mode",
           "mode " + std::to_string(mode) + " (" + modeName(mode) +
               ") is not supported; only TRIANGLES (4), TRIANGLE_STRIP (5) and TRIANGLE_FAN (6): "
               "clipray compares surfaces, and points and lines have none");
    }
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) {
      fail(path_, element + ".attributes", "missing the POSITION attribute");
    }
    MeshObject object;
    const int positionComponentType = positionComponentTypeChecked(position->second, element);
    const AccessorBytes positions = accessorBytes(
        position->second, "POSITION of " + element, TINYGLTF_TYPE_VEC3, {positionComponentType},
        positionComponentType != TINYGLTF_COMPONENT_TYPE_FLOAT);
    // The accessor index is proven in range by accessorBytes (found by fuzz_gltf: read before).
    const bool positionNormalized =
        model_.accessors[static_cast<std::size_t>(position->second)].normalized;
    if (positions.count > 0xFFFFFFFFull) {
      fail(path_, element, "more vertices than 32-bit indices can address");
    }
    object.worldPositions.reserve(positions.count);
    for (std::size_t v = 0; v < positions.count; ++v) {
      const glm::dvec3 value = positionAt(positions.data + v * positions.stride,
                                          positionComponentType, positionNormalized);
      if (!std::isfinite(value.x) || !std::isfinite(value.y) || !std::isfinite(value.z)) {
        fail(path_,
             indexText("accessors", static_cast<std::size_t>(position->second)) + " (POSITION of " +
                 element + ")",
             "vertex " + std::to_string(v) + " is not finite, got " + formatVector(value));
      }
      object.worldPositions.push_back(value);
    }
    const std::size_t vertexCount = positions.count;
    // The primitive's vertex sequence: 0, 1, 2, ... without indices, else the indices, checked.
    std::vector<std::uint32_t> sequence;
    const std::string indicesElement = element + ".indices";
    if (primitive.indices < 0) {
      sequence.resize(vertexCount);
      for (std::size_t v = 0; v < vertexCount; ++v) sequence[v] = static_cast<std::uint32_t>(v);
    } else {
      const AccessorBytes indices = accessorBytes(
          primitive.indices, "indices of " + element, TINYGLTF_TYPE_SCALAR,
          {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
           TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
      const int componentType =
          model_.accessors[static_cast<std::size_t>(primitive.indices)].componentType;
      sequence.resize(indices.count);
      for (std::size_t i = 0; i < indices.count; ++i) {
        const unsigned char* at = indices.data + i * indices.stride;
        std::uint32_t value = 0;
        if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
          value = *at;
        } else if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
          std::uint16_t shortValue;
          std::memcpy(&shortValue, at, sizeof shortValue);
          value = shortValue;
        } else {
          std::memcpy(&value, at, sizeof value);
        }
        if (value >= vertexCount) {
          fail(path_, indicesElement,
               "index " + std::to_string(i) + " is " + std::to_string(value) +
                   ", out of range for " + std::to_string(vertexCount) + " vertices");
        }
        sequence[i] = value;
      }
    }
    const std::size_t n = sequence.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0) {
        if (primitive.indices < 0) {
          fail(
              path_, element,
              "without indices the vertex count must be a multiple of 3, got " + std::to_string(n));
        }
        fail(path_, indicesElement,
             "the index count must be a multiple of 3, got " + std::to_string(n));
      }
      object.triangles.reserve(n / 3);
      for (std::size_t i = 0; i + 2 < n; i += 3) {
        object.triangles.emplace_back(sequence[i], sequence[i + 1], sequence[i + 2]);
      }
      return object;
    }
    if (n < 3) {
      fail(path_, primitive.indices < 0 ? element : indicesElement,
           std::string(modeName(mode)) + " needs at least 3 vertices, got " + std::to_string(n));
    }
    // glTF 2.0, 3.7.2.1: strip triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}) (every other one
    // reversed, so all keep the first one's winding); fan triangle i is (v_{i+1}, v_{i+2}, v_0).
    object.triangles.reserve(n - 2);
    for (std::size_t i = 0; i + 2 < n; ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        object.triangles.emplace_back(sequence[i], sequence[i + 1 + i % 2],
                                      sequence[i + 2 - i % 2]);
      } else {
        object.triangles.emplace_back(sequence[i + 1], sequence[i + 2], sequence[0]);
      }
    }
    return object;
  }

  void addMeshInstance(std::size_t nodeIndex, const glm::dmat4& world) {
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size()) {
      fail(path_, indexText("nodes", nodeIndex) + ".mesh",
           "mesh index " + std::to_string(node.mesh) + " out of range for " +
               std::to_string(model_.meshes.size()) + " meshes");
    }
    const auto meshIndex = static_cast<std::size_t>(node.mesh);
    const std::vector<MeshObject>& primitives = meshPrimitives(meshIndex);
    const std::string& meshName = model_.meshes[meshIndex].name;
    for (std::size_t p = 0; p < primitives.size(); ++p) {
      MeshObject object = primitives[p];
      const std::string base = (meshName.empty() ? "mesh" + std::to_string(meshIndex) : meshName) +
                               "/" + std::to_string(p);
      object.name = objectNames_.claim(base);
      const std::string element =
          (meshName.empty() ? indexText("meshes", meshIndex) : "mesh " + quotedText(meshName)) +
          " primitive " + std::to_string(p);
      addObject(contents_, path_, element, std::move(object), world);
    }
  }

  // ---- Cameras ---------------------------------------------------------------------------------

  void addCamera(std::size_t nodeIndex, const glm::dmat4& world) {
    const tinygltf::Node& node = model_.nodes[nodeIndex];
    if (static_cast<std::size_t>(node.camera) >= model_.cameras.size()) {
      fail(path_, indexText("nodes", nodeIndex) + ".camera",
           "camera index " + std::to_string(node.camera) + " out of range for " +
               std::to_string(model_.cameras.size()) + " cameras");
    }
    const auto cameraIndex = static_cast<std::size_t>(node.camera);
    const tinygltf::Camera& source = model_.cameras[cameraIndex];
    const std::string element = indexText("cameras", cameraIndex);
    Camera camera;
    camera.viewport = {kDefaultViewportWidth, kDefaultViewportHeight};
    if (source.type == "perspective") {
      const tinygltf::PerspectiveCamera& perspective = source.perspective;
      if (!(perspective.yfov > 0.0 && perspective.yfov < std::numbers::pi)) {
        fail(path_, element + ".perspective.yfov",
             "expected an angle in (0, pi) radians, got " + formatNumber(perspective.yfov));
      }
      if (!(perspective.znear > 0.0) || !std::isfinite(perspective.znear)) {
        fail(path_, element + ".perspective.znear",
             "expected a positive number, got " + formatNumber(perspective.znear));
      }
      PerspectiveProjection projection;
      projection.fovYDegrees = perspective.yfov * 180.0 / std::numbers::pi;
      projection.nearDistance = perspective.znear;
      // tinygltf reads an absent zfar (an infinite far plane) as 0.
      if (perspective.zfar != 0.0) {
        if (!(perspective.zfar > perspective.znear) || !std::isfinite(perspective.zfar)) {
          fail(path_, element + ".perspective.zfar",
               "expected a number greater than znear (" + formatNumber(perspective.znear) +
                   "), got " + formatNumber(perspective.zfar));
        }
        projection.farDistance = perspective.zfar;
      }
      // tinygltf reads an absent aspectRatio as 0: the viewport's aspect is used then.
      if (perspective.aspectRatio != 0.0) {
        if (!(perspective.aspectRatio > 0.0) || !std::isfinite(perspective.aspectRatio)) {
          fail(path_, element + ".perspective.aspectRatio",
               "expected a positive number, got " + formatNumber(perspective.aspectRatio));
        }
        projection.aspect = perspective.aspectRatio;
        const double width =
            std::clamp(std::round(kDefaultViewportHeight * perspective.aspectRatio), 1.0,
                       kMaxViewportDimension);
        camera.viewport.width = static_cast<int>(width);
      }
      camera.projection = projection;
    } else if (source.type == "orthographic") {
      const tinygltf::OrthographicCamera& orthographic = source.orthographic;
      auto checkMagnification = [&](double value, const char* name) {
        if (value == 0.0 || !std::isfinite(value)) {
          fail(path_, element + ".orthographic." + name,
               "expected a finite non-zero number, got " + formatNumber(value));
        }
      };
      checkMagnification(orthographic.xmag, "xmag");
      checkMagnification(orthographic.ymag, "ymag");
      if (!(orthographic.znear >= 0.0) || !std::isfinite(orthographic.znear)) {
        fail(path_, element + ".orthographic.znear",
             "expected a non-negative number, got " + formatNumber(orthographic.znear));
      }
      if (!(orthographic.zfar > orthographic.znear) || !std::isfinite(orthographic.zfar)) {
        fail(path_, element + ".orthographic.zfar",
             "expected a number greater than znear (" + formatNumber(orthographic.znear) +
                 "), got " + formatNumber(orthographic.zfar));
      }
      OrthographicProjection projection;
      projection.left = -orthographic.xmag;
      projection.right = orthographic.xmag;
      projection.bottom = -orthographic.ymag;
      projection.top = orthographic.ymag;
      projection.nearDistance = orthographic.znear;
      projection.farDistance = orthographic.zfar;
      camera.projection = projection;
    } else {
      fail(path_, element + ".type",
           "expected \"perspective\" or \"orthographic\", got " + quotedText(source.type));
    }
    // glTF cameras look down -Z with +Y up, as OpenGL view space does.
    camera.viewFromWorld = glm::inverse(world);
    camera.name = cameraNames_.claim(
        node.name.empty() ? "camera" + std::to_string(contents_.cameras.size()) : node.name);
    contents_.cameras.push_back(std::move(camera));
  }

  const tinygltf::Model& model_;
  const std::string& path_;
  const glm::dmat4& worldFromFile_;
  bool quantizedPositions_ = false;  // KHR_mesh_quantization in extensionsUsed
  std::vector<std::optional<std::vector<MeshObject>>> meshCache_;
  UniqueNames objectNames_;
  UniqueNames cameraNames_;
  MeshFileContents contents_;
};

}  // namespace

MeshFileContents parseGltf(std::string_view bytes, const std::string& path, bool binary,
                           const glm::dmat4& worldFromFile) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) {
    fail(path, binary ? "glb" : "gltf",
         "files over 4 GiB are not supported, got " + std::to_string(bytes.size()) + " bytes");
  }
  checkGltfJson(binary ? checkGlbContainer(bytes, path) : bytes, path);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(ignoreImage, nullptr);
  loader.SetFsCallbacks(tinygltf::FsCallbacks{regularFileExists, pathUnchanged, readRegularFile,
                                              writeNothing, nullptr});
  const std::string baseDirectory = std::filesystem::path(path).parent_path().string();
  tinygltf::Model model;
  std::string error;
  std::string warning;
  const auto size = static_cast<unsigned int>(bytes.size());
  auto load = [&] {
    return binary ? loader.LoadBinaryFromMemory(
                        &model, &error, &warning,
                        reinterpret_cast<const unsigned char*>(bytes.data()), size, baseDirectory)
                  : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), size,
                                               baseDirectory);
  };
  bool loaded = false;
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  // The fuzzers want library exceptions to surface as findings, not as messages.
  loaded = load();
#else
  // A library exception is a tinygltf bug that the checks above did not foresee; the user still
  // gets a message naming the file instead of a crash.
  try {
    loaded = load();
  } catch (const std::exception& libraryError) {
    fail(path, binary ? "glb" : "gltf",
         std::string("tinygltf failed on this file: ") + libraryError.what());
  }
#endif
  if (!loaded) {
    fail(path, binary ? "glb" : "gltf", "tinygltf rejected the file: " + trimmed(error));
  }
  return GltfReader(model, path, worldFromFile).read();
}

}  // namespace clipray::meshfiles
