// Tests of core/mesh: loading each format, the checks, saving, mass properties,
// every error path by its message, and the shipped object models.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/mesh.h"

#ifndef AEROGRASP_DATA_DIR
#error "AEROGRASP_DATA_DIR must be defined (a string literal: the repository's data folder)"
#endif

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

// A fresh directory under the system's temporary folder, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ =
        fs::temp_directory_path() / (std::string("aerograsp_test_mesh_") + info->test_suite_name() +
                                     "_" + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string Path(const std::string& name) const { return (path_ / name).string(); }

  // Writes `contents` to a file named `name` and returns its path.
  std::string Write(const std::string& name, const std::string& contents) const {
    const std::string path = Path(name);
    std::ofstream out(path, std::ios::binary);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    EXPECT_TRUE(out.good()) << path;
    return path;
  }

 private:
  fs::path path_;
};

// The message LoadMesh (or another call) throws, or "" if it does not throw.
template <typename F>
std::string ErrorOf(F&& call) {
  try {
    call();
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

// ---------------------------------------------------------------------------
// The unit cube [0, 1]^3 with outward-facing quads, and writers for each format.

const double kCube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                              {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
const std::uint8_t kCubeColors[8][3] = {{255, 0, 0},   {0, 255, 0},   {0, 0, 255},  {255, 255, 0},
                                        {0, 255, 255}, {255, 0, 255}, {10, 20, 30}, {128, 64, 32}};

std::vector<std::array<int, 3>> CubeTriangles() {
  std::vector<std::array<int, 3>> triangles;
  for (const auto& q : kCubeQuads) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
  return triangles;
}

TriangleMesh CubeMesh() {
  TriangleMesh mesh;
  for (const auto& v : kCube) mesh.vertices.emplace_back(v[0], v[1], v[2]);
  for (const auto& t : CubeTriangles()) mesh.triangles.emplace_back(t[0], t[1], t[2]);
  return mesh;
}

template <typename T>
void AppendBinary(std::string* out, T value, bool big_endian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  const std::uint16_t one = 1;
  char first = 0;
  std::memcpy(&first, &one, 1);
  const bool host_little = first == 1;
  if (host_little == big_endian) std::reverse(bytes, bytes + sizeof(T));
  out->append(bytes, sizeof(T));
}

// ASCII PLY with quad faces (the loader fan-triangulates them), optionally coloured.
std::string AsciiPlyCube(bool with_color, double scale = 1.0) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment unit cube\nelement vertex 8\n"
      << "property float x\nproperty float y\nproperty float z\n";
  if (with_color) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out << "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 8; ++i) {
    out << kCube[i][0] * scale << " " << kCube[i][1] * scale << " " << kCube[i][2] * scale;
    if (with_color) {
      out << " " << int{kCubeColors[i][0]} << " " << int{kCubeColors[i][1]} << " "
          << int{kCubeColors[i][2]};
    }
    out << "\n";
  }
  for (const auto& q : kCubeQuads)
    out << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  return out.str();
}

// Binary PLY with triangle faces; float or double coordinates, int or uint indices.
std::string BinaryPlyCube(bool big_endian, bool double_coordinates, bool unsigned_indices) {
  std::string out = std::string("ply\nformat ") +
                    (big_endian ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" +
                    "element vertex 8\n";
  const char* type = double_coordinates ? "double" : "float";
  for (const char* axis : {"x", "y", "z"})
    out += std::string("property ") + type + " " + axis + "\n";
  out += "element face 12\nproperty list uchar ";
  out += unsigned_indices ? "uint" : "int";
  out += " vertex_indices\nend_header\n";
  for (const auto& v : kCube) {
    for (int a = 0; a < 3; ++a) {
      if (double_coordinates) {
        AppendBinary<double>(&out, v[a], big_endian);
      } else {
        AppendBinary<float>(&out, static_cast<float>(v[a]), big_endian);
      }
    }
  }
  for (const auto& t : CubeTriangles()) {
    out.push_back(3);
    for (int k : t) {
      if (unsigned_indices) {
        AppendBinary<std::uint32_t>(&out, static_cast<std::uint32_t>(k), big_endian);
      } else {
        AppendBinary<std::int32_t>(&out, k, big_endian);
      }
    }
  }
  return out;
}

// OBJ with quad faces written as v, v/vt, v//vn and v/vt/vn references.
std::string ObjCube() {
  std::ostringstream out;
  out << "# unit cube\no cube\n";
  for (const auto& v : kCube) out << "v " << v[0] << " " << v[1] << " " << v[2] << "\n";
  out << "vt 0 0\nvn 0 0 1\ns off\n";
  const char* suffixes[] = {"", "/1", "//1", "/1/1"};
  int f = 0;
  for (const auto& q : kCubeQuads) {
    out << "f";
    for (int k = 0; k < 4; ++k) out << " " << q[k] + 1 << suffixes[(f + k) % 4];
    out << "\n";
    ++f;
  }
  return out.str();
}

std::string AsciiStlCube() {
  std::ostringstream out;
  out << "solid cube made by hand\n";
  for (const auto& t : CubeTriangles()) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (int k : t)
      out << "      vertex " << kCube[k][0] << " " << kCube[k][1] << " " << kCube[k][2] << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid cube made by hand\n";
  return out.str();
}

std::string BinaryStlCube(const std::string& header_text, std::uint32_t declared_count = 12,
                          std::size_t written_count = 12) {
  std::string out = header_text;
  out.resize(80, ' ');
  AppendBinary<std::uint32_t>(&out, declared_count, false);
  const auto triangles = CubeTriangles();
  for (std::size_t i = 0; i < written_count; ++i) {
    for (int a = 0; a < 3; ++a) AppendBinary<float>(&out, 0.0f, false);  // normal, unused
    for (int k : triangles[i % triangles.size()]) {
      for (int a = 0; a < 3; ++a) AppendBinary<float>(&out, static_cast<float>(kCube[k][a]), false);
    }
    out.append(2, '\0');
  }
  return out;
}

// What every cube loaded from a file must satisfy.
void ExpectUnitCube(const TriangleMesh& mesh) {
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_TRUE(check.IsClosed()) << check.Describe();
  const MassProperties mass = ComputeMassProperties(mesh);
  EXPECT_NEAR(mass.volume_m3, 1.0, 1e-12);
  EXPECT_TRUE(mass.center_of_mass.isApprox(Eigen::Vector3d(0.5, 0.5, 0.5), 1e-12))
      << mass.center_of_mass.transpose();
}

// ---------------------------------------------------------------------------
// Loading

TEST(MeshLoadTest, AsciiPlyCubeWithQuadFacesLoads) {
  TempDir dir;
  const TriangleMesh mesh = LoadMesh(dir.Write("cube.ply", AsciiPlyCube(false)));
  ExpectUnitCube(mesh);
  EXPECT_TRUE(mesh.colors.empty());
}

TEST(MeshLoadTest, BinaryLittleEndianPlyCubeLoads) {
  TempDir dir;
  ExpectUnitCube(LoadMesh(dir.Write("cube.ply", BinaryPlyCube(false, false, true))));
}

TEST(MeshLoadTest, BinaryBigEndianPlyCubeLoads) {
  TempDir dir;
  ExpectUnitCube(LoadMesh(dir.Write("cube.ply", BinaryPlyCube(true, true, false))));
}

TEST(MeshLoadTest, PlySkipsPropertiesAndElementsItDoesNotUse) {
  TempDir dir;
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float nx\n"
      << "property float y\nproperty float z\nproperty list uchar float extra\n"
      << "element face 6\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
      << "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (const auto& v : kCube) out << v[0] << " 0.5 " << v[1] << " " << v[2] << " 2 7 8\n";
  for (const auto& q : kCubeQuads)
    out << "9 4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  out << "0 1\n";
  ExpectUnitCube(LoadMesh(dir.Write("cube.ply", out.str())));
}

TEST(MeshLoadTest, ObjCubeWithSlashedIndicesLoads) {
  TempDir dir;
  ExpectUnitCube(LoadMesh(dir.Write("cube.obj", ObjCube())));
}

TEST(MeshLoadTest, ObjNegativeIndicesCountBackFromTheLastVertex) {
  TempDir dir;
  // Each quad written right after its own four vertices, referenced as -4..-1.
  std::ostringstream out;
  for (const auto& q : kCubeQuads) {
    for (int k = 0; k < 4; ++k)
      out << "v " << kCube[q[k]][0] << " " << kCube[q[k]][1] << " " << kCube[q[k]][2] << "\n";
    out << "f -4/1 -3 -2 -1\n";
  }
  const TriangleMesh mesh = LoadMesh(dir.Write("cube.obj", out.str()));
  ASSERT_EQ(mesh.vertices.size(), 24u);
  ASSERT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(mesh.triangles[2], Eigen::Vector3i(4, 5, 6));
  EXPECT_NEAR(ComputeMassProperties(mesh).volume_m3, 1.0, 1e-12);
}

TEST(MeshLoadTest, AsciiStlCubeMergesItsVertices) {
  TempDir dir;
  ExpectUnitCube(LoadMesh(dir.Write("cube.stl", AsciiStlCube())));
}

TEST(MeshLoadTest, BinaryStlCubeMergesItsVertices) {
  TempDir dir;
  ExpectUnitCube(LoadMesh(dir.Write("cube.stl", BinaryStlCube("binary cube"))));
}

TEST(MeshLoadTest, BinaryStlIsRecognisedBySizeEvenWhenItsHeaderSaysSolid) {
  TempDir dir;
  ExpectUnitCube(
      LoadMesh(dir.Write("cube.stl", BinaryStlCube("solid cube exported by a CAD tool"))));
}

TEST(MeshLoadTest, StlMergesNegativeAndPositiveZero) {
  TempDir dir;
  std::string stl = AsciiStlCube();
  // The first corner at the origin written as -0 once.
  stl.replace(stl.find("vertex 0 0 0"), 12, "vertex -0 0 0");
  ExpectUnitCube(LoadMesh(dir.Write("cube.stl", stl)));
}

TEST(MeshLoadTest, ExtensionIsCaseInsensitive) {
  TempDir dir;
  ExpectUnitCube(LoadMesh(dir.Write("CUBE.PLY", AsciiPlyCube(false))));
}

TEST(MeshLoadTest, PlyVertexColoursAreRead) {
  TempDir dir;
  const TriangleMesh mesh = LoadMesh(dir.Write("cube.ply", AsciiPlyCube(true)));
  ASSERT_EQ(mesh.colors.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(mesh.colors[i], (std::array<std::uint8_t, 3>{kCubeColors[i][0], kCubeColors[i][1],
                                                           kCubeColors[i][2]}))
        << "vertex " << i;
  }
}

TEST(MeshLoadTest, ObjVertexColoursAreReadAsFractions) {
  TempDir dir;
  std::string obj = "v 0 0 0 1 0 0\nv 1 0 0 0 0.5 1\nv 0 1 0 0 0 0\nf 1 2 3\n";
  const TriangleMesh mesh = LoadMesh(dir.Write("tri.obj", obj));
  ASSERT_EQ(mesh.colors.size(), 3u);
  EXPECT_EQ(mesh.colors[0], (std::array<std::uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(mesh.colors[1], (std::array<std::uint8_t, 3>{0, 128, 255}));
  EXPECT_EQ(mesh.colors[2], (std::array<std::uint8_t, 3>{0, 0, 0}));
}

TEST(MeshLoadTest, SaveMeshPlyThenLoadMeshGivesTheSameMesh) {
  TempDir dir;
  TriangleMesh mesh = CubeMesh();
  for (auto& v : mesh.vertices) v = 0.1 * v + Eigen::Vector3d(0.123456789, -2.5, 1.0 / 3.0);
  for (const auto& c : kCubeColors) mesh.colors.push_back({c[0], c[1], c[2]});
  const std::string path = dir.Path("saved.ply");
  SaveMeshPly(mesh, path);
  const TriangleMesh loaded = LoadMesh(path);
  EXPECT_EQ(loaded.vertices, mesh.vertices);
  EXPECT_EQ(loaded.triangles, mesh.triangles);
  EXPECT_EQ(loaded.colors, mesh.colors);
}

TEST(MeshLoadTest, SaveMeshPlyWithoutColoursWritesNone) {
  TempDir dir;
  const std::string path = dir.Path("saved.ply");
  SaveMeshPly(CubeMesh(), path);
  const TriangleMesh loaded = LoadMesh(path);
  ExpectUnitCube(loaded);
  EXPECT_TRUE(loaded.colors.empty());
}

// ---------------------------------------------------------------------------
// Error paths, each by its message

TEST(MeshErrorTest, MissingFileIsNamed) {
  TempDir dir;
  const std::string path = dir.Path("absent.ply");
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }), path + ": cannot open file");
}

TEST(MeshErrorTest, UnknownExtensionIsNamed) {
  TempDir dir;
  const std::string path = dir.Write("x.foo", "whatever");
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": unknown mesh format '.foo' (expected .ply, .obj, .stl or .cao)");
}

