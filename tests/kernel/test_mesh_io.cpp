#include "st/mesh_io.h"

#include "st/errors.h"

#include <sys/stat.h>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

// ---- fixtures built in code ---------------------------------------------------------------------

fs::path output_dir() {
  const fs::path dir = fs::path(ST_TEST_OUTPUT_DIR) / "mesh_io";
  fs::create_directories(dir);
  return dir;
}

std::string temp_path(const std::string& file) { return (output_dir() / file).string(); }

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Regular octahedron with vertices at +-r on the axes: 6 vertices, 8 outward triangles.
st::TriangleMesh octahedron(double r = 1.0, st::Vec3 c = st::Vec3::Zero()) {
  st::TriangleMesh m;
  m.positions = {c + st::Vec3(r, 0, 0), c + st::Vec3(-r, 0, 0), c + st::Vec3(0, r, 0),
                 c + st::Vec3(0, -r, 0), c + st::Vec3(0, 0, r), c + st::Vec3(0, 0, -r)};
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        const st::Index x = sx, y = 2 + sy, z = 4 + sz;
        if ((sx + sy + sz) % 2 == 0)
          m.triangles.push_back({x, y, z});
        else
          m.triangles.push_back({x, z, y});
      }
  return m;
}

/// Unit cube corners, numbered x + 2y... as in the PLY/OBJ fixtures below.
const double kCube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
/// Its six faces as outward counter-clockwise quads.
const int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                              {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};

/// Every edge is used by exactly two triangles, once in each direction (closed, oriented).
bool closed_and_oriented(const st::TriangleMesh& m) {
  std::map<std::pair<st::Index, st::Index>, int> directed;
  for (const st::Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return !m.triangles.empty();
}

double signed_volume_of(const st::TriangleMesh& m) {
  double v = 0.0;
  for (const st::Triangle& t : m.triangles) {
    const st::Vec3& a = m.positions[t[0]];
    const st::Vec3& b = m.positions[t[1]];
    const st::Vec3& c = m.positions[t[2]];
    v += a.x() * (b.y() * c.z() - b.z() * c.y()) - a.y() * (b.x() * c.z() - b.z() * c.x()) +
         a.z() * (b.x() * c.y() - b.y() * c.x());
  }
  return v / 6.0;
}

/// Same triangles in the same order, with corners at the same coordinates (up to `tol`).
void expect_same_corners(const st::TriangleMesh& expected, const st::TriangleMesh& actual,
                         double tol = 0.0) {
  ASSERT_EQ(expected.triangles.size(), actual.triangles.size());
  for (std::size_t f = 0; f < expected.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const st::Vec3& e = expected.positions[expected.triangles[f][k]];
      const st::Vec3& a = actual.positions[actual.triangles[f][k]];
      EXPECT_LE((e - a).cwiseAbs().maxCoeff(), tol) << "triangle " << f << " corner " << k;
    }
}

/// Runs `read` and expects InvalidInput whose message holds every one of `parts`.
void expect_invalid(const std::function<void()>& read, std::initializer_list<std::string> parts) {
  try {
    read();
    ADD_FAILURE() << "expected st::InvalidInput";
  } catch (const st::InvalidInput& e) {
    const std::string message = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos)
          << "message '" << message << "' lacks '" << part << "'";
  }
}

void put_f32(std::string& out, float v) {
  const auto bits = std::bit_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xff);
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

/// Binary STL bytes written by the test itself (not by write_stl), normals left zero.
std::string stl_binary(const st::TriangleMesh& m, const std::string& header = "test") {
  std::string out = header.substr(0, 80);
  out.resize(80, ' ');
  put_u32(out, static_cast<std::uint32_t>(m.triangles.size()));
  for (const st::Triangle& t : m.triangles) {
    for (int i = 0; i < 3; ++i) put_f32(out, 0.0f);
    for (st::Index v : t)
      for (int d = 0; d < 3; ++d) put_f32(out, static_cast<float>(m.positions[v][d]));
    out += std::string(2, '\0');
  }
  return out;
}

std::string stl_ascii(const st::TriangleMesh& m, const std::string& name = "octa") {
  std::ostringstream out;
  out.precision(9);
  out << "solid " << name << "\n";
  for (const st::Triangle& t : m.triangles) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (st::Index v : t)
      out << "      vertex " << m.positions[v].x() << " " << m.positions[v].y() << " "
          << m.positions[v].z() << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid " << name << "\n";
  return out.str();
}

/// Little helper to build binary PLY bodies in either byte order.
class PlyBytes {
public:
  explicit PlyBytes(bool big_endian) : big_(big_endian) {}
  template <typename T> PlyBytes& put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_ != (std::endian::native == std::endian::big))
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    bytes_.append(raw, sizeof(T));
    return *this;
  }
  const std::string& str() const { return bytes_; }

