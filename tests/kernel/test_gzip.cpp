// Compressed mesh files: read as the file they hold; truncated or corrupt ones are refused clearly.

#include "helpers.h"

#include "st/core/errors.h"
#include "st/io/mesh_io.h"

#include <fstream>
#include <iterator>

using namespace st;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

std::string expect_refused(const std::string& path) {
  try {
    read_mesh(path);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was accepted";
  return {};
}

} // namespace

TEST(Gzip, CompressedStlReadsLikeThePlainFile) {
  const TriangleMesh m = read_mesh(test::examples_dir() + "/meshes/vertebrae_lumbar_L2-L5_ssm_mean.stl.gz");
  EXPECT_EQ(m.face_count(), 130956u);
  EXPECT_EQ(m.vertex_count(), 65478u);
}

TEST(Gzip, TruncatedFileIsRefusedNamingIt) {
  const std::string bytes = slurp(test::examples_dir() + "/meshes/tibia.stl.gz");
  const std::string path = test::output_dir() + "/truncated.stl.gz";
  spit(path, bytes.substr(0, bytes.size() / 2));
  const std::string message = expect_refused(path);
  EXPECT_NE(message.find("truncated.stl.gz"), std::string::npos) << message;
}

TEST(Gzip, CorruptDataIsRefused) {
  std::string bytes = slurp(test::examples_dir() + "/meshes/tibia.stl.gz");
  for (std::size_t i = 100; i < 400; ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  const std::string path = test::output_dir() + "/corrupt.stl.gz";
  spit(path, bytes);
  const std::string message = expect_refused(path);
  EXPECT_NE(message.find("corrupt.stl.gz"), std::string::npos) << message;
}

TEST(Gzip, EmptyArchiveHoldsNoTriangles) {
  const std::string path = test::output_dir() + "/empty.stl.gz";
  // gzip of zero bytes.
  spit(path, std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03\x03\x00\x00\x00\x00\x00\x00\x00\x00\x00", 20));
  const std::string message = expect_refused(path);
  EXPECT_NE(message.find("no triangles"), std::string::npos) << message;
}
