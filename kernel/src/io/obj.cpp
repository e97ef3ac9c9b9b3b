// Wavefront OBJ: v and f statements (polygons fanned into triangles), negative indices.

#include "mesh_reader.h"

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

namespace st::mesh_reader {
namespace {

// ---- OBJ ----------------------------------------------------------------------------------------

} // namespace

TriangleMesh read_obj(const char* data, std::size_t size, const std::string& name, ReadReport* report) {
  MeshBuilder builder(name, MeshFormat::Obj);
  std::vector<Index> polygon;
  std::size_t pos = bom_length(data, size);
  std::size_t line_no = 0;
  while (pos < size) {
    const char* nl = static_cast<const char*>(std::memchr(data + pos, '\n', size - pos));
    const std::size_t line_end = nl ? static_cast<std::size_t>(nl - data) : size;
    std::string_view line(data + pos, line_end - pos);
    pos = line_end + 1;
    ++line_no;

    line = trim(line);
    if (line.empty()) continue;
    if (line.front() == '#') {
      builder.add_header_line(trim(line.substr(1)));
      continue;
    }
    line = line.substr(0, line.find('#'));
    TextCursor words(line.data(), line.data() + line.size());
    const std::string_view key = words.token();
    const std::string at = "line " + std::to_string(line_no) + ": ";
    if (key == "v") {
      double xyz[3];
      for (double& c : xyz) {
        const std::string_view tok = words.token();
        if (!parse_real(tok, c))
          fail(name,
               at + "expected 3 vertex coordinates, found " + (tok.empty() ? std::string("end of line") : quoted(tok)));
      }
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
        fail(name, at + "vertex " + std::to_string(builder.mesh().positions.size() + 1) +
                       " (counting from 1, as OBJ does) has a non-finite coordinate " + triple(xyz[0], xyz[1], xyz[2]));
      builder.add_vertex(Vec3(xyz[0], xyz[1], xyz[2])); // an optional w (or colour) is ignored
    } else if (key == "f") {
      polygon.clear();
      const auto defined = static_cast<std::int64_t>(builder.mesh().positions.size());
      for (std::string_view tok = words.token(); !tok.empty(); tok = words.token()) {
        const std::string_view index_text = tok.substr(0, tok.find('/'));
        std::int64_t i = 0;
        if (!parse_int(index_text, i) || i == 0) fail(name, at + "bad vertex index " + quoted(tok));
        const std::int64_t v = i > 0 ? i - 1 : defined + i;
        if (v < 0 || v >= defined)
          fail(name, at + "face refers to vertex " + std::to_string(i) + " but only " + std::to_string(defined) +
                         " vertices are defined so far");
        polygon.push_back(static_cast<Index>(v));
      }
      if (polygon.size() < 3)
        fail(name, at + "face has " + std::to_string(polygon.size()) + " vertices, needs at least 3");
      builder.add_polygon(polygon);
    }
    // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) is ignored.
  }
  return builder.finish(report);
}

} // namespace st::mesh_reader