private:
  bool big_;
  std::string bytes_;
};

/// The cube as PLY with extra vertex and face properties (a vertex list property too), quads, an
/// extra element before and after, and coordinates of three different types.
std::string cube_ply(const std::string& format) {
  std::string header = "ply\nformat " + format + " 1.0\ncomment made by test SPACE=RAS\n";
  header += "element camera 1\nproperty float view_px\nproperty list uchar int tags\n";
  header += "element vertex 8\nproperty float x\nproperty uchar red\nproperty double y\n"
            "property list uchar float extra\nproperty int z\nproperty float32 confidence\n";
  header += "element face 6\nproperty uchar intensity\nproperty list uchar uint vertex_indices\n"
            "property float64 quality\n";
  header += "element edge 2\nproperty int vertex1\nproperty int vertex2\n";
  header += "element nothing 4000000000\n";  // no properties: takes no bytes
  header += "end_header\n";
  if (format == "ascii") {
    std::string body = "7.5 2 11 22\n";
    for (int v = 0; v < 8; ++v)
      body += std::to_string(kCube[v][0]) + " 200 " + std::to_string(kCube[v][1]) + " 2 0.5 " +
              "1.5 " + std::to_string(static_cast<int>(kCube[v][2])) + " 0.25\n";
    for (const auto& q : kCubeQuads)
      body += "9 4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " +
              std::to_string(q[2]) + " " + std::to_string(q[3]) + " 0.5\n";
    body += "0 1\n1 2\n";
    return header + body;
  }
  PlyBytes b(format == "binary_big_endian");
  b.put(7.5f).put<std::uint8_t>(2).put<std::int32_t>(11).put<std::int32_t>(22);
  for (int v = 0; v < 8; ++v) {
    b.put(static_cast<float>(kCube[v][0])).put<std::uint8_t>(200).put(kCube[v][1]);
    b.put<std::uint8_t>(2).put(0.5f).put(1.5f);
    b.put(static_cast<std::int32_t>(kCube[v][2])).put(0.25f);
  }
  for (const auto& q : kCubeQuads) {
    b.put<std::uint8_t>(9).put<std::uint8_t>(4);
    for (int i : q) b.put(static_cast<std::uint32_t>(i));
    b.put(0.5);
  }
  b.put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(1).put<std::int32_t>(2);
  return header + b.str();
}

void expect_cube(const st::TriangleMesh& m, const st::ReadReport& r) {
  ASSERT_EQ(m.vertex_count(), 8u);
  EXPECT_EQ(m.face_count(), 12u);  // 6 quads, fan-triangulated
  EXPECT_EQ(r.input_triangles, 12u);
  EXPECT_EQ(r.degenerate_dropped, 0u);
  for (int v = 0; v < 8; ++v)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(m.positions[v][d], kCube[v][d]) << v << " " << d;
  EXPECT_TRUE(closed_and_oriented(m));
  EXPECT_NEAR(signed_volume_of(m), 1.0, 1e-12);
}

st::TriangleMesh read_memory(const std::string& bytes, st::MeshFormat format,
                             st::ReadReport* report = nullptr) {
  return st::read_mesh_from_memory(bytes.data(), bytes.size(), format, "memory", report);
}

// ---- STL ----------------------------------------------------------------------------------------

TEST(MeshIoStl, BinaryOctahedronSeamsWelded) {
  const st::TriangleMesh octa = octahedron(2.5, st::Vec3(10, -20, 30));
  const std::string path = temp_path("octa_binary.stl");
  write_bytes(path, stl_binary(octa, "octahedron"));
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  EXPECT_EQ(m.vertex_count(), 6u);
  EXPECT_EQ(m.face_count(), 8u);
  EXPECT_EQ(report.input_triangles, 8u);
  EXPECT_EQ(report.merged_vertices, 24u - 6u);
  EXPECT_EQ(report.degenerate_dropped, 0u);
  EXPECT_EQ(report.format, st::MeshFormat::Stl);
  EXPECT_EQ(report.header, "octahedron");
  EXPECT_TRUE(closed_and_oriented(m));
  expect_same_corners(octa, m);
}

