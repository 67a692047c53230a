// Matrices read from uniform buffers (harness/clipray/trace/UniformBuffers.*) on dump lines as
// `apitrace dump --blobs` writes them (the calls of tests/traceapps/ConventionApp.cpp's ubo
// cases), with the blob files written here.

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "clipray/trace/DumpLine.hpp"
#include "clipray/trace/UniformBuffers.hpp"
#include "support/RunCommand.hpp"

namespace clipray::trace {
namespace {

using testing::TempFolder;

// A std140 camera block: eye 0, exposure 12, viewFromWorld 16, frustumColumns 80 (a vec4[4]),
// clipFromWorld 144; 208 bytes.
const std::string kCameraShader =
    "#version 450 core\\nlayout(std140) uniform Camera {\\n  vec3 eye;\\n  float exposure;\\n  "
    "mat4 viewFromWorld;\\n  vec4 frustumColumns[4];\\n  mat4 clipFromWorld;\\n} camera;\\nvoid "
    "main() { gl_Position = camera.clipFromWorld * vec4(0.0); }\\n";

// Sixteen distinct values: element k of a matrix is base + k.
std::vector<float> sequence(float base) {
  std::vector<float> values(16);
  for (int k = 0; k < 16; ++k) values[k] = base + static_cast<float>(k);
  return values;
}

// The camera block's bytes: every mat4 and the vec4[4] filled with distinct sequences.
std::vector<float> cameraBlock() {
  std::vector<float> block(52, 0.0f);
  block[0] = 0.0f;
  block[1] = 2.0f;
  block[2] = 5.0f;
  block[3] = 1.0f;
  const auto put = [&](std::size_t at, float base) {
    const std::vector<float> values = sequence(base);
    std::copy(values.begin(), values.end(), block.begin() + static_cast<std::ptrdiff_t>(at));
  };
  put(4, 100.0f);   // viewFromWorld
  put(20, 200.0f);  // frustumColumns
  put(36, 300.0f);  // clipFromWorld
  return block;
}

void writeBlob(const TempFolder& folder, const std::string& name, const std::vector<float>& data,
               std::size_t bytes) {
  std::ofstream file(folder.path() / name, std::ios::binary);
  file.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(bytes));
}

void feed(UniformBuffers& buffers, const std::vector<std::string>& lines) {
  for (const std::string& line : lines) {
    const DumpCall call = parseDumpCall(line);
    ASSERT_TRUE(UniformBuffers::needs(call.name)) << call.name;
    buffers.apply(call);
  }
}

// The camera program (1) with its block at binding 3 through glUniformBlockBinding, a 464-byte
// buffer bound at offset 256 for 208 bytes.
std::vector<std::string> cameraProgram() {
  return {
      "27 glShaderSource(shader = 2, count = 1, string = &\"" + kCameraShader +
          "\", length = NULL)",
      "30 glAttachShader(program = 1, shader = 2)",
      "37 glLinkProgram(program = 1)",
      "40 glBindBuffer(target = GL_UNIFORM_BUFFER, buffer = 1)",
      "41 glBufferData(target = GL_UNIFORM_BUFFER, size = 464, data = NULL, usage = "
      "GL_DYNAMIC_DRAW)",
      "42 glGetUniformBlockIndex(program = 1, uniformBlockName = \"Camera\") = 0",
      "43 glUniformBlockBinding(program = 1, uniformBlockIndex = 0, uniformBlockBinding = 3)",
      "44 glBindBufferRange(target = GL_UNIFORM_BUFFER, index = 3, buffer = 1, offset = 256, "
      "size = 208)",
  };
}

std::vector<std::string> sources(const std::vector<UniformBlockMatrix>& matrices) {
  std::vector<std::string> names;
  for (const UniformBlockMatrix& m : matrices) names.push_back(m.source);
  return names;
}

TEST(TraceUniformBuffers, MappedWriteGivesTheBlocksMat4sNotItsVec4Array) {
  TempFolder folder;
  writeBlob(folder, "blob_call55.bin", cameraBlock(), 208);
  UniformBuffers buffers;
  buffers.setBlobDirectory(folder.path());
  feed(buffers, cameraProgram());
  feed(buffers,
       {"54 glMapBufferRange(target = GL_UNIFORM_BUFFER, offset = 256, length = 208, access = "
        "GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT) = 0x55efe46b80c0",
        "55 memcpy(dest = 0x55efe46b80c0, src = blob(\"blob_call55.bin\"), n = 208) // fake",
        "56 glUnmapBuffer(target = GL_UNIFORM_BUFFER) = GL_TRUE"});
  const std::vector<UniformBlockMatrix> matrices = buffers.matrices(1, 57);
  // frustumColumns holds 16 floats too, but a vec4[4] is no matrix.
  ASSERT_EQ(sources(matrices), (std::vector<std::string>{"ubo Camera.viewFromWorld (program 1)",
                                                         "ubo Camera.clipFromWorld (program 1)"}));
  EXPECT_EQ(matrices[1].matrix[0][0], 300.0);
  EXPECT_EQ(matrices[1].matrix[0][1], 301.0);  // column 0, row 1: the second float
  EXPECT_EQ(matrices[1].matrix[3][2], 314.0);
  EXPECT_EQ(matrices[0].matrix[2][3], 111.0);
  EXPECT_EQ(buffers.unreadNotes(), std::vector<std::string>{});
  EXPECT_EQ(buffers.matrices(2, 57).size(), 0u);  // another program: no blocks
}

TEST(TraceUniformBuffers, BlockNamedByGlGetActiveUniformBlockName) {
  // OpenSceneGraph's osg::Program enumerates its blocks (glGetActiveUniformBlockName for index 0
  // to GL_ACTIVE_UNIFORM_BLOCKS - 1) instead of asking glGetUniformBlockIndex for a name
  // (osguniformbuffer): the index is the argument, the name the result.
  TempFolder folder;
  writeBlob(folder, "blob_call46.bin", cameraBlock(), 208);
  UniformBuffers buffers;
  buffers.setBlobDirectory(folder.path());
  std::vector<std::string> calls = cameraProgram();
  calls[5] =
      "42 glGetActiveUniformBlockName(program = 1, uniformBlockIndex = 0, bufSize = 7, length = "
      "&6, uniformBlockName = \"Camera\")";
  feed(buffers, calls);
  feed(buffers, {"46 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 256, size = 208, data = "
                 "blob(\"blob_call46.bin\"))"});
  const std::vector<UniformBlockMatrix> matrices = buffers.matrices(1, 50);
  ASSERT_EQ(sources(matrices), (std::vector<std::string>{"ubo Camera.viewFromWorld (program 1)",
                                                         "ubo Camera.clipFromWorld (program 1)"}));
  EXPECT_EQ(matrices[1].matrix[0][0], 300.0);
  EXPECT_EQ(buffers.unreadNotes(), std::vector<std::string>{});
}

TEST(TraceUniformBuffers, RowMajorMatrixAtBindingFromTheShader) {
  TempFolder folder;
  const std::vector<float> values = sequence(1.0f);
  writeBlob(folder, "blob_call9.bin", values, 64);
  UniformBuffers buffers;
  buffers.setBlobDirectory(folder.path());
  feed(buffers,
       {"3 glShaderSource(shader = 4, count = 2, string = {\"layout(std140, binding = 5) uniform "
        "\", \"Scene { layout(row_major) mat4 projection; };\"}, length = NULL)",
        "4 glAttachShader(program = 7, shader = 4)", "5 glLinkProgram(program = 7)",
        "7 glNamedBufferStorage(buffer = 2, size = 64, data = NULL, flags = "
        "GL_DYNAMIC_STORAGE_BIT)",
        "8 glBindBufferBase(target = GL_UNIFORM_BUFFER, index = 5, buffer = 2)",
        "9 glNamedBufferSubData(buffer = 2, offset = 0, size = 64, data = "
        "blob(\"blob_call9.bin\"))"});
  const auto matrices = buffers.matrices(7, 10);
  ASSERT_EQ(sources(matrices), std::vector<std::string>{"ubo Scene.projection (program 7)"});
  // Row-major: the second float is row 0, column 1.
  EXPECT_EQ(matrices[0].matrix[1][0], 2.0);
  EXPECT_EQ(matrices[0].matrix[0][1], 5.0);
}

// GL 4.4 multi-bind: glBindBuffersRange sets bindings first .. first + count - 1 at once, and
// glBindBuffersBase with buffers = NULL unbinds them.
TEST(TraceUniformBuffers, MultiBind) {
  TempFolder folder;
  writeBlob(folder, "blob_call50.bin", cameraBlock(), 208);
  UniformBuffers buffers;
  buffers.setBlobDirectory(folder.path());
  feed(buffers, cameraProgram());
  feed(buffers,
       {"50 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 0, size = 208, data = "
        "blob(\"blob_call50.bin\"))",
        "51 glBindBuffersRange(target = GL_UNIFORM_BUFFER, first = 2, count = 2, buffers = {1, "
        "1}, offsets = {256, 0}, sizes = {208, 208})"});
  const auto matrices = buffers.matrices(1, 52);  // binding 3: buffer 1 at offset 0
  ASSERT_EQ(sources(matrices), (std::vector<std::string>{"ubo Camera.viewFromWorld (program 1)",
                                                         "ubo Camera.clipFromWorld (program 1)"}));
  EXPECT_EQ(matrices[1].matrix[0][0], 300.0);
  feed(buffers, {"53 glBindBuffersBase(target = GL_UNIFORM_BUFFER, first = 0, count = 4, buffers "
                 "= NULL)"});
  EXPECT_EQ(buffers.matrices(1, 54).size(), 0u);
  EXPECT_EQ(buffers.unreadNotes(),
            std::vector<std::string>{"ubo Camera (program 1): no buffer bound to uniform buffer "
                                     "binding 3 (first at the draw at call 54)"});
  EXPECT_THROW(feed(buffers, {"55 glBindBuffersBase(target = GL_UNIFORM_BUFFER, first = 0, count "
                              "= 2, buffers = {1})"}),
               std::invalid_argument);
}

TEST(TraceUniformBuffers, WhatCannotBeReadIsNoted) {
  TempFolder folder;
  writeBlob(folder, "blob_call50.bin", cameraBlock(), 100);  // shorter than the call says
  UniformBuffers buffers;
  buffers.setBlobDirectory(folder.path());
  feed(buffers, cameraProgram());
  feed(buffers, {"50 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 256, size = 208, data = "
                 "blob(\"blob_call50.bin\"))"});
  EXPECT_EQ(buffers.matrices(1, 51).size(), 0u);
  feed(buffers, {"52 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 256, size = 208, data = "
                 "blob(\"blob_call52.bin\"))"});  // no such file
  EXPECT_EQ(buffers.matrices(1, 53).size(), 0u);
  // A range that ends inside the block: the second matrix is past its end.
  writeBlob(folder, "blob_call54.bin", cameraBlock(), 208);
  feed(buffers,
       {"54 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 256, size = 208, data = "
        "blob(\"blob_call54.bin\"))",
        "55 glBindBufferRange(target = GL_UNIFORM_BUFFER, index = 3, buffer = 1, offset = 256, "
        "size = 160)"});
  EXPECT_EQ(sources(buffers.matrices(1, 56)),
            std::vector<std::string>{"ubo Camera.viewFromWorld (program 1)"});
  // A range past the buffer's end (464 bytes), with an offset that would wrap a sum.
  feed(buffers, {"56 glBindBufferRange(target = GL_UNIFORM_BUFFER, index = 3, buffer = 1, offset = "
                 "18446744073709551600, size = 208)"});
  EXPECT_EQ(buffers.matrices(1, 56).size(), 0u);
  // Deleting the buffer unbinds it, as glBindBufferBase(..., 0) does.
  feed(buffers, {"57 glDeleteBuffers(n = 2, buffers = {-1, 1})"});
  EXPECT_EQ(buffers.matrices(1, 58).size(), 0u);
  EXPECT_EQ(buffers.unreadNotes(),
            (std::vector<std::string>{
                "ubo Camera.viewFromWorld (program 1): buffer 1 holds bytes the trace does not "
                "show here (last: glBufferSubData at call 50: blob file blob_call50.bin holds 100 "
                "bytes, not the 208 written) (first at the draw at call 51)",
                "ubo Camera.clipFromWorld (program 1): buffer 1 holds bytes the trace does not "
                "show here (last: glBufferSubData at call 50: blob file blob_call50.bin holds 100 "
                "bytes, not the 208 written) (first at the draw at call 51)",
                "ubo Camera.clipFromWorld (program 1): the bound range of buffer 1 ends at byte "
                "160 of the block, before the matrix (bytes 144 to 208) (first at the draw at "
                "call 56)",
                "ubo Camera (program 1): the range bound at binding 3 starts at byte "
                "18446744073709551600, past the end of buffer 1 (464 bytes) (first at the draw at "
                "call 56)",
                "ubo Camera (program 1): no buffer bound to uniform buffer binding 3 (first at "
                "the draw at call 58)"}));
}

// Vertex data is not held: a buffer filled through GL_ARRAY_BUFFER and only then bound as a
// uniform buffer has bytes clipray does not know, and says so.
TEST(TraceUniformBuffers, BytesWrittenBeforeTheBufferWasAUniformBuffer) {
  TempFolder folder;
  writeBlob(folder, "blob_call46.bin", cameraBlock(), 208);
  UniformBuffers buffers;
  buffers.setBlobDirectory(folder.path());
  feed(buffers, cameraProgram());
  feed(buffers, {"45 glBindBuffer(target = GL_ARRAY_BUFFER, buffer = 9)",
                 "46 glBufferData(target = GL_ARRAY_BUFFER, size = 208, data = "
                 "blob(\"blob_call46.bin\"), usage = GL_STATIC_DRAW)",
                 "47 glBindBufferBase(target = GL_UNIFORM_BUFFER, index = 3, buffer = 9)"});
  EXPECT_EQ(buffers.matrices(1, 48).size(), 0u);
  ASSERT_EQ(buffers.unreadNotes().size(), 2u);
  EXPECT_EQ(buffers.unreadNotes()[0],
            "ubo Camera.viewFromWorld (program 1): buffer 9 holds bytes the trace does not show "
            "here (last: its data was written before glBindBufferBase at call 47 made it a "
            "uniform buffer) (first at the draw at call 48)");
  // Written again while a uniform buffer: read.
  feed(buffers, {"49 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 0, size = 208, data = "
                 "blob(\"blob_call46.bin\"))"});
  EXPECT_EQ(sources(buffers.matrices(1, 50)),
            (std::vector<std::string>{"ubo Camera.viewFromWorld (program 1)",
                                      "ubo Camera.clipFromWorld (program 1)"}));
}

TEST(TraceUniformBuffers, SharedLayoutAndUnknownOffsetsAreNotGuessed) {
  UniformBuffers buffers;
  feed(buffers,
       {"3 glShaderSource(shader = 4, count = 1, string = &\"uniform Shared { mat4 m; };\\n"
        "layout(std140) uniform Later { vec4 planes[COUNT]; mat4 projection; };\", length = "
        "NULL)",
        "4 glAttachShader(program = 1, shader = 4)", "5 glLinkProgram(program = 1)",
        "6 glUniformBlockBinding(program = 1, uniformBlockIndex = 1, uniformBlockBinding = 2)"});
  // apitrace 11.1 writes the offsets an app queries as the address they went to: no offsets.
  const DumpCall query = parseDumpCall(
      "8 glGetActiveUniformsiv(program = 1, uniformCount = 1, uniformIndices = &0, pname = "
      "GL_UNIFORM_OFFSET, params = 0x7fffba05a6c0)");
  EXPECT_EQ(query.argument("params")->text, "0x7fffba05a6c0");
  EXPECT_FALSE(UniformBuffers::needs(query.name));
  EXPECT_EQ(buffers.matrices(1, 9).size(), 0u);
  EXPECT_EQ(buffers.unreadNotes(),
            (std::vector<std::string>{
                "glUniformBlockBinding at call 6: block index 1 of program 1 was not named by "
                "glGetUniformBlockIndex or glGetActiveUniformBlockName in the trace: that "
                "block's binding is unknown",
                "ubo Shared (program 1): shared layout: its offsets are the implementation's "
                "(apitrace records an app's GL_UNIFORM_OFFSET query without its result), so its "
                "matrices are not read (first at the draw at call 9)",
                "ubo Later.projection (program 1): not read: the array size of planes is not a "
                "literal number (first at the draw at call 9)"}));
}

TEST(TraceUniformBuffers, WithoutBlobFilesTheBytesAreUnknown) {
  UniformBuffers buffers;
  feed(buffers, cameraProgram());
  feed(buffers, {"50 glBufferSubData(target = GL_UNIFORM_BUFFER, offset = 256, size = 208, data = "
                 "blob(208))"});
  EXPECT_EQ(buffers.matrices(1, 51).size(), 0u);
  ASSERT_EQ(buffers.unreadNotes().size(), 2u);
  EXPECT_EQ(buffers.unreadNotes()[0],
            "ubo Camera.viewFromWorld (program 1): buffer 1 holds bytes the trace does not show "
            "here (last: glBufferSubData at call 50: the bytes are not in the dump text (they are "
            "only in the blob files of `apitrace dump --blobs`)) (first at the draw at call 51)");
}

TEST(TraceUniformBuffers, BlobFileNamesStayInTheDumpFolder) {
  DumpValue value;
  value.text = "blob(\"blob_call45.bin\")";
  EXPECT_EQ(blobFileName(value), "blob_call45.bin");
  value.text = "blob(\"../../etc/passwd\")";
  EXPECT_EQ(blobFileName(value), std::nullopt);
  value.text = "blob(\"blob_call.bin\")";
  EXPECT_EQ(blobFileName(value), std::nullopt);
  value.text = "blob(36)";
  EXPECT_EQ(blobFileName(value), std::nullopt);
  EXPECT_EQ(blobFileNames("55 memcpy(dest = 0x1, src = blob(\"blob_call55.bin\"), n = 8) // fake "
                          "blob(\"/tmp/x\")"),
            std::vector<std::string>{"blob_call55.bin"});
}

}  // namespace
}  // namespace clipray::trace