TEST(MeshErrorTest, TruncatedBinaryStlSaysHowManyTrianglesItHolds) {
  TempDir dir;
  const std::string path = dir.Write("x.stl", BinaryStlCube("binary", 40, 12));
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": file is truncated: header says 40 triangles, found bytes for 12");
}

TEST(MeshErrorTest, TruncatedBinaryPlySaysWhereTheDataEnds) {
  TempDir dir;
  std::string ply = BinaryPlyCube(false, false, false);
  ply.resize(ply.size() - 13 * 5 - 2);  // the last five faces and a bit of the sixth last
  const std::string path = dir.Write("x.ply", ply);
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": file is truncated: data ends in face 6 of 12");
}

TEST(MeshErrorTest, PlyElementCountBeyondTheFileIsRefusedNotLoopedOver) {
  TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "end_header\n0 0 0\n0.1 0 0\n0 0.1 0\n3 0 1 2\n";
  // 2^64 - 1 entries of nothing: each takes no byte, so the count is all that bounds the loop.
  const std::string empty =
      dir.Write("empty.ply", header + "element junk 18446744073709551615\n" + body);
  EXPECT_EQ(ErrorOf([&] { LoadMesh(empty); }),
            empty +
                ": element 'junk' declares 18446744073709551615 entries of 0 properties, more "
                "than the 30 bytes after the header hold (corrupt header or truncated file?)");
  const std::string many =
      dir.Write("many.ply", header + "element junk 1000000000000\nproperty uchar a\n" + body);
  EXPECT_THAT(ErrorOf([&] { LoadMesh(many); }),
              HasSubstr("element 'junk' declares 1000000000000 entries of 1 properties"));
}