TEST(MeshIoStl, AsciiOctahedronSeamsWelded) {
  const st::TriangleMesh octa = octahedron(1.25, st::Vec3(-4, 0.5, 8));
  const std::string path = temp_path("octa_ascii.stl");
  write_bytes(path, stl_ascii(octa, "octa SPACE=RAS"));
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  EXPECT_EQ(m.vertex_count(), 6u);
  EXPECT_EQ(m.face_count(), 8u);
  EXPECT_EQ(report.merged_vertices, 18u);
  EXPECT_EQ(report.header, "solid octa SPACE=RAS");
  EXPECT_TRUE(closed_and_oriented(m));
  expect_same_corners(octa, m);
}

TEST(MeshIoStl, AsciiToleratesCaseWhitespaceCrlfAndSeveralSolids) {
  const std::string text =
      "  SOLID first part\r\n"
      "FACET NORMAL nan nan nan\r\n\tOUTER LOOP\r\n"
      "\t\tVERTEX 0 0 0\r\n vertex\t1e0   0 0\r\n vertex +0 1 -0\r\n ENDLOOP\r\nENDFACET\r\n"
      "endsolid first part\r\n"
      "solid second\n facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 0 0 1 "
      "endloop endfacet\nendsolid";
  st::ReadReport report;
  const st::TriangleMesh m = read_memory(text, st::MeshFormat::Stl, &report);
  EXPECT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.vertex_count(), 4u);  // (0,0,0) and (1,0,0) shared, -0 welded with 0
  EXPECT_EQ(report.header, "SOLID first part\nsolid second");
}

TEST(MeshIoStl, AsciiErrorsNameTheLine) {
  expect_invalid(
      [] {
        read_memory("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 oops 0\n",
                    st::MeshFormat::Stl);
      },
      {"memory", "line 5", "oops"});
  expect_invalid(
      [] {
        read_memory("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                    "endloop\nendfacet\n",
                    st::MeshFormat::Stl);
      },
      {"line 6", "facet 0", "2 vertices"});
  expect_invalid([] { read_memory("solid x\nfacet normal 0 0 1\nouter", st::MeshFormat::Stl); },
                 {"line 3", "end of file"});
}

TEST(MeshIoStl, BinaryWhoseHeaderStartsWithSolidIsReadAsBinary) {
  const st::TriangleMesh octa = octahedron();
  const std::string path = temp_path("solid_header_binary.stl");
  write_bytes(path, stl_binary(octa, "solid this is really binary"));
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  EXPECT_EQ(m.face_count(), 8u);
  EXPECT_EQ(m.vertex_count(), 6u);
  EXPECT_EQ(report.header, "solid this is really binary");
  expect_same_corners(octa, m);
}

TEST(MeshIoStl, TruncatedBinaryThrowsWithSizes) {
  std::string bytes = stl_binary(octahedron());
  bytes.resize(bytes.size() - 10);
  const std::string path = temp_path("truncated.stl");
  write_bytes(path, bytes);
  expect_invalid([&] { st::read_mesh(path); },
                 {path, "truncated", "8 triangles", "needs 484 bytes", "has 474 bytes"});
  // The same with a header starting with "solid": still reported as a truncated binary file.
  std::string solid = stl_binary(octahedron(), "solid name");
  solid.resize(solid.size() - 50);
  expect_invalid([&] { read_memory(solid, st::MeshFormat::Stl); }, {"truncated", "8 triangles"});
  // Shorter than the header.
  expect_invalid([] { read_memory(std::string(40, '\x01'), st::MeshFormat::Stl); },
                 {"truncated", "40 bytes"});
}

TEST(MeshIoStl, ZeroTrianglesThrows) {
  expect_invalid([] { read_memory(stl_binary(st::TriangleMesh{}), st::MeshFormat::Stl); },
                 {"contains no triangles"});
  expect_invalid([] { read_memory("solid empty\nendsolid empty\n", st::MeshFormat::Stl); },
                 {"contains no triangles"});
}

