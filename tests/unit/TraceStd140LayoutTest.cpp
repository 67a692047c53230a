// The uniform-block reader and std140 offsets (harness/clipray/trace/Std140Layout.*). The
// expected offsets are those of the OpenGL 4.6 core specification, 7.6.2.2, worked by hand (and
// the ones Mesa's llvmpipe reports through GL_UNIFORM_OFFSET for the same blocks).

#include <gtest/gtest.h>

#include "clipray/trace/Std140Layout.hpp"

namespace clipray::trace {
namespace {

struct Placed {
  std::string name;
  std::optional<std::uint32_t> offset;
  std::uint32_t arrayStride = 0;
  std::uint32_t matrixStride = 0;
  bool rowMajor = false;
  bool operator==(const Placed&) const = default;
};

std::ostream& operator<<(std::ostream& out, const Placed& placed) {
  return out << placed.name << "@" << (placed.offset ? std::to_string(*placed.offset) : "none")
             << " array " << placed.arrayStride << " matrix " << placed.matrixStride
             << (placed.rowMajor ? " row-major" : "");
}

std::vector<Placed> placed(const UniformBlockDeclaration& block) {
  std::vector<Placed> result;
  for (const BlockMember& m : block.members) {
    result.push_back({m.name, m.offset, m.arrayStride, m.matrixStride, m.rowMajor});
  }
  return result;
}

TEST(TraceStd140Layout, Vec3FollowedByFloatSharesItsSlot) {
  const auto blocks = parseUniformBlocks(
      "#version 450 core\n"
      "layout(std140, binding = 2) uniform Camera {\n"
      "  vec3 eye;\n"
      "  float exposure;\n"
      "  vec2 jitter;\n"
      "  float time;\n"
      "  vec3 sun;\n"
      "  mat4 clipFromWorld;\n"
      "} camera;\n");
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].blockName, "Camera");
  EXPECT_EQ(blocks[0].instanceName, "camera");
  EXPECT_EQ(blocks[0].binding, 2u);
  EXPECT_EQ(blocks[0].layout, BlockLayout::kStd140);
  EXPECT_EQ(blocks[0].offsetsStop, "");
  // vec2 aligns to 8 (16), float packs after it (24), vec3 aligns to 16 (32), mat4 to 16 (48).
  EXPECT_EQ(placed(blocks[0]), (std::vector<Placed>{{"eye", 0},
                                                    {"exposure", 12},
                                                    {"jitter", 16},
                                                    {"time", 24},
                                                    {"sun", 32},
                                                    {"clipFromWorld", 48, 0, 16}}));
}

TEST(TraceStd140Layout, Mat3ArraysAndRowMajor) {
  const auto blocks = parseUniformBlocks(
      "layout(std140) uniform Lights {\n"
      "  float intensity;\n"
      "  mat3 normalFromModel;    // three vec3 columns, each rounded up to a vec4\n"
      "  float weights[3];        /* array elements round up to 16 bytes */\n"
      "  vec4 frustumColumns[4];\n"
      "  layout(row_major) mat4x3 rowMajorTransform;\n"
      "  mat4 cascades[2], last;\n"
      "  vec2 tail;\n"
      "};\n");
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].instanceName, "");
  EXPECT_EQ(blocks[0].binding, std::nullopt);
  EXPECT_EQ(placed(blocks[0]), (std::vector<Placed>{{"intensity", 0},
                                                    {"normalFromModel", 16, 0, 16},
                                                    {"weights", 64, 16},
                                                    {"frustumColumns", 112, 16},
                                                    // 3 rows of vec4: 48 bytes
                                                    {"rowMajorTransform", 176, 0, 16, true},
                                                    {"cascades", 224, 64, 16},
                                                    {"last", 352, 0, 16},
                                                    {"tail", 416}}));
  EXPECT_EQ(blocks[0].members[3].type, "vec4");
  EXPECT_EQ(blocks[0].members[3].arraySize, 4u);
  EXPECT_EQ(blocks[0].members[5].type, "mat4");
  EXPECT_EQ(blocks[0].members[5].arraySize, 2u);
}

TEST(TraceStd140Layout, BlockAndDefaultMatrixOrder) {
  const auto blocks = parseUniformBlocks(
      "layout(std140, row_major) uniform;\n"
      "uniform A { mat4 m; layout(column_major) mat4 n; };\n"
      "layout(column_major) uniform B { mat4 m; };\n");
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[0].layout, BlockLayout::kStd140);  // from the default
  EXPECT_EQ(placed(blocks[0]),
            (std::vector<Placed>{{"m", 0, 0, 16, true}, {"n", 64, 0, 16, false}}));
  EXPECT_EQ(placed(blocks[1]), (std::vector<Placed>{{"m", 0, 0, 16, false}}));
}

TEST(TraceStd140Layout, SharedAndStd430BlocksHaveNoOffsets) {
  const auto blocks = parseUniformBlocks(
      "uniform Shared { mat4 clipFromWorld; };\n"
      "layout(packed) uniform Packed { mat4 m; };\n"
      "layout(std430, binding = 1) buffer Storage { mat4 m; };\n");
  ASSERT_EQ(blocks.size(), 2u);  // a storage block is no uniform block
  EXPECT_EQ(blocks[0].layout, BlockLayout::kShared);
  EXPECT_EQ(blockLayoutName(blocks[0].layout), "shared");
  EXPECT_EQ(placed(blocks[0]), (std::vector<Placed>{{"clipFromWorld", std::nullopt}}));
  EXPECT_EQ(blocks[1].layout, BlockLayout::kPacked);
}

TEST(TraceStd140Layout, OffsetsStopAtWhatIsNotFollowed) {
  const auto blocks = parseUniformBlocks(
      "struct Light { vec4 position; };\n"
      "layout(std140) uniform WithStruct { mat4 before; Light light; mat4 after; };\n"
      "layout(std140) uniform WithMacro { mat4 first; vec4 planes[MAX_PLANES]; mat4 after; };\n"
      "layout(std140) uniform WithOffset { mat4 a; layout(offset = 128) mat4 b; };\n"
      "void main() { gl_Position = vec4(0.0); }\n");
  ASSERT_EQ(blocks.size(), 3u);
  EXPECT_EQ(blocks[0].members[0].offset, 0u);
  EXPECT_EQ(blocks[0].members[1].offset, std::nullopt);
  EXPECT_EQ(blocks[0].members[2].offset, std::nullopt);
  EXPECT_EQ(blocks[0].offsetsStop, "light is a Light (not followed)");
  EXPECT_EQ(blocks[1].members[0].offset, 0u);
  EXPECT_EQ(blocks[1].members[2].offset, std::nullopt);
  EXPECT_EQ(blocks[1].offsetsStop, "the array size of planes is not a literal number");
  EXPECT_EQ(blocks[2].members[0].offset, 0u);
  EXPECT_EQ(blocks[2].offsetsStop, "b has an explicit offset or align qualifier");
}

TEST(TraceStd140Layout, CommentsAndDirectivesHideNoBlock) {
  const auto blocks = parseUniformBlocks(
      "// layout(std140) uniform Commented { mat4 m; };\n"
      "/* uniform AlsoCommented { mat4 m; }; */\n"
      "#define BLOCK uniform Hidden { mat4 m; }; \\\n"
      "  uniform StillDirective { mat4 m; };\n"
      "uniform mat4 plainUniform;\n"
      "layout(std140) uniform Real { mat4 m; };\n"
      "uniform Lights { vec4 colour; } lights[4];\n"
      "uniform Broken { mat4 ;\n");
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].blockName, "Real");
}

}  // namespace
}  // namespace clipray::trace
