// Mesh files in OBJ and PLY, and what every format shares (a missing file, an unknown
// extension, a file without triangles): what the shipped test files turn into, exactly, and the
// message for every kind of bad input. glTF and GLB: MeshFileGltfTest.cpp.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/scene/MeshFiles.hpp"
#include "support/MeshFileChecks.hpp"

namespace clipray {
namespace {

using ::testing::ElementsAre;
using testing::errorOf;
using ::testing::HasSubstr;
using testing::kMeshDataDir;
using testing::positionsOf;
using ::testing::StartsWith;

// ---- Good files ------------------------------------------------------------------------------

TEST(MeshFileObj, QuadsAreFannedAndRelativeIndicesResolved) {
  const MeshFileContents contents = loadMeshFile(kMeshDataDir + "quads.obj");
  ASSERT_EQ(contents.objects.size(), 2u);
  EXPECT_EQ(contents.objects[0].name, "first");
  EXPECT_THAT(positionsOf(contents.objects[0]),
              ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(1, 1, 0),
                          glm::dvec3(0, 1, 0)));
  EXPECT_THAT(contents.objects[0].triangles,
              ElementsAre(glm::u32vec3(0, 1, 2), glm::u32vec3(0, 2, 3)));
  EXPECT_EQ(contents.objects[1].name, "second");
  EXPECT_THAT(positionsOf(contents.objects[1]),
              ElementsAre(glm::dvec3(0, 0, 1), glm::dvec3(2, 0, 1), glm::dvec3(2, 2, 1),
                          glm::dvec3(0, 2, 1)));
  EXPECT_THAT(contents.objects[1].triangles,
              ElementsAre(glm::u32vec3(0, 1, 2), glm::u32vec3(0, 2, 3)));
  EXPECT_TRUE(contents.cameras.empty());
}

// "o é\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" as UTF-16 with a byte order mark.
std::string utf16Triangle(bool bigEndian) {
  const std::u16string text = u"o \u00e9\U0001F600\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::string bytes = bigEndian ? "\xFE\xFF" : "\xFF\xFE";
  for (char16_t unit : text) {
    const char high = static_cast<char>(unit >> 8), low = static_cast<char>(unit & 0xFF);
    bytes += bigEndian ? std::string{high, low} : std::string{low, high};
  }
  return bytes;
}

TEST(MeshFileObj, Utf16AndUtf8ByteOrderMarksAreReadAsAssimpReadsThem) {
  for (const std::string& bytes :
       {utf16Triangle(true), utf16Triangle(false),
        std::string(
            "\xEF\xBB\xBFo \xC3\xA9\xF0\x9F\x98\x80\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")}) {
    const MeshFileContents contents = parseMeshFile(bytes, "m.obj");
    ASSERT_EQ(contents.objects.size(), 1u);
    EXPECT_EQ(contents.objects[0].name, "\xC3\xA9\xF0\x9F\x98\x80");  // é and U+1F600, in UTF-8
    EXPECT_THAT(positionsOf(contents.objects[0]),
                ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)));
  }
  EXPECT_EQ(errorOf(utf16Triangle(true).substr(1), "m.obj"),
            "m.obj: byte 1: a NUL byte in a text file");  // no mark: read as ASCII
  EXPECT_EQ(errorOf(utf16Triangle(true) + '\0', "m.obj"),
            "m.obj: UTF-16BE: a UTF-16 file needs an even number of bytes, got 79");
  EXPECT_EQ(errorOf(std::string("\xFF\xFEo\x00 \x00\x00\xDC", 8), "m.obj"),
            "m.obj: UTF-16LE byte 6: an unpaired surrogate");
}

TEST(MeshFilePly, AsciiAndBothBinaryByteOrdersReadTheSameMesh) {
  for (const char* name : {"ascii", "binary_little", "binary_big"}) {
    SCOPED_TRACE(name);
    const glm::dmat4 worldFromFile = glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
    const MeshFileContents contents = loadMeshFile(kMeshDataDir + name + ".ply", worldFromFile);
    ASSERT_EQ(contents.objects.size(), 1u);
    EXPECT_EQ(contents.objects[0].name, name);
    EXPECT_THAT(positionsOf(contents.objects[0]),
                ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(2, 0, 0), glm::dvec3(2, 2, 0),
                            glm::dvec3(0, 2, 0), glm::dvec3(1, 1, 2)));
    EXPECT_THAT(contents.objects[0].triangles,
                ElementsAre(glm::u32vec3(0, 1, 2), glm::u32vec3(0, 2, 3), glm::u32vec3(0, 1, 4)));
    EXPECT_TRUE(contents.warnings.empty());
  }
}

// ---- Bad files: the files themselves ---------------------------------------------------------

TEST(MeshFileErrors, MissingFileAndUnknownExtension) {
  EXPECT_EQ(errorOf("", "model.stl"),
            "model.stl: unsupported mesh file extension \".stl\"; clipray reads .gltf, .glb, .obj "
            "and .ply");
  const std::string missing = kMeshDataDir + "no-such-file.ply";
  try {
    loadMeshFile(missing);
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), missing + ": cannot open file");
  }
}

