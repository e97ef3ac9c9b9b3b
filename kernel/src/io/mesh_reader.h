#pragma once
// Private to the mesh readers (stl.cpp, ply.cpp, obj.cpp, mesh_io.cpp): the messages, byte and
// number parsing, mesh builder and text cursor they share, and the three format readers. The public
// API is st/io/mesh_io.h.

#include "detail/text.h"
#include "st/core/errors.h"
#include "st/io/mesh_io.h"

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

using detail::iequals;
using detail::is_space;
using detail::to_lower;
using detail::trim;

namespace fs = std::filesystem;

/// Largest number of vertices or triangles: indices 0 .. 2^32 - 3, kInvalidIndex stays free.
constexpr std::uint64_t kMaxElements = 0xFFFFFFFEull;

constexpr std::size_t kStlHeaderBytes = 84;
constexpr std::size_t kStlTriangleBytes = 50;

// ---- messages -----------------------------------------------------------------------------------

[[noreturn]] inline void fail(const std::string& name, const std::string& what) {
  throw InvalidInput(name + ": " + what);
}

inline std::string system_reason(int err) { return std::generic_category().message(err); }

/// A token as it appears in a message: quoted, at most 40 characters, non-printable bytes escaped.
inline std::string quoted(std::string_view s) {
  std::string out = "'";
  const std::size_t n = std::min<std::size_t>(s.size(), 40);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  if (s.size() > n) out += "...";
  return out + "'";
}

inline std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

inline std::string triple(double x, double y, double z) {
  std::string out = "(";
  out.append(number(x)).append(", ").append(number(y)).append(", ").append(number(z)).append(")");
  return out;
}

// ---- bytes and numbers --------------------------------------------------------------------------

inline std::uint32_t load_u32_le(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
         static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
}

inline void store_u32_le(char* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<char>((v >> (8 * i)) & 0xffu);
}

/// True when the bytes hold control characters that no text mesh file contains.
inline bool looks_binary(const char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    const auto c = static_cast<unsigned char>(data[i]);
    if (c < 0x09 || (c > 0x0d && c < 0x20) || c == 0x7f) return true;
  }
  return false;
}

