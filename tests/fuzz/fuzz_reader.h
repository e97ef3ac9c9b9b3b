#pragma once
// Shared body of the reader fuzz targets: read_mesh_from_memory on arbitrary bytes in one format,
// then with format detection. st::InvalidInput is the only allowed way to refuse an input; any other
// exception, a crash, a sanitizer report, a hang or a returned mesh that breaks the reader's
// guarantees is a bug.

#include "st/core/errors.h"
#include "st/io/mesh_io.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace st::fuzz {

/// What every returned mesh guarantees: indices in range, no repeated corner, finite coordinates,
/// a consistent report.
inline void check_result(const TriangleMesh& mesh, const ReadReport& report) {
  bool ok = !mesh.triangles.empty() && report.format != MeshFormat::Auto &&
            report.input_triangles == mesh.triangles.size() + report.degenerate_dropped;
  for (const Vec3& p : mesh.positions) ok = ok && p.allFinite();
  for (const Triangle& t : mesh.triangles)
    ok = ok && t[0] < mesh.vertex_count() && t[1] < mesh.vertex_count() && t[2] < mesh.vertex_count() && t[0] != t[1] &&
         t[1] != t[2] && t[0] != t[2];
  if (!ok) std::abort();
}

inline void read_as(const std::uint8_t* data, std::size_t size, MeshFormat format, const char* name) {
  try {
    ReadReport report;
    const TriangleMesh mesh = read_mesh_from_memory(reinterpret_cast<const char*>(data), size, format, name, &report);
    check_result(mesh, report);
  } catch (const InvalidInput&) {
    // A refused input: fine.
  }
}

} // namespace st::fuzz