TEST(MeshFileErrors, NonInvertibleWorldFromFile) {
  EXPECT_EQ(errorOf("", "a.ply"), "a.ply: line 1: expected the magic line \"ply\", got \"\"");
  try {
    parseMeshFile("", "a.ply", glm::dmat4(0.0));
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), StartsWith("a.ply: worldFromFile: row 3 must be 0, 0, 0, 1"));
  }
}

TEST(MeshFileObj, MissingMaterialLibrariesAreWarnedAboutOnce) {
  const MeshFileContents contents = parseMeshFile(
      "mtllib no such.mtl \nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3/1/1\nmtllib " +
          kMeshDataDir + "quads.obj\n",
      kMeshDataDir + "m.obj");
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_EQ(contents.warnings,
            std::vector<std::string>{kMeshDataDir +
                                     "m.obj: line 1: material library \"no such.mtl\" not found; "
                                     "materials do not change depth, ignored"});
}

TEST(MeshFileObj, FacesNamingMissingTexCoordsOrNormalsAreReadWithOneWarning) {
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  EXPECT_TRUE(parseMeshFile(triangle + "f 1/1/1 2/1/1 3//-1\n", "m.obj").warnings.empty());
  // Defined after the face that names it: no warning either.
  EXPECT_TRUE(parseMeshFile(triangle + "f 1/2 2/2 3/2\nvt 1 1\n", "m.obj").warnings.empty());
  const std::string kWarning =
      " (and maybe others): a face names texture coordinates or normals the file does not define; "
      "clipray reads positions only, ignored";
  const MeshFileContents beyond =
      parseMeshFile(triangle + "f 1 2 3\nf 1/1/1 2/1/1 3/1/1\nf 1/1/7 2/1/1 3/1/1\n", "m.obj");
  ASSERT_EQ(beyond.objects.size(), 1u);
  EXPECT_EQ(beyond.objects[0].triangles.size(), 3u);
  EXPECT_EQ(beyond.warnings, std::vector<std::string>{"m.obj: line 8" + kWarning});
  EXPECT_EQ(parseMeshFile(triangle + "f 1/-2 2/1 3/1\nf 1/x 2 3\n", "m.obj").warnings,
            std::vector<std::string>{"m.obj: line 6" + kWarning});
}

TEST(MeshFileErrors, ObjWithoutFacesSaysWhatItHolds) {
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\np 1 2\nl 1 2\np 2\n", "m.obj"),
            "m.obj: obj: no faces (\"f\" lines), only 2 vertices, 2 point (\"p\") and 1 line "
            "(\"l\") elements: clipray compares surfaces, and points and lines have none");
  EXPECT_EQ(errorOf("", "m.obj"),
            "m.obj: obj: no faces (\"f\" lines), only 0 vertices, 0 point (\"p\") and 0 line "
            "(\"l\") elements: clipray compares surfaces, and points and lines have none");
}

// ---- Bad files: OBJ --------------------------------------------------------------------------

TEST(MeshFileErrors, ObjIndexOutOfRange) {
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "m.obj"),
            "m.obj: line 4: vertex index 4 out of range for 3 vertices");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", "m.obj"),
            "m.obj: line 3: face 0: relative vertex index -3 out of range for 2 vertices defined "
            "so far");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "m.obj"),
            "m.obj: line 4: face 0: vertex index 0 is invalid (OBJ indices start at 1)");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nf 1 2\n", "m.obj"),
            "m.obj: line 3: face 0: a face needs at least 3 vertices, got 2");
}

