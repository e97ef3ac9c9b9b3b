// libFuzzer target: read_mesh_from_memory on arbitrary bytes as STL, then with format detection.
// st::InvalidInput is the only allowed way to refuse an input; any other exception, a crash, a
// sanitizer report, a hang or a returned mesh that breaks the reader's guarantees is a bug.

#include "st/errors.h"
#include "st/mesh_io.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace {

/// What every returned mesh guarantees: indices in range, no repeated corner, finite coordinates,
/// a consistent report.
void check_result(const st::TriangleMesh& mesh, const st::ReadReport& report) {
  bool ok = !mesh.triangles.empty() && report.format != st::MeshFormat::Auto &&
            report.input_triangles == mesh.triangles.size() + report.degenerate_dropped;
  for (const st::Vec3& p : mesh.positions) ok = ok && p.allFinite();
  for (const st::Triangle& t : mesh.triangles)
    ok = ok && t[0] < mesh.vertex_count() && t[1] < mesh.vertex_count() &&
         t[2] < mesh.vertex_count() && t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
  if (!ok) std::abort();
}

void read_as(const std::uint8_t* data, std::size_t size, st::MeshFormat format) {
  try {
    st::ReadReport report;
    const st::TriangleMesh mesh = st::read_mesh_from_memory(
        reinterpret_cast<const char*>(data), size, format, "fuzz.stl", &report);
    check_result(mesh, report);
  } catch (const st::InvalidInput&) {
    // A refused input: fine.
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  read_as(data, size, st::MeshFormat::Stl);
  read_as(data, size, st::MeshFormat::Auto);
  return 0;
}