TEST(MeshIoStl, NonFiniteCoordinateNamesTriangleAndCorner) {
  st::TriangleMesh octa = octahedron();
  octa.positions.push_back(st::Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  octa.triangles[5][1] = 6;
  expect_invalid([&] { read_memory(stl_binary(octa), st::MeshFormat::Stl); },
                 {"triangle 5", "corner 1", "non-finite"});
  octa.positions[6] = st::Vec3(0, std::numeric_limits<double>::infinity(), 0);
  expect_invalid([&] { read_memory(stl_binary(octa), st::MeshFormat::Stl); },
                 {"triangle 5", "corner 1", "non-finite"});
  // ASCII: the line too; values beyond float32 count as non-finite.
  std::string text = stl_ascii(octahedron());
  text.replace(text.find("vertex 1 0 0"), 12, "vertex 1e39 0 0");
  expect_invalid([&] { read_memory(text, st::MeshFormat::Stl); },
                 {"line 4", "facet 0", "corner 0", "non-finite"});
}

TEST(MeshIoStl, GarbageThrowsInvalidInput) {
  std::string garbage;
  std::uint32_t state = 12345;
  for (int i = 0; i < 1000; ++i) {
    state = state * 1664525u + 1013904223u;
    garbage += static_cast<char>(state >> 24);
  }
  expect_invalid([&] { read_memory(garbage, st::MeshFormat::Stl); }, {"truncated or corrupt"});
  expect_invalid([&] { read_memory(garbage, st::MeshFormat::Auto); }, {"memory"});
  expect_invalid([&] { read_memory(garbage, st::MeshFormat::Ply); }, {"not a PLY file"});
  expect_invalid([] { read_memory("solid\nthis is not a facet\n", st::MeshFormat::Stl); },
                 {"line 2", "expected 'facet'"});
}

TEST(MeshIoStl, NegativeZeroWeldsWithZero) {
  st::TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.0, -0.0, 0.0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {3, 2, 4}};
  st::ReadReport report;
  const st::TriangleMesh back = read_memory(stl_binary(m), st::MeshFormat::Stl, &report);
  EXPECT_EQ(back.vertex_count(), 4u);
  EXPECT_EQ(back.triangles[1][0], back.triangles[0][0]);
  EXPECT_EQ(report.merged_vertices, 2u);
}

TEST(MeshIoStl, DegenerateTrianglesDroppedAndCounted) {
  st::TriangleMesh m = octahedron();
  m.triangles.insert(m.triangles.begin() + 3, st::Triangle{0, 0, 2});
  m.triangles.push_back({4, 4, 4});
  m.positions.push_back(m.positions[1]);  // welds with vertex 1
  m.triangles.push_back({1, 6, 3});
  st::ReadReport report;
  const st::TriangleMesh back = read_memory(stl_binary(m), st::MeshFormat::Stl, &report);
  EXPECT_EQ(report.input_triangles, 11u);
  EXPECT_EQ(report.degenerate_dropped, 3u);
  EXPECT_EQ(back.face_count(), 8u);
  EXPECT_TRUE(closed_and_oriented(back));
  expect_same_corners(octahedron(), back);

  st::TriangleMesh all_bad;
  all_bad.positions = {{0, 0, 0}, {1, 0, 0}};
  all_bad.triangles = {{0, 0, 1}, {1, 1, 1}};
  expect_invalid([&] { read_memory(stl_binary(all_bad), st::MeshFormat::Stl); },
                 {"all 2 triangles are degenerate"});
}

TEST(MeshIoStl, LargeBinaryIsReadInLinearTime) {
  // 200k triangles of a strip: 100k + 2 vertex pairs. Quadratic work would take minutes.
  st::TriangleMesh strip;
  const int n = 100000;
  for (int i = 0; i <= n; ++i) {
    strip.positions.emplace_back(0.5 * i, 0.0, 0.0);
    strip.positions.emplace_back(0.5 * i, 1.0, std::sin(0.01 * i));
  }
  for (st::Index i = 0; i < static_cast<st::Index>(n); ++i) {
    strip.triangles.push_back({2 * i, 2 * i + 2, 2 * i + 1});
    strip.triangles.push_back({2 * i + 1, 2 * i + 2, 2 * i + 3});
  }
  const std::string bytes = stl_binary(strip);
  const auto start = std::chrono::steady_clock::now();
  const st::TriangleMesh m = read_memory(bytes, st::MeshFormat::Stl);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(m.face_count(), 2u * n);
  EXPECT_EQ(m.vertex_count(), 2u * (n + 1));
  EXPECT_LT(seconds, 5.0);  // about 0.02 s in a release build
}

// ---- PLY ----------------------------------------------------------------------------------------

TEST(MeshIoPly, AsciiWithExtraPropertiesAndQuads) {
  st::ReadReport report;
  const st::TriangleMesh m = read_memory(cube_ply("ascii"), st::MeshFormat::Ply, &report);
  expect_cube(m, report);
  EXPECT_EQ(report.format, st::MeshFormat::Ply);
  EXPECT_EQ(report.header, "made by test SPACE=RAS");
}

TEST(MeshIoPly, BinaryLittleEndianWithExtraPropertiesAndQuads) {
  const std::string path = temp_path("cube_le.ply");
  write_bytes(path, cube_ply("binary_little_endian"));
  st::ReadReport report;
  expect_cube(st::read_mesh(path, &report), report);
}

TEST(MeshIoPly, BinaryBigEndianWithExtraPropertiesAndQuads) {
  st::ReadReport report;
  expect_cube(read_memory(cube_ply("binary_big_endian"), st::MeshFormat::Ply, &report), report);
}