TEST(MeshFileErrors, ObjNonFinitePosition) {
  EXPECT_EQ(errorOf("v 0 0 0\n\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "m.obj"),
            "m.obj: line 3: vertex 2: y is not finite, got \"nan\"");
  EXPECT_EQ(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n", "m.obj"),
            "m.obj: line 3: vertex 3: z is not finite, got \"-inf\"");
  EXPECT_EQ(errorOf("v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "m.obj"),
            "m.obj: line 1: vertex 1: z does not fit a double, got \"1e999\"");
}

TEST(MeshFileErrors, ObjLoneCarriageReturnEndsALineAsInTinyobjloader) {
  EXPECT_EQ(errorOf("v 0 0 0\rv nan 0 0\r\nv 0 1 0\rf 1 2 3\r", "m.obj"),
            "m.obj: line 2: vertex 2: x is not finite, got \"nan\"");
}

TEST(MeshFileErrors, ObjDegenerateTriangleIsKeptAndWarned) {
  const MeshFileContents contents =
      parseMeshFile("o flat\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n", "m.obj");
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_EQ(contents.objects[0].triangles.size(), 2u);
  EXPECT_THAT(contents.warnings,
              ElementsAre("m.obj: object \"flat\": 1 degenerate triangle kept (first: triangle "
                          "1)"));
}

// ---- Bad files: PLY --------------------------------------------------------------------------

const std::string kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(MeshFileErrors, PlyHeaderProblems) {
  EXPECT_EQ(errorOf("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", "m.ply"),
            "m.ply: header: no \"end_header\" line before the end of the file (after line 4)");
  EXPECT_EQ(errorOf("ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "m.ply"),
            "m.ply: line 3: element \"vertex\": count must be a non-negative integer, got \"-3\"");
  EXPECT_EQ(errorOf("ply\nformat ascii 1.0\nelement vertex 3x\nend_header\n", "m.ply"),
            "m.ply: line 3: element \"vertex\": count must be a non-negative integer, got \"3x\"");
  EXPECT_EQ(errorOf("ply\nformat binary_middle_endian 1.0\nend_header\n", "m.ply"),
            "m.ply: line 2: unknown format \"binary_middle_endian\"; expected ascii, "
            "binary_little_endian or binary_big_endian");
  EXPECT_EQ(
      errorOf("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nend_header\n", "m.ply"),
      "m.ply: element \"vertex\": missing property \"y\"");
}

TEST(MeshFileErrors, PlyTruncatedAndCountMismatch) {
  EXPECT_EQ(errorOf(kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "m.ply"),
            "m.ply: face 0: the file ends before property \"vertex_indices\" (truncated "
            "after line 13)");
  EXPECT_EQ(errorOf(kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", "m.ply"),
            "m.ply: line 14: unexpected data after the last element, got \"3\"");
  std::string binary = kPlyHeader;
  binary.replace(binary.find("ascii"), 5, "binary_little_endian");
  EXPECT_EQ(errorOf(binary + std::string(30, '\0'), "m.ply"),
            "m.ply: vertex 2: the file ends inside property \"y\" (truncated after " +
                std::to_string(binary.size() + 30) + " bytes)");
}

TEST(MeshFileErrors, PlyIndexOutOfRangeAndNonFinite) {
  EXPECT_EQ(errorOf(kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "m.ply"),
            "m.ply: face 0: vertex index 3 out of range for 3 vertices");
  EXPECT_EQ(errorOf(kPlyHeader + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "m.ply"),
            "m.ply: line 11: vertex 1: property \"y\" is not finite, got nan");
  std::string binary = kPlyHeader;
  binary.replace(binary.find("ascii"), 5, "binary_big_endian");
  const unsigned char bigEndianInfinity[4] = {0x7F, 0x80, 0, 0};
  std::string body(36, '\0');
  std::memcpy(body.data() + 20, bigEndianInfinity, 4);  // vertex 1, z
  body += std::string("\3\0\0\0\0\0\0\0\1\0\0\0\2", 13);
  EXPECT_EQ(errorOf(binary + body, "m.ply"),
            "m.ply: vertex 1: property \"z\" is not finite, got inf");
}

TEST(MeshFilePly, ElementWithoutPropertiesTakesNoBytesWhateverItsCount) {
  std::string header = kPlyHeader;
  header.insert(header.find("end_header"), "element nothing 18446744073709551615\n");
  const MeshFileContents contents =
      parseMeshFile(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "m.ply");
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_THAT(contents.objects[0].triangles, ElementsAre(glm::u32vec3(0, 1, 2)));
}

TEST(MeshFilePly, UnknownHeaderLinesAreSkippedWithAWarning) {
  // Blender 2.4's exporter wrote its credit line without "comment" (assimp's Wuson.ply).
  std::string header = kPlyHeader;
  header.insert(header.find("element"), "Created by Blender3D 247 - www.blender.org\n");
  header.insert(header.find("end_header"), "obj_info kept quietly\nuv_map?\n");
  const MeshFileContents contents =
      parseMeshFile(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "m.ply");
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_THAT(contents.objects[0].triangles, ElementsAre(glm::u32vec3(0, 1, 2)));
  ASSERT_EQ(contents.warnings.size(), 1u);
  EXPECT_EQ(contents.warnings[0],
            "m.ply: header lines 3, 11: unknown keyword, ignored as a comment");
}

TEST(MeshFileErrors, PlyWithoutFacesHoldsNoTriangles) {
  std::string empty = kPlyHeader;
  empty.replace(empty.find("face 1"), 6, "face 0");
  EXPECT_EQ(errorOf(empty + "0 0 0\n1 0 0\n0 1 0\n", "m.ply"),
            "m.ply: the file holds no triangles");
  EXPECT_EQ(errorOf("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float "
                    "y\nproperty float z\nend_header\n0 0 0\n1 0 0\n",
                    "m.ply"),
            "m.ply: header: missing element \"face\": a point cloud of 2 vertices; clipray "
            "compares surfaces, and points have none");
  // assimp's PLY/issue623.ply: the faces' index lists declared as a property of the vertices.
  EXPECT_EQ(errorOf("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                    "y\nproperty float z\nproperty list uchar uint vertex_indices\nend_header\n",
                    "m.ply"),
            "m.ply: header: missing element \"face\": the face lists are a property of element "
            "\"vertex\", where no reader looks for them (they belong in their own element "
            "\"face\")");
}

}  // namespace
}  // namespace clipray
