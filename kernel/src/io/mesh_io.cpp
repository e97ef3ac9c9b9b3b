#include "st/io/mesh_io.h"

#include "mesh_reader.h"
#include "detail/gzip.h"
#include "detail/input_file.h"
#include "st/core/tolerances.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string_view>
#include <system_error>
#include <vector>

namespace st {

using namespace mesh_reader;

namespace {

// ---- format detection ---------------------------------------------------------------------------

bool starts_with_ply_magic(const char* data, std::size_t size) {
  const std::size_t bom = bom_length(data, size);
  data += bom;
  size -= bom;
  return size >= 4 && std::memcmp(data, "ply", 3) == 0 && (data[3] == '\n' || data[3] == '\r');
}

bool looks_like_obj(const char* data, std::size_t size) {
  const std::size_t n = std::min<std::size_t>(size, 1 << 16);
  if (looks_binary(data, n)) return false;
  TextCursor in(data + bom_length(data, n), data + n);
  const std::string_view first = in.token();
  static constexpr std::string_view kStatements[] = {"v", "vt", "vn", "vp", "f",      "g",
                                                     "o", "s",  "l",  "p",  "mtllib", "usemtl"};
  if (!first.empty() && first.front() == '#') return true;
  return std::find(std::begin(kStatements), std::end(kStatements), first) != std::end(kStatements);
}

MeshFormat sniff_format(const char* data, std::size_t size, const std::string& name) {
  if (is_blank(data, size)) fail_blank(name, size);
  if (starts_with_ply_magic(data, size)) return MeshFormat::Ply;
  if (size >= kStlHeaderBytes && kStlHeaderBytes + kStlTriangleBytes * std::uint64_t{load_u32_le(data + 80)} == size)
    return MeshFormat::Stl;
  if (starts_with_solid(data, size)) return MeshFormat::Stl;
  if (looks_like_obj(data, size)) return MeshFormat::Obj;
  // A binary file without any magic: most likely a damaged binary STL, say so.
  if (looks_binary(data, size)) return MeshFormat::Stl;
  fail(name, "unknown mesh format (not STL, PLY or OBJ)");
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = to_lower(c);
  return ext;
}

// ---- files --------------------------------------------------------------------------------------

struct FileBytes {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
};

/// The whole file in memory, read in one go. Only regular files under the size limit are read
/// (detail/input_file.h): a device or a FIFO would be read forever or block.
FileBytes read_file(const std::string& path) {
  const std::uintmax_t size = detail::check_input_file(path, "mesh file", tol::kMaxMeshFileBytes);
  errno = 0;
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) fail(path, "cannot open: " + system_reason(errno));
  FileBytes bytes;
  bytes.data = std::make_unique_for_overwrite<char[]>(static_cast<std::size_t>(size) + 1);
  bytes.size = std::fread(bytes.data.get(), 1, static_cast<std::size_t>(size), file.get());
  if (std::ferror(file.get())) fail(path, "cannot read: " + system_reason(errno));
  if (bytes.size != size) fail(path, "cannot read: the file changed size while being read");
  return bytes;
}

} // namespace

TriangleMesh read_mesh_from_memory(const char* data, std::size_t size, MeshFormat format, const std::string& name,
                                   ReadReport* report) {
  static const char kEmpty = 0;
  if (!data) {
    if (size != 0) fail(name, "no data (null pointer)");
    data = &kEmpty;
  }
  if (format == MeshFormat::Auto) format = sniff_format(data, size, name);
  switch (format) {
  case MeshFormat::Ply: return read_ply(data, size, name, report);
  case MeshFormat::Obj: return read_obj(data, size, name, report);
  case MeshFormat::Stl:
  case MeshFormat::Auto: break;
  }
  return read_stl(data, size, name, report);
}

TriangleMesh read_mesh(const std::string& path, ReadReport* report, MeshFormat format) {
  const FileBytes bytes = read_file(path);
  // A gzip-compressed file (e.g. bone.stl.gz) is read as the file it holds. A binary STL header
  // is free text and may start with the gzip magic too, so a file of exact binary STL size is
  // taken as STL.
  const bool exact_binary_stl =
      bytes.size >= kStlHeaderBytes &&
      kStlHeaderBytes + kStlTriangleBytes * std::uint64_t{load_u32_le(bytes.data.get() + 80)} == bytes.size;
  const bool gzipped = !exact_binary_stl && detail::is_gzip(bytes.data.get(), bytes.size);
  std::string plain_name = path;
  std::vector<char> inflated;
  if (gzipped) {
    inflated = detail::gunzip(bytes.data.get(), bytes.size, path);
    if (lower_extension(plain_name) == ".gz") plain_name.resize(plain_name.size() - 3);
  }
  if (format == MeshFormat::Auto) {
    const std::string ext = lower_extension(plain_name);
    if (ext == ".stl") format = MeshFormat::Stl;
    else if (ext == ".ply") format = MeshFormat::Ply;
    else if (ext == ".obj") format = MeshFormat::Obj;
  }
  if (gzipped) return read_mesh_from_memory(inflated.data(), inflated.size(), format, path, report);
  return read_mesh_from_memory(bytes.data.get(), bytes.size, format, path, report);
}

} // namespace st
