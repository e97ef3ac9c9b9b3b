#pragma once
// Fixtures of the mesh reader and writer tests: meshes built in code, the same meshes as STL, PLY and
// OBJ bytes, and checks of what a reader returns.

#include "st/io/mesh_io.h"

#include "st/core/errors.h"

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

namespace mesh_io_test {

namespace fs = std::filesystem;

// ---- fixtures built in code ---------------------------------------------------------------------

inline fs::path output_dir() {
  const fs::path dir = fs::path(ST_TEST_OUTPUT_DIR) / "mesh_io";
  fs::create_directories(dir);
  return dir;
}

inline std::string temp_path(const std::string& file) { return (output_dir() / file).string(); }

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Regular octahedron with vertices at +-r on the axes: 6 vertices, 8 outward triangles.
inline st::TriangleMesh octahedron(double r = 1.0, st::Vec3 c = st::Vec3::Zero()) {
  st::TriangleMesh m;
  m.positions = {c + st::Vec3(r, 0, 0),  c + st::Vec3(-r, 0, 0), c + st::Vec3(0, r, 0),
                 c + st::Vec3(0, -r, 0), c + st::Vec3(0, 0, r),  c + st::Vec3(0, 0, -r)};
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        const st::Index x = sx, y = 2 + sy, z = 4 + sz;
        if ((sx + sy + sz) % 2 == 0) m.triangles.push_back({x, y, z});
        else m.triangles.push_back({x, z, y});
      }
  return m;
}

/// Unit cube corners, numbered x + 2y... as in the PLY/OBJ fixtures below.
const double kCube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
/// Its six faces as outward counter-clockwise quads.
const int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};

/// Every edge is used by exactly two triangles, once in each direction (closed, oriented).
inline bool closed_and_oriented(const st::TriangleMesh& m) {
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

inline double signed_volume_of(const st::TriangleMesh& m) {
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
inline void expect_same_corners(const st::TriangleMesh& expected, const st::TriangleMesh& actual, double tol = 0.0) {
  ASSERT_EQ(expected.triangles.size(), actual.triangles.size());
  for (std::size_t f = 0; f < expected.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const st::Vec3& e = expected.positions[expected.triangles[f][k]];
      const st::Vec3& a = actual.positions[actual.triangles[f][k]];
      EXPECT_LE((e - a).cwiseAbs().maxCoeff(), tol) << "triangle " << f << " corner " << k;
    }
}

/// Runs `read` and expects InvalidInput whose message holds every one of `parts`.
inline void expect_invalid(const std::function<void()>& read, std::initializer_list<std::string> parts) {
  try {
    read();
    ADD_FAILURE() << "expected st::InvalidInput";
  } catch (const st::InvalidInput& e) {
    const std::string message = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "message '" << message << "' lacks '" << part << "'";
  }
}

inline void put_f32(std::string& out, float v) {
  const auto bits = std::bit_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xff);
}

inline void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

/// Binary STL bytes written by the test itself (not by write_stl), normals left zero.
inline std::string stl_binary(const st::TriangleMesh& m, const std::string& header = "test") {
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

inline std::string stl_ascii(const st::TriangleMesh& m, const std::string& name = "octa") {
  std::ostringstream out;
  out.precision(9);
  out << "solid " << name << "\n";
  for (const st::Triangle& t : m.triangles) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (st::Index v : t)
      out << "      vertex " << m.positions[v].x() << " " << m.positions[v].y() << " " << m.positions[v].z() << "\n";
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
inline std::string cube_ply(const std::string& format) {
  std::string header = "ply\nformat " + format + " 1.0\ncomment made by test SPACE=RAS\n";
  header += "element camera 1\nproperty float view_px\nproperty list uchar int tags\n";
  header += "element vertex 8\nproperty float x\nproperty uchar red\nproperty double y\n"
            "property list uchar float extra\nproperty int z\nproperty float32 confidence\n";
  header += "element face 6\nproperty uchar intensity\nproperty list uchar uint vertex_indices\n"
            "property float64 quality\n";
  header += "element edge 2\nproperty int vertex1\nproperty int vertex2\n";
  header += "element nothing 4000000000\n"; // no properties: takes no bytes
  header += "end_header\n";
  if (format == "ascii") {
    std::string body = "7.5 2 11 22\n";
    for (int v = 0; v < 8; ++v)
      body += std::to_string(kCube[v][0]) + " 200 " + std::to_string(kCube[v][1]) + " 2 0.5 " + "1.5 " +
              std::to_string(static_cast<int>(kCube[v][2])) + " 0.25\n";
    for (const auto& q : kCubeQuads)
      body += "9 4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
              std::to_string(q[3]) + " 0.5\n";
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

inline void expect_cube(const st::TriangleMesh& m, const st::ReadReport& r) {
  ASSERT_EQ(m.vertex_count(), 8u);
  EXPECT_EQ(m.face_count(), 12u); // 6 quads, fan-triangulated
  EXPECT_EQ(r.input_triangles, 12u);
  EXPECT_EQ(r.degenerate_dropped, 0u);
  for (int v = 0; v < 8; ++v)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(m.positions[v][d], kCube[v][d]) << v << " " << d;
  EXPECT_TRUE(closed_and_oriented(m));
  EXPECT_NEAR(signed_volume_of(m), 1.0, 1e-12);
}

inline st::TriangleMesh read_memory(const std::string& bytes, st::MeshFormat format, st::ReadReport* report = nullptr) {
  return st::read_mesh_from_memory(bytes.data(), bytes.size(), format, "memory", report);
}

// ---- STL ----------------------------------------------------------------------------------------

} // namespace mesh_io_test
