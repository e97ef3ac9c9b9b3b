// PLY, ASCII and binary (both byte orders): vertex and face elements.

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

// ---- PLY ----------------------------------------------------------------------------------------

enum class PlyType : std::uint8_t { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

bool ply_type_from_name(std::string_view s, PlyType& t) {
  struct Entry {
    std::string_view name;
    PlyType type;
  };
  static constexpr Entry kTypes[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::Uint8},
      {"uint8", PlyType::Uint8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::Uint16},  {"uint16", PlyType::Uint16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::Uint32},     {"uint32", PlyType::Uint32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const Entry& e : kTypes)
    if (e.name == s) {
      t = e.type;
      return true;
    }
  return false;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
  case PlyType::Int8:
  case PlyType::Uint8: return 1;
  case PlyType::Int16:
  case PlyType::Uint16: return 2;
  case PlyType::Int32:
  case PlyType::Uint32:
  case PlyType::Float32: return 4;
  case PlyType::Float64: return 8;
  }
  return 1;
}

bool ply_is_integer(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

enum class PlyEncoding { Ascii, LittleEndian, BigEndian };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32; // the item type for a list
  bool is_list = false;
  PlyType count_type = PlyType::Uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0; // header line that declares it
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0; // first byte after "end_header\n"
  std::size_t body_line = 0;   // line number of that byte
};

