#pragma once
// The uniform blocks a GLSL source declares (`layout(std140, binding = 2) uniform Camera { ... }`)
// and, for std140 blocks, the byte offset of each member as the std140 rules place it (OpenGL 4.6
// core specification, section 7.6.2.2 "Standard Uniform Block Layout"). `clipray check --trace`
// reads the glShaderSource text from the dump, so it can find the mat4 members of a block and
// read them from the bound buffer's bytes.
//
// Blocks in the shared or packed layout (the default when no layout is given) have offsets only
// the implementation knows: their members are listed without offsets, to be filled from the
// app's own glGetActiveUniformsiv(GL_UNIFORM_OFFSET) queries where the trace has them.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clipray::trace {

enum class BlockLayout { kStd140, kStd430, kShared, kPacked };

struct BlockMember {
  std::string name;             // as declared: "clipFromWorld"
  std::string type;             // "mat4", "vec3", "float" ("mat4x4" is written "mat4")
  std::uint32_t arraySize = 0;  // 0: not an array
  bool rowMajor = false;
  // std140 only (nullopt in other layouts, and from the first member whose layout is unknown).
  std::optional<std::uint32_t> offset;
  std::uint32_t arrayStride = 0;   // bytes between array elements (std140)
  std::uint32_t matrixStride = 0;  // bytes between a matrix's columns (rows when row-major)
};

struct UniformBlockDeclaration {
  std::string blockName;                 // "Camera"
  std::string instanceName;              // "camera" in `uniform Camera { ... } camera;`, else ""
  std::optional<std::uint32_t> binding;  // layout(binding = N)
  BlockLayout layout = BlockLayout::kShared;
  std::vector<BlockMember> members;
  // Why std140 offsets stop before the end of the block (a struct member, an array sized by a
  // macro): "" when every member has its offset.
  std::string offsetsStop;
};

// The uniform blocks of one GLSL source (comments and preprocessor lines skipped; macros are not
// expanded). Storage blocks (`buffer`) and plain uniforms are not blocks here. Never throws: a
// block whose text cannot be read is left out.
std::vector<UniformBlockDeclaration> parseUniformBlocks(std::string_view source);

// "std140", "std430", "shared", "packed".
std::string_view blockLayoutName(BlockLayout layout);

// Whether the GLSL source names gl_ClipDistance outside comments and preprocessor lines (a vertex
// or geometry shader that writes it clips with the planes GL_CLIP_DISTANCEi enables).
bool mentionsClipDistance(std::string_view source);

// The first built-in of the compatibility profile's fixed-function transform the GLSL source
// reads outside comments and preprocessor lines: "ftransform()", "gl_ModelViewProjectionMatrix",
// "gl_ProjectionMatrix" (or their Transpose forms); "" for none. A vertex shader that reads one
// transforms through GL_PROJECTION (and GL_MODELVIEW), not through a uniform of its own.
std::string fixedFunctionTransformRead(std::string_view source);

}  // namespace clipray::trace