TEST(MeshErrorTest, TruncatedAsciiStlNamesTheUnfinishedFacet) {
  TempDir dir;
  std::string stl = AsciiStlCube();
  stl.resize(stl.find("endloop", stl.find("facet normal", 100)));  // inside the 2nd facet
  const std::string path = dir.Write("x.stl", stl);
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": file is truncated: facet 2 is not finished");
}

TEST(MeshErrorTest, PlyFaceIndexOutOfRangeNamesFaceAndVertexCount) {
  TempDir dir;
  std::string ply = AsciiPlyCube(false);
  ply.replace(ply.find("4 0 4 7 3"), 9, "4 0 4 8 3");  // face 4
  const std::string path = dir.Write("x.ply", ply);
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": face 4 refers to vertex 8 but the file has 8 vertices");
}

TEST(MeshErrorTest, ObjFaceIndexOutOfRangeNamesLineAndVertexCount) {
  TempDir dir;
  const std::string path = dir.Write("x.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 907\n");
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": line 5: face refers to vertex 907 but the file has 3 vertices");
}

TEST(MeshErrorTest, ObjNegativeIndexBeforeTheFirstVertexIsNamed) {
  TempDir dir;
  const std::string path = dir.Write("x.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": line 3: face refers to vertex -3 but only 2 vertices are defined before it");
}

TEST(MeshErrorTest, ObjWithoutFacesHasNoTriangles) {
  TempDir dir;
  const std::string path = dir.Write("x.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }), path + ": no triangles");
}

TEST(MeshErrorTest, PlyNonFiniteCoordinateNamesTheVertex) {
  TempDir dir;
  std::string ply = AsciiPlyCube(false);
  ply.replace(ply.find("0 1 0\n"), 5, "0 nan 0");  // vertex 3
  const std::string path = dir.Write("x.ply", ply);
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }), path + ": vertex 3 has a non-finite coordinate");
}