TEST(MeshIoPly, FacesBeforeVerticesAndVertexIndexName) {
  const std::string text = "ply\r\nformat ascii 1.0\r\nelement face 1\r\n"
                           "property list uint8 int16 vertex_index\r\n"
                           "element vertex 3\r\nproperty float64 z\r\nproperty float64 y\r\n"
                           "property float64 x\r\nend_header\r\n"
                           "3 0 1 2\r\n0 0 0\r\n0 0 1\r\n0 1 0\r\n";
  const st::TriangleMesh m = read_memory(text, st::MeshFormat::Ply);
  ASSERT_EQ(m.face_count(), 1u);
  EXPECT_EQ(m.positions[1], st::Vec3(1, 0, 0));
  EXPECT_EQ(m.positions[2], st::Vec3(0, 1, 0));
}

TEST(MeshIoPly, IndexOutOfRangeNamesTheFace) {
  std::string text = cube_ply("ascii");
  text.replace(text.find("9 4 1 2 6 5"), 11, "9 4 1 2 6 8");
  expect_invalid([&] { read_memory(text, st::MeshFormat::Ply); },
                 {"face 5", "vertex 8", "only 8 vertices", "line"});
  std::string binary = cube_ply("binary_little_endian");
  // The last index of the first face (0 3 2 1): make it 99.
  const std::size_t body = binary.find("end_header\n") + 11;
  const std::size_t first_face = body + 4 + 1 + 4 + 4 + 8 * (4 + 1 + 8 + 1 + 4 + 4 + 4 + 4);
  binary[first_face + 2 + 12] = 99;
  expect_invalid([&] { read_memory(binary, st::MeshFormat::Ply); },
                 {"face 0", "vertex 99", "byte offset"});
}

TEST(MeshIoPly, NonFiniteVertexNamed) {
  std::string text = cube_ply("ascii");
  const std::size_t third_vertex = text.find("1.000000 200 1.000000");
  text.replace(third_vertex, 8, "nan");
  expect_invalid([&] { read_memory(text, st::MeshFormat::Ply); }, {"vertex 2", "non-finite"});
}

TEST(MeshIoPly, HugeCountsAreRefusedBeforeReserving) {
  const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                           "property float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expect_invalid([&] { read_memory(head + std::string(24, '\0'), st::MeshFormat::Ply); },
                 {"vertex", "4000000000"});
  const std::string list = "ply\nformat binary_big_endian 1.0\nelement vertex 3\n"
                           "property uchar x\nproperty uchar y\nproperty uchar z\n"
                           "element face 1\nproperty list uint int vertex_indices\nend_header\n";
  PlyBytes b(true);
  for (int i = 0; i < 9; ++i) b.put<std::uint8_t>(static_cast<std::uint8_t>(i));
  b.put<std::uint32_t>(0xfffffff0u).put<std::int32_t>(0).put<std::int32_t>(1);
  expect_invalid([&] { read_memory(list + b.str(), st::MeshFormat::Ply); }, {"face", "0"});
}

TEST(MeshIoPly, ErrorsForMissingPartsAndDegenerateFaces) {
  expect_invalid([] { read_memory("ply\nformat ascii 1.0\nend_header\n", st::MeshFormat::Ply); },
                 {"contains no triangles"});
  expect_invalid([] { read_memory("ply\nformat ascii 1.0\nelement vertex 1\n",
                                  st::MeshFormat::Ply); },
                 {"end_header"});
  expect_invalid([] { read_memory("ply\nformat ascii 1.0\nproperty float x\nend_header\n",
                                  st::MeshFormat::Ply); },
                 {"line 3", "before any 'element'"});
  expect_invalid([] { read_memory("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n"
                                  "end_header\n",
                                  st::MeshFormat::Ply); },
                 {"line 4", "'quad'"});
  const std::string degenerate = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 2\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 2 2 3\n";
  st::ReadReport report;
  const st::TriangleMesh m = read_memory(degenerate, st::MeshFormat::Ply, &report);
  EXPECT_EQ(report.input_triangles, 3u);
  EXPECT_EQ(report.degenerate_dropped, 1u);
  ASSERT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.triangles[1], (st::Triangle{0, 2, 3}));
}

// ---- OBJ ----------------------------------------------------------------------------------------