PlyHeader parse_ply_header(const char* data, std::size_t size, const std::string& name, MeshBuilder& builder) {
  PlyHeader header;
  bool have_format = false;
  std::size_t pos = 0;
  std::size_t line_no = 0;
  for (;;) {
    if (pos >= size) fail(name, "PLY header has no 'end_header' line");
    const char* nl = static_cast<const char*>(std::memchr(data + pos, '\n', size - pos));
    const std::size_t line_end = nl ? static_cast<std::size_t>(nl - data) : size;
    std::string_view line(data + pos, line_end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = nl ? line_end + 1 : size;
    ++line_no;
    const std::string at = "line " + std::to_string(line_no) + ": ";

    // Split into words.
    std::vector<std::string_view> words;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && is_space(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (i > start) words.push_back(line.substr(start, i - start));
    }

    if (line_no == 1) {
      if (words.size() != 1 || words[0] != "ply") fail(name, "not a PLY file (no 'ply' magic)");
      continue;
    }
    if (words.empty()) continue;
    const std::string_view key = words[0];
    if (key == "comment") {
      const std::size_t offset = static_cast<std::size_t>(words[0].data() - line.data()) + 7;
      builder.add_header_line(trim(line.substr(std::min(offset, line.size()))));
    } else if (key == "obj_info") {
      // Free text, not needed.
    } else if (key == "format") {
      if (words.size() < 2) fail(name, at + "'format' needs an encoding");
      if (words[1] == "ascii") {
        header.encoding = PlyEncoding::Ascii;
      } else if (words[1] == "binary_little_endian") {
        header.encoding = PlyEncoding::LittleEndian;
      } else if (words[1] == "binary_big_endian") {
        header.encoding = PlyEncoding::BigEndian;
      } else {
        fail(name, at + "unknown PLY format " + quoted(words[1]));
      }
      have_format = true;
    } else if (key == "element") {
      std::int64_t count = 0;
      if (words.size() != 3 || !parse_int(words[2], count) || count < 0)
        fail(name, at + "expected 'element <name> <count>'");
      PlyElement e;
      e.name = std::string(words[1]);
      e.count = static_cast<std::uint64_t>(count);
      e.line = line_no;
      header.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (header.elements.empty()) fail(name, at + "'property' before any 'element'");
      PlyProperty p;
      if (words.size() == 5 && words[1] == "list") {
        p.is_list = true;
        if (!ply_type_from_name(words[2], p.count_type)) fail(name, at + "unknown PLY type " + quoted(words[2]));
        if (!ply_is_integer(p.count_type))
          fail(name, at + "list count type " + quoted(words[2]) + " is not an integer type");
        if (!ply_type_from_name(words[3], p.type)) fail(name, at + "unknown PLY type " + quoted(words[3]));
        p.name = std::string(words[4]);
      } else if (words.size() == 3 && words[1] != "list") {
        if (!ply_type_from_name(words[1], p.type)) fail(name, at + "unknown PLY type " + quoted(words[1]));
        p.name = std::string(words[2]);
      } else {
        fail(name, at + "expected 'property <type> <name>' or "
                        "'property list <count type> <item type> <name>'");
      }
      header.elements.back().properties.push_back(std::move(p));
    } else if (key == "end_header") {
      break;
    } else {
      fail(name, at + "unknown PLY header line " + quoted(key));
    }
  }
  if (!have_format) fail(name, "PLY header has no 'format' line");
  header.body_offset = pos;
  header.body_line = line_no + 1;
  return header;
}

/// Reads values of the binary PLY body.
class PlyBinarySource {
public:
  PlyBinarySource(const char* data, std::size_t begin, std::size_t size, bool big_endian)
      : data_(data), p_(data + begin), end_(data + size), big_(big_endian) {}

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  std::string where() const { return "byte offset " + std::to_string(p_ - data_); }

  bool real(PlyType t, double& out) {
    std::uint64_t raw = 0;
    if (!load(t, raw)) return false;
    switch (t) {
    case PlyType::Int8: out = static_cast<std::int8_t>(raw); break;
    case PlyType::Uint8: out = static_cast<std::uint8_t>(raw); break;
    case PlyType::Int16: out = static_cast<std::int16_t>(raw); break;
    case PlyType::Uint16: out = static_cast<std::uint16_t>(raw); break;
    case PlyType::Int32: out = static_cast<std::int32_t>(raw); break;
    case PlyType::Uint32: out = static_cast<std::uint32_t>(raw); break;
    case PlyType::Float32: out = std::bit_cast<float>(static_cast<std::uint32_t>(raw)); break;
    case PlyType::Float64: out = std::bit_cast<double>(raw); break;
    }
    return true;
  }

  /// Only for integer types.
  bool integer(PlyType t, std::int64_t& out) {
    std::uint64_t raw = 0;
    if (!load(t, raw)) return false;
    switch (t) {
    case PlyType::Int8: out = static_cast<std::int8_t>(raw); break;
    case PlyType::Uint8: out = static_cast<std::uint8_t>(raw); break;
    case PlyType::Int16: out = static_cast<std::int16_t>(raw); break;
    case PlyType::Uint16: out = static_cast<std::uint16_t>(raw); break;
    case PlyType::Int32: out = static_cast<std::int32_t>(raw); break;
    case PlyType::Uint32: out = static_cast<std::uint32_t>(raw); break;
    default: return false;
    }
    return true;
  }

  bool skip(PlyType t) {
    const std::size_t n = ply_size(t);
    if (remaining() < n) return false;
    p_ += n;
    return true;
  }

  /// Skips a list of `count` items; false when fewer bytes are left.
  bool skip_items(PlyType t, std::uint64_t count) {
    if (count > remaining() / ply_size(t)) return false;
    p_ += count * ply_size(t);
    return true;
  }

  /// Whether `count` items of at least `min_bytes` each can still follow.
  bool can_hold(std::uint64_t count, std::size_t min_bytes) const {
    return min_bytes == 0 || count <= remaining() / min_bytes;
  }

private:
  bool load(PlyType t, std::uint64_t& raw) {
    const std::size_t n = ply_size(t);
    if (remaining() < n) return false;
    const auto* b = reinterpret_cast<const unsigned char*>(p_);
    raw = 0;
    if (big_) {
      for (std::size_t i = 0; i < n; ++i) raw = raw << 8 | b[i];
    } else {
      for (std::size_t i = n; i-- > 0;) raw = raw << 8 | b[i];
    }
    p_ += n;
    return true;
  }

  const char* data_;
  const char* p_;
  const char* end_;
  bool big_;
};

/// Reads values of the ASCII PLY body: one whitespace-separated token each.
class PlyAsciiSource {
public:
  PlyAsciiSource(const char* data, std::size_t begin, std::size_t size, std::size_t line)
      : in_(data + begin, data + size, line), end_(data + size) {}

  std::string where() const { return "line " + std::to_string(in_.token_line()); }

  bool real(PlyType, double& out) { return parse_real(in_.token(), out); }
  bool integer(PlyType, std::int64_t& out) { return parse_int(in_.token(), out); }
  bool skip(PlyType) { return !in_.token().empty(); }
  bool skip_items(PlyType t, std::uint64_t count) {
    if (!can_hold(count, 1)) return false;
    for (std::uint64_t i = 0; i < count; ++i)
      if (!skip(t)) return false;
    return true;
  }
  /// Each value takes at least one byte (a digit), so a count above the bytes left is impossible.
  bool can_hold(std::uint64_t count, std::size_t min_values) const {
    return min_values == 0 || count <= static_cast<std::size_t>(end_ - in_.position()) / min_values;
  }

private:
  TextCursor in_;
  const char* end_;
};

template <typename Source> void read_ply_body(Source& in, const PlyHeader& header, std::size_t bytes_per_value,
                                              const std::string& name, MeshBuilder& builder) {
  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex" && !vertex_element) vertex_element = &e;
    if (e.name == "face" && !face_element) face_element = &e;
  }
  if (!face_element) fail(name, "contains no triangles (no 'face' element)");

  // Where x, y, z and the face corner list are.
  int xyz_property[3] = {-1, -1, -1};
  std::uint64_t vertex_count = 0;
  if (vertex_element) {
    vertex_count = vertex_element->count;
    const auto& props = vertex_element->properties;
    for (int k = 0; k < 3; ++k) {
      const char* axis = k == 0 ? "x" : (k == 1 ? "y" : "z");
      for (std::size_t i = 0; i < props.size(); ++i)
        if (props[i].name == axis && !props[i].is_list) {
          xyz_property[k] = static_cast<int>(i);
          break;
        }
      if (xyz_property[k] < 0 && vertex_count > 0)
        fail(name,
             "line " + std::to_string(vertex_element->line) + ": the 'vertex' element has no '" + axis + "' property");
    }
  }
  if (vertex_count > kMaxElements)
    fail(name, "line " + std::to_string(vertex_element->line) + ": " + std::to_string(vertex_count) +
                   " vertices, more than " + std::to_string(kMaxElements));
  int corner_property = -1;
  for (std::size_t i = 0; i < face_element->properties.size(); ++i) {
    const PlyProperty& p = face_element->properties[i];
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
      corner_property = static_cast<int>(i);
      break;
    }
  }
  if (corner_property < 0 && face_element->count > 0)
    fail(name, "line " + std::to_string(face_element->line) +
                   ": the 'face' element has no list property 'vertex_indices' or 'vertex_index'");
  if (corner_property >= 0 && !ply_is_integer(face_element->properties[static_cast<std::size_t>(corner_property)].type))
    fail(name, "line " + std::to_string(face_element->line) + ": the face corner list has a non-integer index type");

  std::vector<Index> polygon;
  for (const PlyElement& e : header.elements) {
    if (e.properties.empty()) continue; // takes no bytes, whatever its count
    // The smallest size of one entry; a header count above what the bytes left can hold is refused
    // before anything is reserved.
    std::size_t min_bytes = 0;
    for (const PlyProperty& p : e.properties)
      min_bytes += bytes_per_value == 0 ? 1 : ply_size(p.is_list ? p.count_type : p.type);
    if (!in.can_hold(e.count, min_bytes))
      fail(name, "element '" + e.name + "' declares " + std::to_string(e.count) +
                     " entries, more than the rest of the file can hold (truncated file?)");
    const bool is_vertex = &e == vertex_element;
    const bool is_face = &e == face_element;
    if (is_vertex) builder.mesh().positions.reserve(e.count);
    if (is_face) builder.mesh().triangles.reserve(e.count);

    auto truncated = [&](std::uint64_t i) {
      fail(name, in.where() + ": unexpected end of data or bad value in element '" + e.name + "' " + std::to_string(i));
    };
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double xyz[3] = {0.0, 0.0, 0.0};
      for (std::size_t j = 0; j < e.properties.size(); ++j) {
        const PlyProperty& p = e.properties[j];
        const int pj = static_cast<int>(j);
        if (!p.is_list) {
          if (is_vertex && (pj == xyz_property[0] || pj == xyz_property[1] || pj == xyz_property[2])) {
            const int k = pj == xyz_property[0] ? 0 : (pj == xyz_property[1] ? 1 : 2);
            if (!in.real(p.type, xyz[k])) truncated(i);
          } else if (!in.skip(p.type)) {
            truncated(i);
          }
          continue;
        }
        std::int64_t count = 0;
        if (!in.integer(p.count_type, count)) truncated(i);
        if (count < 0)
          fail(name, in.where() + ": element '" + e.name + "' " + std::to_string(i) +
                         " has a list of negative length " + std::to_string(count));
        if (!(is_face && pj == corner_property)) {
          if (!in.skip_items(p.type, static_cast<std::uint64_t>(count))) truncated(i);
          continue;
        }
        if (!in.can_hold(static_cast<std::uint64_t>(count), bytes_per_value == 0 ? 1 : ply_size(p.type))) truncated(i);
        if (count < 3)
          fail(name, in.where() + ": face " + std::to_string(i) + " has " + std::to_string(count) +
                         " vertices, needs at least 3");
        polygon.clear();
        for (std::int64_t c = 0; c < count; ++c) {
          std::int64_t v = 0;
          if (!in.integer(p.type, v)) truncated(i);
          if (v < 0 || static_cast<std::uint64_t>(v) >= vertex_count)
            fail(name, in.where() + ": face " + std::to_string(i) + " refers to vertex " + std::to_string(v) +
                           " but there are only " + std::to_string(vertex_count) + " vertices");
          polygon.push_back(static_cast<Index>(v));
        }
        builder.add_polygon(polygon);
      }
      if (is_vertex) {
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
          fail(name, in.where() + ": vertex " + std::to_string(i) + " has a non-finite coordinate " +
                         triple(xyz[0], xyz[1], xyz[2]));
        builder.add_vertex(Vec3(xyz[0], xyz[1], xyz[2]));
      }
    }
  }
}

} // namespace

TriangleMesh read_ply(const char* data, std::size_t size, const std::string& name, ReadReport* report) {
  if (is_blank(data, size)) fail_blank(name, size);
  // A byte order mark before the magic is skipped (byte offsets in messages then count from the
  // magic).
  const std::size_t bom = bom_length(data, size);
  data += bom;
  size -= bom;
  MeshBuilder builder(name, MeshFormat::Ply);
  const PlyHeader header = parse_ply_header(data, size, name, builder);
  if (header.encoding == PlyEncoding::Ascii) {
    PlyAsciiSource in(data, header.body_offset, size, header.body_line);
    read_ply_body(in, header, 0, name, builder);
  } else {
    PlyBinarySource in(data, header.body_offset, size, header.encoding == PlyEncoding::BigEndian);
    read_ply_body(in, header, 1, name, builder);
  }
  return builder.finish(report);
}

} // namespace st::mesh_reader