TEST(MeshErrorTest, MeshInMillimetresIsCaughtByItsExtent) {
  TempDir dir;
  const std::string path = dir.Write("x.ply", AsciiPlyCube(false, 250.0));
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": extent 250 m is over 10 m: is the mesh in millimetres?");
}

TEST(MeshErrorTest, PlyFaceWithTwoVerticesIsNamed) {
  TempDir dir;
  std::string ply = AsciiPlyCube(false);
  ply.replace(ply.find("4 4 5 6 7"), 9, "2 4 5");  // face 1
  const std::string path = dir.Write("x.ply", ply);
  EXPECT_THAT(ErrorOf([&] { LoadMesh(path); }),
              StartsWith(path + ": face 1 has 2 vertices (need at least 3)"));
}

TEST(MeshErrorTest, PlyBadNumberNamesLineAndVertex) {
  TempDir dir;
  std::string ply = AsciiPlyCube(false);
  ply.replace(ply.find("1 1 0\n"), 5, "1 x 0");  // vertex 2, on line 13
  const std::string path = dir.Write("x.ply", ply);
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": line 13: vertex 2: expected a number, found 'x'");
}

TEST(MeshErrorTest, NotAPlyFileIsNamed) {
  TempDir dir;
  const std::string path = dir.Write("x.ply", "solid cube\nendsolid\n");
  EXPECT_EQ(ErrorOf([&] { LoadMesh(path); }),
            path + ": not a PLY file (the first line is not 'ply')");
}

