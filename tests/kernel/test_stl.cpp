// The STL reader (binary and ASCII).

#include "mesh_io_fixtures.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <random>

namespace {

using namespace mesh_io_test;

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
  const std::string text = "  SOLID first part\r\n"
                           "FACET NORMAL nan nan nan\r\n\tOUTER LOOP\r\n"
                           "\t\tVERTEX 0 0 0\r\n vertex\t1e0   0 0\r\n vertex +0 1 -0\r\n ENDLOOP\r\nENDFACET\r\n"
                           "endsolid first part\r\n"
                           "solid second\n facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 0 0 1 "
                           "endloop endfacet\nendsolid";
  st::ReadReport report;
  const st::TriangleMesh m = read_memory(text, st::MeshFormat::Stl, &report);
  EXPECT_EQ(m.face_count(), 2u);
  EXPECT_EQ(m.vertex_count(), 4u); // (0,0,0) and (1,0,0) shared, -0 welded with 0
  EXPECT_EQ(report.header, "SOLID first part\nsolid second");
}

TEST(MeshIoStl, AsciiErrorsNameTheLine) {
  expect_invalid(
      [] {
        read_memory("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 oops 0\n", st::MeshFormat::Stl);
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
  expect_invalid([&] { st::read_mesh(path); }, {path, "truncated", "8 triangles", "needs 484 bytes", "has 474 bytes"});
  // The same with a header starting with "solid": still reported as a truncated binary file.
  std::string solid = stl_binary(octahedron(), "solid name");
  solid.resize(solid.size() - 50);
  expect_invalid([&] { read_memory(solid, st::MeshFormat::Stl); }, {"truncated", "8 triangles"});
  // Shorter than the header.
  expect_invalid([] { read_memory(std::string(40, '\x01'), st::MeshFormat::Stl); }, {"truncated", "40 bytes"});
}

TEST(MeshIoStl, ZeroTrianglesThrows) {
  expect_invalid([] { read_memory(stl_binary(st::TriangleMesh{}), st::MeshFormat::Stl); }, {"contains no triangles"});
  expect_invalid([] { read_memory("solid empty\nendsolid empty\n", st::MeshFormat::Stl); }, {"contains no triangles"});
}

TEST(MeshIoStl, NonFiniteCoordinateNamesTriangleAndCorner) {
  st::TriangleMesh octa = octahedron();
  octa.positions.push_back(st::Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  octa.triangles[5][1] = 6;
  expect_invalid([&] { read_memory(stl_binary(octa), st::MeshFormat::Stl); }, {"triangle 5", "corner 1", "non-finite"});
  octa.positions[6] = st::Vec3(0, std::numeric_limits<double>::infinity(), 0);
  expect_invalid([&] { read_memory(stl_binary(octa), st::MeshFormat::Stl); }, {"triangle 5", "corner 1", "non-finite"});
  // ASCII: the line too; values beyond float32 count as non-finite.
  std::string text = stl_ascii(octahedron());
  text.replace(text.find("vertex 1 0 0"), 12, "vertex 1e39 0 0");
  expect_invalid([&] { read_memory(text, st::MeshFormat::Stl); }, {"line 4", "facet 0", "corner 0", "non-finite"});
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
  m.positions.push_back(m.positions[1]); // welds with vertex 1
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
  expect_invalid([&] { read_memory(stl_binary(all_bad), st::MeshFormat::Stl); }, {"all 2 triangles are degenerate"});
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
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(m.face_count(), 2u * n);
  EXPECT_EQ(m.vertex_count(), 2u * (n + 1));
  EXPECT_LT(seconds, 5.0); // about 0.02 s in a release build
}

// A file large enough to be read in ranges on several threads (ranges of at least 2^17 triangles):
// the mesh must be the one a single pass gives. Reference: vertices numbered in order of first
// appearance over the triangles in file order by a std::map of the corners' float32 bits (-0.0 as
// 0.0), degenerate triangles dropped after welding.
TEST(MeshIoStl, LargeBinaryReadInRangesIsTheSinglePassMesh) {
  const int side = 400; // a grid of 400 x 400 squares: 320k triangles, shuffled
  st::TriangleMesh grid;
  for (int j = 0; j <= side; ++j)
    for (int i = 0; i <= side; ++i)
      grid.positions.emplace_back(0.25 * i, 0.25 * j, std::sin(0.05 * i) * std::cos(0.03 * j));
  auto at = [&](int i, int j) { return static_cast<st::Index>(j * (side + 1) + i); };
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      grid.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      grid.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  std::mt19937 rng(7);
  std::shuffle(grid.triangles.begin(), grid.triangles.end(), rng);
  const std::size_t n = grid.triangles.size();
  // -0.0 in the second half where 0.0 came first; degenerate triangles in both halves; a vertex
  // first seen in the last triangles.
  grid.positions.push_back(st::Vec3(-0.0, -0.0, std::sin(0.0) * std::cos(0.0)));
  const st::Index negative_zero = grid.vertex_count() - 1;
  grid.triangles[3 * n / 4] = {negative_zero, at(1, 0), at(1, 1)};
  grid.triangles[n / 3] = {at(5, 5), at(5, 5), at(6, 6)};
  grid.triangles[n - 2] = {at(7, 7), at(8, 8), at(7, 7)};
  grid.positions.emplace_back(-3.0, -3.0, 1.0);
  grid.triangles.push_back({grid.vertex_count() - 1, at(0, 0), at(1, 0)});
  const std::string bytes = stl_binary(grid);

  auto bits_of = [](const st::Vec3& p) {
    std::array<std::uint32_t, 3> b{};
    for (int d = 0; d < 3; ++d) {
      b[static_cast<std::size_t>(d)] = std::bit_cast<std::uint32_t>(static_cast<float>(p[d]));
      if (b[static_cast<std::size_t>(d)] == 0x80000000u) b[static_cast<std::size_t>(d)] = 0;
    }
    return b;
  };
  std::map<std::array<std::uint32_t, 3>, st::Index> ids;
  st::TriangleMesh expected;
  std::size_t degenerate = 0;
  for (const st::Triangle& t : grid.triangles) {
    st::Triangle u{};
    for (int k = 0; k < 3; ++k) {
      const auto b = bits_of(grid.positions[t[static_cast<std::size_t>(k)]]);
      const auto [it, fresh] = ids.emplace(b, static_cast<st::Index>(expected.positions.size()));
      if (fresh)
        expected.positions.emplace_back(std::bit_cast<float>(b[0]), std::bit_cast<float>(b[1]),
                                        std::bit_cast<float>(b[2]));
      u[static_cast<std::size_t>(k)] = it->second;
    }
    if (u[0] == u[1] || u[1] == u[2] || u[0] == u[2]) ++degenerate;
    else expected.triangles.push_back(u);
  }
  ASSERT_EQ(degenerate, 2u);

  st::ReadReport report;
  const st::TriangleMesh m = read_memory(bytes, st::MeshFormat::Stl, &report);
  EXPECT_EQ(m.positions, expected.positions);
  EXPECT_EQ(m.triangles, expected.triangles);
  EXPECT_EQ(report.input_triangles, grid.triangles.size());
  EXPECT_EQ(report.degenerate_dropped, degenerate);
  EXPECT_EQ(report.merged_vertices, 3 * grid.triangles.size() - expected.positions.size());

  // A corner that is not finite is named as one pass names it: the first in the file.
  st::TriangleMesh bad = grid;
  bad.positions.push_back(st::Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  const st::Index nan = bad.vertex_count() - 1;
  bad.triangles[n - 5][2] = nan;
  expect_invalid([&] { read_memory(stl_binary(bad), st::MeshFormat::Stl); },
                 {"triangle " + std::to_string(n - 5) + " corner 2", "non-finite"});
  bad.triangles[n / 5][0] = nan;
  expect_invalid([&] { read_memory(stl_binary(bad), st::MeshFormat::Stl); },
                 {"triangle " + std::to_string(n / 5) + " corner 0", "non-finite"});
}

// ---- PLY ----------------------------------------------------------------------------------------

} // namespace