/// Length of a UTF-8 byte order mark at the start of a text (0 or 3).
inline std::size_t bom_length(const char* data, std::size_t size) {
  return size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

/// The size without trailing NUL bytes (some writers pad text files with them).
inline std::size_t without_trailing_nuls(const char* data, std::size_t size) {
  while (size > 0 && data[size - 1] == '\0') --size;
  return size;
}

/// Parses the whole of `s` as a real number (a leading '+' allowed, also "nan" and "inf").
/// A value too large for T becomes infinity, one too small becomes zero. Returns false when `s` is
/// not a number.
template <typename T> bool parse_real(std::string_view s, T& out) {
  if (s.size() >= 2 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  if (ptr != end || s.empty()) return false;
  if (ec == std::errc::result_out_of_range) {
    // Overflow or underflow: tell which from the sign of the exponent.
    const bool negative = s.front() == '-';
    const std::size_t e = s.find_first_of("eE");
    const bool underflow = e != std::string_view::npos && e + 1 < s.size() && s[e + 1] == '-';
    out = underflow ? T(0) : std::numeric_limits<T>::infinity();
    if (negative) out = -out;
    return true;
  }
  return ec == std::errc();
}

/// Parses the whole of `s` as a decimal integer (a leading '+' allowed).
inline bool parse_int(std::string_view s, std::int64_t& out) {
  if (s.size() >= 2 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return !s.empty() && ptr == end && ec == std::errc();
}

// ---- building the mesh --------------------------------------------------------------------------

/// Collects triangles, drops the degenerate ones and fills the report at the end.
class MeshBuilder {
public:
  MeshBuilder(const std::string& name, MeshFormat format) : name_(name), format_(format) {}

  TriangleMesh& mesh() { return mesh_; }
  std::string& header() { return header_; }

  void add_header_line(std::string_view line) {
    if (!header_.empty()) header_ += '\n';
    header_.append(line.data(), line.size());
  }

  Index add_vertex(const Vec3& p) {
    if (mesh_.positions.size() >= kMaxElements) fail(name_, "more than " + std::to_string(kMaxElements) + " vertices");
    mesh_.positions.push_back(p);
    return static_cast<Index>(mesh_.positions.size() - 1);
  }

  void add_triangle(Index a, Index b, Index c) {
    ++input_triangles_;
    if (a == b || b == c || a == c) {
      ++degenerate_;
      return;
    }
    if (mesh_.triangles.size() >= kMaxElements) fail(name_, "more than " + std::to_string(kMaxElements) + " triangles");
    mesh_.triangles.push_back({a, b, c});
  }

  /// Fan triangulation (v0, vi, vi+1) of a polygon with at least 3 corners.
  void add_polygon(const std::vector<Index>& corners) {
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) add_triangle(corners[0], corners[i], corners[i + 1]);
  }

  TriangleMesh finish(ReadReport* report, std::size_t merged = 0) {
    if (input_triangles_ == 0) fail(name_, "contains no triangles");
    if (mesh_.triangles.empty())
      fail(name_,
           "all " + std::to_string(input_triangles_) + " triangles are degenerate (two corners at the same vertex)");
    if (report) {
      report->input_triangles = input_triangles_;
      report->merged_vertices = merged;
      report->degenerate_dropped = degenerate_;
      report->header = header_;
      report->format = format_;
    }
    return std::move(mesh_);
  }

  std::size_t input_triangles() const { return input_triangles_; }

private:
  const std::string& name_;
  MeshFormat format_;
  TriangleMesh mesh_;
  std::string header_;
  std::size_t input_triangles_ = 0;
  std::size_t degenerate_ = 0;
};

/// Whitespace-separated tokens of a text, with the line each starts on.
class TextCursor {
public:
  TextCursor(const char* begin, const char* end, std::size_t line = 1) : p_(begin), end_(end), line_(line) {}

  /// The next token, or an empty view at the end of the text.
  std::string_view token() {
    skip_space();
    token_line_ = line_;
    const char* start = p_;
    while (p_ < end_ && !is_space(*p_)) ++p_;
    return {start, static_cast<std::size_t>(p_ - start)};
  }

  /// The rest of the current line (trimmed); the cursor moves to the start of the next line.
  std::string_view rest_of_line() {
    const char* start = p_;
    while (p_ < end_ && *p_ != '\n') ++p_;
    std::string_view rest(start, static_cast<std::size_t>(p_ - start));
    if (p_ < end_) {
      ++p_;
      ++line_;
    }
    return trim(rest);
  }

  /// Line (from 1) of the last token returned.
  std::size_t token_line() const { return token_line_; }
  const char* position() const { return p_; }

private:
  void skip_space() {
    while (p_ < end_ && is_space(*p_)) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
  }

  const char* p_;
  const char* end_;
  std::size_t line_;
  std::size_t token_line_ = 1;
};

inline bool starts_with_solid(const char* data, std::size_t size) {
  std::size_t i = bom_length(data, size);
  while (i < size && is_space(data[i])) ++i;
  return size - i >= 5 && iequals(std::string_view(data + i, 5), "solid");
}

inline bool is_blank(const char* data, std::size_t size) {
  for (std::size_t i = bom_length(data, size); i < size; ++i)
    if (!is_space(data[i])) return false;
  return true;
}

[[noreturn]] inline void fail_blank(const std::string& name, std::size_t size) {
  fail(name, size == 0 ? "contains no triangles (the file is empty)" : "contains no triangles (only blank space)");
}

/// A FILE* closed when it goes out of scope.
struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

/// The format readers: `data` holds `size` bytes of one file named `name` (for messages).
TriangleMesh read_stl(const char* data, std::size_t size, const std::string& name, ReadReport* report);
TriangleMesh read_ply(const char* data, std::size_t size, const std::string& name, ReadReport* report);
TriangleMesh read_obj(const char* data, std::size_t size, const std::string& name, ReadReport* report);

} // namespace st::mesh_reader