TEST(MeshErrorTest, TooShortStlIsNamed) {
  TempDir dir;
  const std::string path = dir.Write("x.stl", std::string(20, '\x01'));
  EXPECT_THAT(ErrorOf([&] { LoadMesh(path); }),
              StartsWith(path + ": not an STL file: 20 bytes is too short"));
}

TEST(MeshErrorTest, SaveMeshPlyToAMissingFolderSaysItCannotWrite) {
  TempDir dir;
  const std::string path = dir.Path("no/such/folder/x.ply");
  EXPECT_EQ(ErrorOf([&] { SaveMeshPly(CubeMesh(), path); }),
            path + ": cannot open file for writing");
}

// ---------------------------------------------------------------------------
// CheckMesh and LoadClosedMesh

TEST(MeshCheckTest, CubeIsClosedWithUnitVolume) {
  const MeshCheck check = CheckMesh(CubeMesh());
  EXPECT_TRUE(check.IsClosed());
  EXPECT_EQ(check.degenerate_triangles, 0u);
  EXPECT_NEAR(check.signed_volume_m3, 1.0, 1e-12);
  EXPECT_EQ(check.Describe(), "closed, volume 1 m^3");
}

TEST(MeshCheckTest, CubeMissingOneTriangleHasThreeBoundaryEdges) {
  TriangleMesh mesh = CubeMesh();
  mesh.triangles.pop_back();
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_EQ(check.boundary_edges, 3u);
  EXPECT_EQ(check.nonmanifold_edges, 0u);
  EXPECT_EQ(check.inconsistent_edges, 0u);
  EXPECT_FALSE(check.IsClosed());
  EXPECT_EQ(check.Describe(), "3 boundary edges");
}

TEST(MeshCheckTest, LoadClosedMeshRejectsACubeWithAHoleNamingPathAndBoundary) {
  TempDir dir;
  std::string ply = BinaryPlyCube(false, false, false);
  ply.replace(ply.find("element face 12"), 15, "element face 11");
  ply.resize(ply.size() - 13);
  const std::string path = dir.Write("holed.ply", ply);
  EXPECT_EQ(LoadMesh(path).triangles.size(), 11u);
  const std::string error = ErrorOf([&] { LoadClosedMesh(path); });
  EXPECT_THAT(error, StartsWith(path + ": "));
  EXPECT_THAT(error, HasSubstr("3 boundary edges"));
}

TEST(MeshCheckTest, LoadClosedMeshAcceptsAClosedCube) {
  TempDir dir;
  ExpectUnitCube(LoadClosedMesh(dir.Write("cube.ply", AsciiPlyCube(false))));
}

TEST(MeshCheckTest, CubeWithOneFlippedTriangleHasInconsistentEdges) {
  TriangleMesh mesh = CubeMesh();
  std::swap(mesh.triangles[5][1], mesh.triangles[5][2]);
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_EQ(check.inconsistent_edges, 3u);
  EXPECT_EQ(check.boundary_edges, 0u);
  EXPECT_FALSE(check.IsClosed());
  EXPECT_EQ(check.Describe(), "3 inconsistently oriented edges");
}

