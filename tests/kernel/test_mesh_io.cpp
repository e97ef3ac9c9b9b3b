// The PLY and OBJ readers, format detection, files, the STL writer, the example meshes.

#include "mesh_io_fixtures.h"

namespace {

using namespace mesh_io_test;

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
  expect_invalid([&] { read_memory(text, st::MeshFormat::Ply); }, {"face 5", "vertex 8", "only 8 vertices", "line"});
  std::string binary = cube_ply("binary_little_endian");
  // The last index of the first face (0 3 2 1): make it 99.
  const std::size_t body = binary.find("end_header\n") + 11;
  const std::size_t first_face = body + 4 + 1 + 4 + 4 + 8 * (4 + 1 + 8 + 1 + 4 + 4 + 4 + 4);
  binary[first_face + 2 + 12] = 99;
  expect_invalid([&] { read_memory(binary, st::MeshFormat::Ply); }, {"face 0", "vertex 99", "byte offset"});
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
  expect_invalid([&] { read_memory(head + std::string(24, '\0'), st::MeshFormat::Ply); }, {"vertex", "4000000000"});
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
  expect_invalid([] { read_memory("ply\nformat ascii 1.0\nelement vertex 1\n", st::MeshFormat::Ply); }, {"end_header"});
  expect_invalid([] { read_memory("ply\nformat ascii 1.0\nproperty float x\nend_header\n", st::MeshFormat::Ply); },
                 {"line 3", "before any 'element'"});
  expect_invalid(
      [] {
        read_memory("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n"
                    "end_header\n",
                    st::MeshFormat::Ply);
      },
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
        std::snprintf(corner, sizeof corner, " %d/1", i - 8); // relative to the 8 vertices
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
  expect_invalid([&] { read_memory(vertices + "f 1 2 -4\n", st::MeshFormat::Obj); }, {"line 4", "-4"});
  expect_invalid([&] { read_memory(vertices + "f 0 1 2\n", st::MeshFormat::Obj); }, {"line 4", "bad vertex index"});
  expect_invalid([&] { read_memory(vertices + "f 1 x/2 3\n", st::MeshFormat::Obj); }, {"line 4", "'x/2'"});
  expect_invalid([&] { read_memory(vertices + "f 1 2\n", st::MeshFormat::Obj); }, {"line 4", "needs at least 3"});
  expect_invalid([] { read_memory("v 0 0 0\nv 1 zero 0\n", st::MeshFormat::Obj); }, {"line 2", "'zero'"});
  expect_invalid([] { read_memory("v 0 0\n", st::MeshFormat::Obj); }, {"line 1"});
  expect_invalid([] { read_memory("v 0 0 0\nv 1 inf 0\n", st::MeshFormat::Obj); },
                 {"line 2", "vertex 2", "non-finite"});
  expect_invalid([] { read_memory("# only a comment\nv 1 2 3\n", st::MeshFormat::Obj); }, {"contains no triangles"});
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
  const st::TriangleMesh obj = read_memory(bom + "v 5 0 0\nv 0 5 0\nv 0 0 5\nf 1 2 3\n", st::MeshFormat::Auto, &report);
  EXPECT_EQ(report.format, st::MeshFormat::Obj);
  ASSERT_EQ(obj.vertex_count(), 3u);
  EXPECT_EQ(obj.positions[obj.triangles[0][0]], st::Vec3(5, 0, 0));

  const std::string ascii = stl_ascii(octahedron());
  EXPECT_EQ(read_memory(bom + ascii, st::MeshFormat::Auto, &report).face_count(), 8u);
  EXPECT_EQ(report.format, st::MeshFormat::Stl);
  EXPECT_EQ(read_memory(ascii + std::string(7, '\0'), st::MeshFormat::Stl).face_count(), 8u);

  const st::TriangleMesh ply = read_memory(bom + cube_ply("binary_little_endian"), st::MeshFormat::Auto, &report);
  EXPECT_EQ(report.format, st::MeshFormat::Ply);
  expect_cube(ply, report);
}

TEST(MeshIo, GzipFileIsReadAsTheFileItHolds) {
  // gzip of an ASCII STL with two triangles sharing an edge (made with Python's gzip, mtime 0).
  static const char kGz[] = "\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\x03\x2b\xce\xcf\xc9\x4c\x51\x48\xaf\xe2\x4a\x4b\x4c"
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
  expect_same_corners(octa, back, 1e-5 * 260); // float32 rounding
  EXPECT_NEAR(signed_volume_of(back), signed_volume_of(octa), 1e-2);

  for (std::size_t f = 0; f < 8; ++f) {
    float n[3];
    std::memcpy(n, bytes.data() + 84 + 50 * f, 12); // little-endian host assumed by the test
    const st::Vec3 normal(n[0], n[1], n[2]);
    const st::Triangle& t = octa.triangles[f];
    const st::Vec3 expected =
        (octa.positions[t[1]] - octa.positions[t[0]]).cross(octa.positions[t[2]] - octa.positions[t[0]]).normalized();
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
  expect_invalid([&] { st::write_stl(octahedron(), missing_dir); }, {missing_dir, "No such file"});
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
  bad.positions[4].y() = 1e300; // beyond float32
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
  EXPECT_TRUE(closed_and_oriented(m)); // watertight genus 0
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