TEST(MeshIoObj, NegativeIndicesSlashesAndQuads) {
  std::string text = "# cube from a test\n# SPACE=RAS\nmtllib cube.mtl\no cube\n";
  for (int v = 0; v < 8; ++v)
    text += "v " + std::to_string(kCube[v][0]) + " " + std::to_string(kCube[v][1]) + "\t" +
            std::to_string(kCube[v][2]) + (v == 3 ? " 1.0" : "") + "\n";
  text += "vt 0 0\nvn 0 0 1\ng faces\nusemtl bone\ns off\n";
  const char* styles[6] = {"%d", "%d/1", "%d//1", "%d/1/1", "-", "%d  "};
  for (int f = 0; f < 6; ++f) {
    text += "f";
    for (int i : kCubeQuads[f]) {
      char corner[32];
      if (f == 4) {
        std::snprintf(corner, sizeof corner, " %d/1", i - 8);  // relative to the 8 vertices
      } else {
        std::snprintf(corner, sizeof corner, styles[f], i + 1);
        std::string c = " " + std::string(corner);
        std::snprintf(corner, sizeof corner, "%s", c.c_str());
      }
      text += corner;
    }
    text += f == 5 ? " # trailing comment\r\n" : "\n";
  }
  const std::string path = temp_path("cube.OBJ");
  write_bytes(path, text);
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  expect_cube(m, report);
  EXPECT_EQ(report.format, st::MeshFormat::Obj);
  EXPECT_EQ(report.header, "cube from a test\nSPACE=RAS");
}

TEST(MeshIoObj, BadNumbersAndIndicesNameTheLine) {
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_invalid([&] { read_memory(vertices + "f 1 2 4\n", st::MeshFormat::Obj); },
                 {"line 4", "vertex 4", "3 vertices"});
  expect_invalid([&] { read_memory(vertices + "f 1 2 -4\n", st::MeshFormat::Obj); },
                 {"line 4", "-4"});
  expect_invalid([&] { read_memory(vertices + "f 0 1 2\n", st::MeshFormat::Obj); },
                 {"line 4", "bad vertex index"});
  expect_invalid([&] { read_memory(vertices + "f 1 x/2 3\n", st::MeshFormat::Obj); },
                 {"line 4", "'x/2'"});
  expect_invalid([&] { read_memory(vertices + "f 1 2\n", st::MeshFormat::Obj); },
                 {"line 4", "needs at least 3"});
  expect_invalid([] { read_memory("v 0 0 0\nv 1 zero 0\n", st::MeshFormat::Obj); },
                 {"line 2", "'zero'"});
  expect_invalid([] { read_memory("v 0 0\n", st::MeshFormat::Obj); }, {"line 1"});
  expect_invalid([] { read_memory("v 0 0 0\nv 1 inf 0\n", st::MeshFormat::Obj); },
                 {"line 2", "vertex 2", "non-finite"});
  expect_invalid([] { read_memory("# only a comment\nv 1 2 3\n", st::MeshFormat::Obj); },
                 {"contains no triangles"});
}

// ---- any format ---------------------------------------------------------------------------------

TEST(MeshIo, EmptyFileThrowsForEveryFormat) {
  for (const char* ext : {".stl", ".ply", ".obj", ".mesh"}) {
    const std::string path = temp_path(std::string("empty") + ext);
    write_bytes(path, "");
    expect_invalid([&] { st::read_mesh(path); }, {path, "contains no triangles"});
  }
  expect_invalid([] { st::read_mesh_from_memory(nullptr, 0, st::MeshFormat::Auto, "nothing"); },
                 {"nothing", "contains no triangles"});
  for (st::MeshFormat format : {st::MeshFormat::Stl, st::MeshFormat::Ply, st::MeshFormat::Obj})
    expect_invalid([&] { read_memory(" \r\n\t\n", format); }, {"contains no triangles"});
}

TEST(MeshIo, MissingFileNamesPathAndReason) {
  const std::string path = temp_path("does_not_exist.stl");
  fs::remove(path);
  expect_invalid([&] { st::read_mesh(path); }, {path, "No such file"});
  expect_invalid([] { st::read_mesh(output_dir().string()); }, {"directory"});
}

TEST(MeshIo, DevicesAndFifosAreRefusedAtOnce) {
  // A device or a FIFO would be read forever (/dev/zero) or block (a FIFO without a writer): refused
  // before anything is opened, naming the path and what it is.
  expect_invalid([] { st::read_mesh("/dev/zero"); }, {"/dev/zero", "character device", "not a regular file"});
  const std::string fifo = temp_path("bone_fifo.stl");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_invalid([&] { st::read_mesh(fifo); }, {fifo, "FIFO"});
  fs::remove(fifo);
}