TEST(MeshCheckTest, InwardFacingCubeHasNegativeVolume) {
  TriangleMesh mesh = CubeMesh();
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_EQ(check.inconsistent_edges, 0u);
  EXPECT_NEAR(check.signed_volume_m3, -1.0, 1e-12);
  EXPECT_FALSE(check.IsClosed());
  EXPECT_THAT(check.Describe(), HasSubstr("triangles face inwards"));
}

TEST(MeshCheckTest, ThirdTriangleOnAnEdgeMakesItNonManifold) {
  TriangleMesh mesh = CubeMesh();
  mesh.vertices.emplace_back(0.5, -1.0, 0.0);
  mesh.triangles.emplace_back(0, 1, 8);  // on the edge 0-1, which two cube triangles share
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_EQ(check.nonmanifold_edges, 1u);
  EXPECT_EQ(check.boundary_edges, 2u);  // 1-8 and 8-0
  EXPECT_FALSE(check.IsClosed());
}

TEST(MeshCheckTest, ZeroAreaTrianglesAreCountedDegenerate) {
  TriangleMesh mesh = CubeMesh();
  mesh.vertices.emplace_back(2.0, 0.0, 0.0);
  mesh.triangles.emplace_back(0, 1, 8);  // collinear
  mesh.triangles.emplace_back(3, 3, 2);  // repeated vertex
  EXPECT_EQ(CheckMesh(mesh).degenerate_triangles, 2u);
}

TEST(MeshCheckTest, DescribeListsEveryDefect) {
  MeshCheck check;
  check.boundary_edges = 1;
  check.nonmanifold_edges = 2;
  check.inconsistent_edges = 3;
  check.degenerate_triangles = 4;
  check.signed_volume_m3 = 0.5;
  EXPECT_EQ(check.Describe(),
            "1 boundary edge, 2 non-manifold edges, 3 inconsistently oriented edges, "
            "4 degenerate triangles");
}

// ---------------------------------------------------------------------------
// Bounds, normals, mass properties

TEST(TriangleMeshTest, BoundsOfAnEmptyMeshAreZero) {
  const TriangleMesh mesh;
  EXPECT_EQ(mesh.BoundsMin(), Eigen::Vector3d::Zero());
  EXPECT_EQ(mesh.BoundsMax(), Eigen::Vector3d::Zero());
}

TEST(TriangleMeshTest, BoundsEncloseTheVertices) {
  TriangleMesh mesh = CubeMesh();
  mesh.vertices.emplace_back(-1.0, 0.5, 3.0);
  EXPECT_EQ(mesh.BoundsMin(), Eigen::Vector3d(-1.0, 0.0, 0.0));
  EXPECT_EQ(mesh.BoundsMax(), Eigen::Vector3d(1.0, 1.0, 3.0));
}

TEST(TriangleMeshTest, TriangleNormalsOfTheCubePointOutwards) {
  const TriangleMesh mesh = CubeMesh();
  const Eigen::Vector3d centre(0.5, 0.5, 0.5);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3d n = mesh.TriangleNormal(i);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    const Eigen::Vector3d to_face = mesh.vertices[mesh.triangles[i][0]] - centre;
    EXPECT_GT(n.dot(to_face), 0.0) << "triangle " << i;
  }
  EXPECT_TRUE(mesh.TriangleNormal(0).isApprox(Eigen::Vector3d(0, 0, -1)));
}

TEST(TriangleMeshTest, NormalOfADegenerateTriangleIsZero) {
  TriangleMesh mesh;
  mesh.vertices = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(2, 0, 0)};
  mesh.triangles = {Eigen::Vector3i(0, 1, 2)};
  EXPECT_EQ(mesh.TriangleNormal(0), Eigen::Vector3d::Zero());
}

TEST(MassPropertiesTest, BoxFarFromTheOriginHasItsVolumeAndCentre) {
  TriangleMesh mesh = CubeMesh();
  const Eigen::Vector3d size(0.2, 0.3, 0.4);
  const Eigen::Vector3d offset(5.0, -3.0, 2.0);
  for (auto& v : mesh.vertices) v = offset + v.cwiseProduct(size);
  const MassProperties mass = ComputeMassProperties(mesh);
  EXPECT_NEAR(mass.volume_m3, 0.024, 1e-12);
  EXPECT_TRUE(mass.center_of_mass.isApprox(offset + 0.5 * size, 1e-12))
      << mass.center_of_mass.transpose();
}

TEST(MassPropertiesTest, LShapeHasItsCentroidOffTheBoundsCentre) {
  // Two unit cubes side by side along x plus one on top of the first: the L
  // (x in [0,2], z in [0,2]) has volume 3 and centroid (5/6, 1/2, 5/6).
  TempDir dir;
  std::ostringstream obj;
  // Cross-section in x-z (counter-clockwise seen from -y), extruded along y by 1.
  const double section[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (double y : {0.0, 1.0}) {
    for (const auto& p : section) obj << "v " << p[0] << " " << y << " " << p[1] << "\n";
  }
  // Near face y=0 faces -y; far face y=1 faces +y; sides face out.
  obj << "f 1 2 3 4 5 6\nf 7 12 11 10 9 8\n";
  for (int k = 0; k < 6; ++k) {
    const int a = k + 1, b = (k + 1) % 6 + 1;
    obj << "f " << a << " " << a + 6 << " " << b + 6 << " " << b << "\n";
  }
  const TriangleMesh mesh = LoadClosedMesh(dir.Write("l.obj", obj.str()));
  const MassProperties mass = ComputeMassProperties(mesh);
  EXPECT_NEAR(mass.volume_m3, 3.0, 1e-12);
  EXPECT_TRUE(mass.center_of_mass.isApprox(Eigen::Vector3d(5.0 / 6.0, 0.5, 5.0 / 6.0), 1e-12))
      << mass.center_of_mass.transpose();
}

// ---------------------------------------------------------------------------
// The shipped object models (data/objects/*/, written by tools/make_objects.py)

TEST(ObjectModelsTest, EveryShippedMeshIsClosedInMetresAndMatchesItsYaml) {
  const fs::path objects = fs::path(AEROGRASP_DATA_DIR) / "objects";
  ASSERT_TRUE(fs::is_directory(objects)) << objects;
  std::vector<fs::path> folders;
  for (const fs::directory_entry& entry : fs::directory_iterator(objects)) {
    if (entry.is_directory()) folders.push_back(entry.path());
  }
  std::sort(folders.begin(), folders.end());
  ASSERT_GE(folders.size(), 3u) << "expected the crawler, u_shape and pipe models in " << objects;
  for (const fs::path& folder : folders) {
    SCOPED_TRACE(folder.string());
    const fs::path yaml_path = folder / "object.yaml";
    ASSERT_TRUE(fs::exists(yaml_path));
    const YAML::Node yaml = YAML::LoadFile(yaml_path.string());
    EXPECT_EQ(yaml["name"].as<std::string>(), folder.filename().string());
    const TriangleMesh mesh = LoadClosedMesh((folder / yaml["mesh"].as<std::string>()).string());

    const Eigen::Vector3d extent = mesh.BoundsMax() - mesh.BoundsMin();
    EXPECT_GE(extent.maxCoeff(), 0.05);
    EXPECT_LE(extent.maxCoeff(), 1.0);
    // Frame convention: origin at the bounds centre, x along the longest side.
    EXPECT_LT((mesh.BoundsMax() + mesh.BoundsMin()).norm(), 1e-6);
    EXPECT_EQ(extent.maxCoeff(), extent.x());

    const MassProperties mass = ComputeMassProperties(mesh);
    EXPECT_GT(yaml["mass_kg"].as<double>(), 0.0);
    const auto com = yaml["center_of_mass_m"].as<std::vector<double>>();
    const auto dimensions = yaml["dimensions_m"].as<std::vector<double>>();
    ASSERT_EQ(com.size(), 3u);
    ASSERT_EQ(dimensions.size(), 3u);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(com[a], mass.center_of_mass[a], 1e-6) << "axis " << a;
      EXPECT_NEAR(dimensions[a], extent[a], 1e-6) << "axis " << a;
    }
    EXPECT_EQ(mesh.colors.size(), mesh.vertices.size());
  }
}

}  // namespace
}  // namespace aerograsp