TEST(MeshIo, FormatFromContentWhenExtensionUnknown) {
  const st::TriangleMesh octa = octahedron();
  const std::string stl_path = temp_path("octa.dat");
  write_bytes(stl_path, stl_binary(octa, "solid looks like text"));
  st::ReadReport report;
  EXPECT_EQ(st::read_mesh(stl_path, &report).face_count(), 8u);
  EXPECT_EQ(report.format, st::MeshFormat::Stl);

  EXPECT_EQ(read_memory(stl_ascii(octa), st::MeshFormat::Auto, &report).face_count(), 8u);
  EXPECT_EQ(report.format, st::MeshFormat::Stl);
  read_memory(cube_ply("binary_big_endian"), st::MeshFormat::Auto, &report);
  EXPECT_EQ(report.format, st::MeshFormat::Ply);
  read_memory("# c\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", st::MeshFormat::Auto, &report);
  EXPECT_EQ(report.format, st::MeshFormat::Obj);

  // Upper-case extension; and an explicit format beats the extension.
  const std::string upper = temp_path("OCTA.STL");
  write_bytes(upper, stl_ascii(octa));
  EXPECT_EQ(st::read_mesh(upper).vertex_count(), 6u);
  const std::string misnamed = temp_path("really_stl.obj");
  write_bytes(misnamed, stl_binary(octa));
  EXPECT_EQ(st::read_mesh(misnamed, &report, st::MeshFormat::Stl).face_count(), 8u);
  expect_invalid([] { read_memory("hello world\n", st::MeshFormat::Auto); }, {"unknown"});
}

TEST(MeshIo, TextFormatsTolerateByteOrderMarkAndNulPadding) {
  const std::string bom = "\xEF\xBB\xBF";
  // An OBJ whose first statement is a vertex: skipping it would shift every index.
  st::ReadReport report;
  const st::TriangleMesh obj =
      read_memory(bom + "v 5 0 0\nv 0 5 0\nv 0 0 5\nf 1 2 3\n", st::MeshFormat::Auto, &report);
  EXPECT_EQ(report.format, st::MeshFormat::Obj);
  ASSERT_EQ(obj.vertex_count(), 3u);
  EXPECT_EQ(obj.positions[obj.triangles[0][0]], st::Vec3(5, 0, 0));

  const std::string ascii = stl_ascii(octahedron());
  EXPECT_EQ(read_memory(bom + ascii, st::MeshFormat::Auto, &report).face_count(), 8u);
  EXPECT_EQ(report.format, st::MeshFormat::Stl);
  EXPECT_EQ(read_memory(ascii + std::string(7, '\0'), st::MeshFormat::Stl).face_count(), 8u);

  const st::TriangleMesh ply =
      read_memory(bom + cube_ply("binary_little_endian"), st::MeshFormat::Auto, &report);
  EXPECT_EQ(report.format, st::MeshFormat::Ply);
  expect_cube(ply, report);
}

TEST(MeshIo, GzipFileIsReadAsTheFileItHolds) {
  // gzip of an ASCII STL with two triangles sharing an edge (made with Python's gzip, mtime 0).
  static const char kGz[] =
    "\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\x03\x2b\xce\xcf\xc9\x4c\x51\x48\xaf\xe2\x4a\x4b\x4c"
    "\x4e\x2d\x51\xc8\xcb\x2f\xca\x4d\xcc\x51\x30\x00\x42\x43\xae\xfc\xd2\x92\xd4\x22\x85\x9c"
    "\xfc\xfc\x02\xae\xb2\xd4\xa2\x92\xd4\x0a\xb0\xb8\x01\x8c\x63\x88\xcc\x31\x00\x71\xb9\x52"
    "\xf3\x52\xc0\xca\x81\x34\xd8\x3c\xe2\x4c\x35\x44\x35\xd5\x90\xa0\xa9\x40\x46\x31\xcc\xdd"
    "\x00\xa3\x03\x71\x01\xc1\x00\x00\x00";
  const std::string gz(kGz, sizeof kGz - 1);
  const std::string path = temp_path("square.stl.gz");
  write_bytes(path, gz);
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  EXPECT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(report.header, "solid gz");

  // Corrupt gzip data is refused with the path.
  std::string corrupt = gz;
  corrupt.resize(40);
  write_bytes(path, corrupt);
  expect_invalid([&] { st::read_mesh(path); }, {path, "gzip"});

  // A binary STL whose free-text header starts with the gzip magic is still a binary STL.
  const std::string stl_path = temp_path("gzip_magic_header.stl");
  write_bytes(stl_path, stl_binary(octahedron(), "\x1f\x8b header"));
  EXPECT_EQ(st::read_mesh(stl_path).face_count(), 8u);
}

// ---- write_stl ----------------------------------------------------------------------------------

TEST(MeshIoWrite, RoundTripKeepsGeometryAndWritesUnitNormals) {
  const st::TriangleMesh octa = octahedron(3.1, st::Vec3(100.1, -250.3, 17.7));
  const std::string path = temp_path("round_trip.stl");
  st::write_stl(octa, path, "round trip SPACE=RAS");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const std::string bytes = read_bytes(path);
  ASSERT_EQ(bytes.size(), 84u + 50u * 8u);

  st::ReadReport report;
  const st::TriangleMesh back = st::read_mesh(path, &report);
  EXPECT_EQ(report.header, "round trip SPACE=RAS");
  EXPECT_EQ(back.vertex_count(), 6u);
  EXPECT_EQ(back.face_count(), 8u);
  EXPECT_TRUE(closed_and_oriented(back));
  expect_same_corners(octa, back, 1e-5 * 260);  // float32 rounding
  EXPECT_NEAR(signed_volume_of(back), signed_volume_of(octa), 1e-2);

  for (std::size_t f = 0; f < 8; ++f) {
    float n[3];
    std::memcpy(n, bytes.data() + 84 + 50 * f, 12);  // little-endian host assumed by the test
    const st::Vec3 normal(n[0], n[1], n[2]);
    const st::Triangle& t = octa.triangles[f];
    const st::Vec3 expected = (octa.positions[t[1]] - octa.positions[t[0]])
                                  .cross(octa.positions[t[2]] - octa.positions[t[0]])
                                  .normalized();
    EXPECT_NEAR((normal - expected).norm(), 0.0, 1e-5) << "triangle " << f;
  }
}

TEST(MeshIoWrite, ReplacesAnExistingFile) {
  const std::string path = temp_path("replace.stl");
  write_bytes(path, "old contents");
  st::write_stl(octahedron(), path);
  EXPECT_EQ(st::read_mesh(path).face_count(), 8u);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(MeshIoWrite, UnwritablePathThrowsAndLeavesNothing) {
  const std::string missing_dir = temp_path("no_such_dir/out.stl");
  fs::remove_all(output_dir() / "no_such_dir");
  expect_invalid([&] { st::write_stl(octahedron(), missing_dir); },
                 {missing_dir, "No such file"});
  EXPECT_FALSE(fs::exists(missing_dir));
  EXPECT_FALSE(fs::exists(missing_dir + ".tmp"));

  // The target is a directory: the temporary file is written, the rename fails, and it is removed.
  const std::string dir = temp_path("a_directory.stl");
  fs::create_directories(dir);
  expect_invalid([&] { st::write_stl(octahedron(), dir); }, {dir});
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_FALSE(fs::exists(dir + ".tmp"));
}

TEST(MeshIoWrite, RefusesNonFiniteAndBadIndices) {
  const std::string path = temp_path("refused.stl");
  fs::remove(path);
  st::TriangleMesh bad = octahedron();
  bad.positions[4].y() = std::numeric_limits<double>::quiet_NaN();
  expect_invalid([&] { st::write_stl(bad, path); }, {path, "vertex 4", "non-finite"});
  bad.positions[4].y() = 1e300;  // beyond float32
  expect_invalid([&] { st::write_stl(bad, path); }, {"vertex 4"});
  bad = octahedron();
  bad.triangles[2][0] = 17;
  expect_invalid([&] { st::write_stl(bad, path); }, {"triangle 2", "vertex 17"});
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

// ---- the example meshes -------------------------------------------------------------------------

TEST(MeshIoExamples, Tibia) {
  const std::string path = std::string(ST_EXAMPLES_DIR) + "/meshes/tibia.stl.gz";
  ASSERT_TRUE(fs::exists(path)) << path;
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  EXPECT_EQ(report.input_triangles, 60362u);
  EXPECT_EQ(m.face_count() + report.degenerate_dropped, 60362u);
  EXPECT_EQ(m.vertex_count(), 30183u);
  EXPECT_TRUE(closed_and_oriented(m));  // watertight genus 0
  EXPECT_GT(signed_volume_of(m), 0.0);
}

TEST(MeshIoExamples, MaxillaDentitionCrop) {
  const std::string path = std::string(ST_EXAMPLES_DIR) + "/meshes/maxilla_dentition_ct_crop.stl.gz";
  ASSERT_TRUE(fs::exists(path)) << path;
  st::ReadReport report;
  const st::TriangleMesh m = st::read_mesh(path, &report);
  EXPECT_EQ(report.input_triangles, 119825u);
  EXPECT_EQ(m.face_count(), 119825u - report.degenerate_dropped);
  EXPECT_EQ(m.vertex_count(), 60918u);
  EXPECT_NE(report.header.find("InVesalius"), std::string::npos);
}

} // namespace
