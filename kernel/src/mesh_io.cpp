#include "st/mesh_io.h"

#include "detail/gzip.h"
#include "detail/input_file.h"

#include "st/errors.h"
#include "st/tolerances.h"

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
namespace {

namespace fs = std::filesystem;

/// Largest number of vertices or triangles: indices 0 .. 2^32 - 3, kInvalidIndex stays free.
constexpr std::uint64_t kMaxElements = 0xFFFFFFFEull;

constexpr std::size_t kStlHeaderBytes = 84;
constexpr std::size_t kStlTriangleBytes = 50;

// ---- messages -----------------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw InvalidInput(name + ": " + what);
}

std::string system_reason(int err) { return std::generic_category().message(err); }

/// A token as it appears in a message: quoted, at most 40 characters, non-printable bytes escaped.
std::string quoted(std::string_view s) {
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

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string triple(double x, double y, double z) {
  return "(" + number(x) + ", " + number(y) + ", " + number(z) + ")";
}

// ---- bytes and numbers --------------------------------------------------------------------------

std::uint32_t load_u32_le(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
         static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
}

void store_u32_le(char* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<char>((v >> (8 * i)) & 0xffu);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

char to_lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (to_lower(a[i]) != to_lower(b[i])) return false;
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

/// True when the bytes hold control characters that no text mesh file contains.
bool looks_binary(const char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) {
    const auto c = static_cast<unsigned char>(data[i]);
    if (c < 0x09 || (c > 0x0d && c < 0x20) || c == 0x7f) return true;
  }
  return false;
}

/// Length of a UTF-8 byte order mark at the start of a text (0 or 3).
std::size_t bom_length(const char* data, std::size_t size) {
  return size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

/// The size without trailing NUL bytes (some writers pad text files with them).
std::size_t without_trailing_nuls(const char* data, std::size_t size) {
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
bool parse_int(std::string_view s, std::int64_t& out) {
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
    if (mesh_.positions.size() >= kMaxElements)
      fail(name_, "more than " + std::to_string(kMaxElements) + " vertices");
    mesh_.positions.push_back(p);
    return static_cast<Index>(mesh_.positions.size() - 1);
  }

  void add_triangle(Index a, Index b, Index c) {
    ++input_triangles_;
    if (a == b || b == c || a == c) {
      ++degenerate_;
      return;
    }
    if (mesh_.triangles.size() >= kMaxElements)
      fail(name_, "more than " + std::to_string(kMaxElements) + " triangles");
    mesh_.triangles.push_back({a, b, c});
  }

  /// Fan triangulation (v0, vi, vi+1) of a polygon with at least 3 corners.
  void add_polygon(const std::vector<Index>& corners) {
    for (std::size_t i = 1; i + 1 < corners.size(); ++i)
      add_triangle(corners[0], corners[i], corners[i + 1]);
  }

  TriangleMesh finish(ReadReport* report, std::size_t merged = 0) {
    if (input_triangles_ == 0) fail(name_, "contains no triangles");
    if (mesh_.triangles.empty())
      fail(name_, "all " + std::to_string(input_triangles_) +
                      " triangles are degenerate (two corners at the same vertex)");
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

// ---- STL ----------------------------------------------------------------------------------------

/// Welds STL corners: a flat open-addressing hash table (linear probing, at most half full) keyed
/// on the three float32 bit patterns. -0.0 must be turned into 0.0 by the caller.
class CornerWelder {
public:
  explicit CornerWelder(std::size_t expected_vertices) {
    std::size_t capacity = 64;
    while (capacity < 2 * expected_vertices) capacity *= 2;
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
  }

  static std::uint64_t hash(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    std::uint64_t h = (static_cast<std::uint64_t>(x) | static_cast<std::uint64_t>(y) << 32) *
                      0x9E3779B97F4A7C15ull;
    h ^= (static_cast<std::uint64_t>(z) + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return h;
  }

  /// Asks the memory system for the slot a later find_or_insert with hash `h` starts at.
  void prefetch(std::uint64_t h) const {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(&slots_[static_cast<std::size_t>(h) & mask_]);
#else
    (void)h;
#endif
  }

  /// The vertex of the corner with these coordinate bits (and hash(x, y, z) == h); `next` (the
  /// vertex count) when it is new.
  Index find_or_insert(std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint64_t h,
                       Index next) {
    if (2 * (count_ + 1) > slots_.size()) grow();
    std::size_t i = static_cast<std::size_t>(h) & mask_;
    for (;;) {
      Slot& s = slots_[i];
      if (s.id == kInvalidIndex) {
        s = Slot{x, y, z, next};
        ++count_;
        return next;
      }
      if (s.x == x && s.y == y && s.z == z) return s.id;
      i = (i + 1) & mask_;
    }
  }

private:
  struct Slot {
    std::uint32_t x = 0, y = 0, z = 0;
    Index id = kInvalidIndex;
  };

  void grow() {
    std::vector<Slot> old(2 * slots_.size());
    old.swap(slots_);
    mask_ = slots_.size() - 1;
    for (const Slot& s : old) {
      if (s.id == kInvalidIndex) continue;
      std::size_t i = static_cast<std::size_t>(hash(s.x, s.y, s.z)) & mask_;
      while (slots_[i].id != kInvalidIndex) i = (i + 1) & mask_;
      slots_[i] = s;
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t count_ = 0;
};

bool is_finite_bits(std::uint32_t bits) { return (bits & 0x7f800000u) != 0x7f800000u; }

float float_from_bits(std::uint32_t bits) { return std::bit_cast<float>(bits); }

/// Adds one STL corner (float32 coordinate bits, -0.0 already made 0.0) through the welder.
Index add_stl_corner(MeshBuilder& builder, CornerWelder& welder, const std::uint32_t bits[3],
                     std::uint64_t hash) {
  const Index next = static_cast<Index>(builder.mesh().positions.size());
  const Index v = welder.find_or_insert(bits[0], bits[1], bits[2], hash, next);
  if (v == next)
    builder.add_vertex(Vec3(float_from_bits(bits[0]), float_from_bits(bits[1]),
                            float_from_bits(bits[2])));
  return v;
}

std::string stl_header_text(const char* data) {
  std::string_view h(data, 80);
  const std::size_t nul = h.find('\0');
  if (nul != std::string_view::npos) h = h.substr(0, nul);
  while (!h.empty() && is_space(h.back())) h.remove_suffix(1);
  return std::string(h);
}

/// Precondition: the size is exactly 84 + 50 * n.
TriangleMesh read_stl_binary(const char* data, const std::string& name, ReadReport* report) {
  const std::size_t n = load_u32_le(data + 80);
  MeshBuilder builder(name, MeshFormat::Stl);
  builder.header() = stl_header_text(data);
  builder.mesh().triangles.reserve(n);
  builder.mesh().positions.reserve(n / 2 + n / 16 + 4);  // a closed mesh has about n / 2
  CornerWelder welder(n / 2 + n / 16 + 4);

  // Corners go through the welder in batches: first all their slots are prefetched, so the cache
  // misses of a batch overlap, then they are looked up in file order (vertices are numbered in
  // order of first appearance).
  constexpr std::size_t kBatch = 32;  // triangles
  std::uint32_t bits[kBatch * 3][3];
  std::uint64_t hashes[kBatch * 3];
  for (std::size_t first = 0; first < n; first += kBatch) {
    const std::size_t count = std::min(kBatch, n - first);
    for (std::size_t b = 0; b < count; ++b) {
      const std::size_t t = first + b;
      const char* record = data + kStlHeaderBytes + kStlTriangleBytes * t;
      for (std::size_t k = 0; k < 3; ++k) {
        const char* corner = record + 12 + 12 * k;
        std::uint32_t* c = bits[3 * b + k];
        c[0] = load_u32_le(corner);
        c[1] = load_u32_le(corner + 4);
        c[2] = load_u32_le(corner + 8);
        if (!is_finite_bits(c[0]) || !is_finite_bits(c[1]) || !is_finite_bits(c[2]))
          fail(name, "triangle " + std::to_string(t) + " corner " + std::to_string(k) +
                         " (byte offset " + std::to_string(corner - data) +
                         ") has a non-finite coordinate " +
                         triple(float_from_bits(c[0]), float_from_bits(c[1]),
                                float_from_bits(c[2])));
        for (int d = 0; d < 3; ++d)
          if (c[d] == 0x80000000u) c[d] = 0;  // -0.0 welds with 0.0
        hashes[3 * b + k] = CornerWelder::hash(c[0], c[1], c[2]);
        welder.prefetch(hashes[3 * b + k]);
      }
    }
    for (std::size_t b = 0; b < count; ++b) {
      Index v[3];
      for (std::size_t k = 0; k < 3; ++k)
        v[k] = add_stl_corner(builder, welder, bits[3 * b + k], hashes[3 * b + k]);
      builder.add_triangle(v[0], v[1], v[2]);
    }
  }
  const std::size_t merged = 3 * n - builder.mesh().positions.size();
  return builder.finish(report, merged);
}

/// Whitespace-separated tokens of a text, with the line each starts on.
class TextCursor {
public:
  TextCursor(const char* begin, const char* end, std::size_t line = 1)
      : p_(begin), end_(end), line_(line) {}

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

TriangleMesh read_stl_ascii(const char* data, std::size_t size, const std::string& name,
                            ReadReport* report) {
  MeshBuilder builder(name, MeshFormat::Stl);
  CornerWelder welder(size / 256 + 16);
  TextCursor in(data + bom_length(data, size), data + size);
  std::vector<Index> corners;
  std::size_t facet = 0;
  std::size_t corner_total = 0;

  auto at = [&](std::size_t line) { return "line " + std::to_string(line) + ": "; };
  auto expect = [&](std::string_view keyword) {
    const std::string_view tok = in.token();
    if (!iequals(tok, keyword))
      fail(name, at(in.token_line()) + "expected '" + std::string(keyword) + "', found " +
                     (tok.empty() ? std::string("end of file") : quoted(tok)));
  };

  for (;;) {
    std::string_view tok = in.token();
    if (tok.empty()) break;
    if (!iequals(tok, "solid"))
      fail(name, at(in.token_line()) + "expected 'solid', found " + quoted(tok));
    const std::string_view solid_name = in.rest_of_line();
    builder.add_header_line(solid_name.empty() ? std::string(tok)
                                               : std::string(tok) + " " + std::string(solid_name));
    bool end_of_file = false;
    for (;;) {
      tok = in.token();
      if (tok.empty()) {  // a missing "endsolid" at the very end is tolerated
        end_of_file = true;
        break;
      }
      if (iequals(tok, "endsolid")) {
        in.rest_of_line();
        break;
      }
      if (!iequals(tok, "facet"))
        fail(name, at(in.token_line()) + "expected 'facet' or 'endsolid', found " + quoted(tok));
      tok = in.token();
      if (iequals(tok, "normal")) {
        // The stored normal is not used; some writers put "nan" there, so any 3 tokens will do.
        for (int k = 0; k < 3; ++k) {
          tok = in.token();
          if (tok.empty() || iequals(tok, "outer"))
            fail(name, at(in.token_line()) + "expected 3 numbers after 'normal', found " +
                           (tok.empty() ? std::string("end of file") : quoted(tok)));
        }
        tok = in.token();
      }
      if (!iequals(tok, "outer"))
        fail(name, at(in.token_line()) + "expected 'outer', found " +
                       (tok.empty() ? std::string("end of file") : quoted(tok)));
      expect("loop");
      corners.clear();
      for (;;) {
        tok = in.token();
        if (iequals(tok, "endloop")) break;
        if (!iequals(tok, "vertex"))
          fail(name, at(in.token_line()) + "expected 'vertex' or 'endloop', found " +
                         (tok.empty() ? std::string("end of file") : quoted(tok)));
        const std::size_t line = in.token_line();
        float xyz[3];
        for (float& c : xyz) {
          tok = in.token();
          if (!parse_real(tok, c))
            fail(name, at(in.token_line()) + "expected a number, found " +
                           (tok.empty() ? std::string("end of file") : quoted(tok)));
        }
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
          fail(name, at(line) + "facet " + std::to_string(facet) + " corner " +
                         std::to_string(corners.size()) +
                         " has a non-finite or out-of-range coordinate " +
                         triple(xyz[0], xyz[1], xyz[2]));
        std::uint32_t bits[3];
        for (int d = 0; d < 3; ++d) {
          bits[d] = std::bit_cast<std::uint32_t>(xyz[d]);
          if (bits[d] == 0x80000000u) bits[d] = 0;  // -0.0 welds with 0.0
        }
        corners.push_back(add_stl_corner(builder, welder, bits,
                                         CornerWelder::hash(bits[0], bits[1], bits[2])));
      }
      if (corners.size() < 3)
        fail(name, at(in.token_line()) + "facet " + std::to_string(facet) + " has " +
                       std::to_string(corners.size()) + " vertices, needs at least 3");
      expect("endfacet");
      builder.add_polygon(corners);
      corner_total += corners.size();
      ++facet;
    }
    if (end_of_file) break;
  }
  return builder.finish(report, corner_total - builder.mesh().positions.size());
}

bool starts_with_solid(const char* data, std::size_t size) {
  std::size_t i = bom_length(data, size);
  while (i < size && is_space(data[i])) ++i;
  return size - i >= 5 && iequals(std::string_view(data + i, 5), "solid");
}

bool is_blank(const char* data, std::size_t size) {
  for (std::size_t i = bom_length(data, size); i < size; ++i)
    if (!is_space(data[i])) return false;
  return true;
}

[[noreturn]] void fail_blank(const std::string& name, std::size_t size) {
  fail(name, size == 0 ? "contains no triangles (the file is empty)"
                       : "contains no triangles (only blank space)");
}

TriangleMesh read_stl(const char* data, std::size_t size, const std::string& name,
                      ReadReport* report) {
  if (is_blank(data, size)) fail_blank(name, size);
  std::uint64_t count = 0;
  std::uint64_t needed = 0;
  if (size >= kStlHeaderBytes) {
    count = load_u32_le(data + 80);
    needed = kStlHeaderBytes + kStlTriangleBytes * count;
    if (needed == size) return read_stl_binary(data, name, report);
  }
  const std::size_t text_size = without_trailing_nuls(data, size);
  if (starts_with_solid(data, text_size) && !looks_binary(data, text_size))
    return read_stl_ascii(data, text_size, name, report);
  if (size < kStlHeaderBytes)
    fail(name, "truncated or corrupt binary STL: file has " + std::to_string(size) +
                   " bytes, less than the 84-byte header (and it is not ASCII STL)");
  fail(name, "truncated or corrupt binary STL: header says " + std::to_string(count) +
                 " triangles (needs " + std::to_string(needed) + " bytes), file has " +
                 std::to_string(size) + " bytes");
}

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
  PlyType type = PlyType::Float32;  // the item type for a list
  bool is_list = false;
  PlyType count_type = PlyType::Uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;  // header line that declares it
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;  // first byte after "end_header\n"
  std::size_t body_line = 0;    // line number of that byte
};

PlyHeader parse_ply_header(const char* data, std::size_t size, const std::string& name,
                           MeshBuilder& builder) {
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
        if (!ply_type_from_name(words[2], p.count_type))
          fail(name, at + "unknown PLY type " + quoted(words[2]));
        if (!ply_is_integer(p.count_type))
          fail(name, at + "list count type " + quoted(words[2]) + " is not an integer type");
        if (!ply_type_from_name(words[3], p.type))
          fail(name, at + "unknown PLY type " + quoted(words[3]));
        p.name = std::string(words[4]);
      } else if (words.size() == 3 && words[1] != "list") {
        if (!ply_type_from_name(words[1], p.type))
          fail(name, at + "unknown PLY type " + quoted(words[1]));
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
    return min_values == 0 ||
           count <= static_cast<std::size_t>(end_ - in_.position()) / min_values;
  }

private:
  TextCursor in_;
  const char* end_;
};

template <typename Source>
void read_ply_body(Source& in, const PlyHeader& header, std::size_t bytes_per_value,
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
        fail(name, "line " + std::to_string(vertex_element->line) +
                       ": the 'vertex' element has no '" + axis + "' property");
    }
  }
  if (vertex_count > kMaxElements)
    fail(name, "line " + std::to_string(vertex_element->line) + ": " +
                   std::to_string(vertex_count) + " vertices, more than " +
                   std::to_string(kMaxElements));
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
  if (corner_property >= 0 &&
      !ply_is_integer(face_element->properties[static_cast<std::size_t>(corner_property)].type))
    fail(name, "line " + std::to_string(face_element->line) +
                   ": the face corner list has a non-integer index type");

  std::vector<Index> polygon;
  for (const PlyElement& e : header.elements) {
    if (e.properties.empty()) continue;  // takes no bytes, whatever its count
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
      fail(name, in.where() + ": unexpected end of data or bad value in element '" + e.name +
                     "' " + std::to_string(i));
    };
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double xyz[3] = {0.0, 0.0, 0.0};
      for (std::size_t j = 0; j < e.properties.size(); ++j) {
        const PlyProperty& p = e.properties[j];
        const int pj = static_cast<int>(j);
        if (!p.is_list) {
          if (is_vertex && (pj == xyz_property[0] || pj == xyz_property[1] ||
                            pj == xyz_property[2])) {
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
        if (!in.can_hold(static_cast<std::uint64_t>(count),
                         bytes_per_value == 0 ? 1 : ply_size(p.type)))
          truncated(i);
        if (count < 3)
          fail(name, in.where() + ": face " + std::to_string(i) + " has " +
                         std::to_string(count) + " vertices, needs at least 3");
        polygon.clear();
        for (std::int64_t c = 0; c < count; ++c) {
          std::int64_t v = 0;
          if (!in.integer(p.type, v)) truncated(i);
          if (v < 0 || static_cast<std::uint64_t>(v) >= vertex_count)
            fail(name, in.where() + ": face " + std::to_string(i) + " refers to vertex " +
                           std::to_string(v) + " but there are only " +
                           std::to_string(vertex_count) + " vertices");
          polygon.push_back(static_cast<Index>(v));
        }
        builder.add_polygon(polygon);
      }
      if (is_vertex) {
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
          fail(name, in.where() + ": vertex " + std::to_string(i) +
                         " has a non-finite coordinate " + triple(xyz[0], xyz[1], xyz[2]));
        builder.add_vertex(Vec3(xyz[0], xyz[1], xyz[2]));
      }
    }
  }
}

TriangleMesh read_ply(const char* data, std::size_t size, const std::string& name,
                      ReadReport* report) {
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
    PlyBinarySource in(data, header.body_offset, size,
                       header.encoding == PlyEncoding::BigEndian);
    read_ply_body(in, header, 1, name, builder);
  }
  return builder.finish(report);
}

// ---- OBJ ----------------------------------------------------------------------------------------

TriangleMesh read_obj(const char* data, std::size_t size, const std::string& name,
                      ReadReport* report) {
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
          fail(name, at + "expected 3 vertex coordinates, found " +
                         (tok.empty() ? std::string("end of line") : quoted(tok)));
      }
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
        fail(name, at + "vertex " + std::to_string(builder.mesh().positions.size() + 1) +
                       " (counting from 1, as OBJ does) has a non-finite coordinate " +
                       triple(xyz[0], xyz[1], xyz[2]));
      builder.add_vertex(Vec3(xyz[0], xyz[1], xyz[2]));  // an optional w (or colour) is ignored
    } else if (key == "f") {
      polygon.clear();
      const auto defined = static_cast<std::int64_t>(builder.mesh().positions.size());
      for (std::string_view tok = words.token(); !tok.empty(); tok = words.token()) {
        const std::string_view index_text = tok.substr(0, tok.find('/'));
        std::int64_t i = 0;
        if (!parse_int(index_text, i) || i == 0)
          fail(name, at + "bad vertex index " + quoted(tok));
        const std::int64_t v = i > 0 ? i - 1 : defined + i;
        if (v < 0 || v >= defined)
          fail(name, at + "face refers to vertex " + std::to_string(i) + " but only " +
                         std::to_string(defined) + " vertices are defined so far");
        polygon.push_back(static_cast<Index>(v));
      }
      if (polygon.size() < 3)
        fail(name, at + "face has " + std::to_string(polygon.size()) +
                       " vertices, needs at least 3");
      builder.add_polygon(polygon);
    }
    // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) is ignored.
  }
  return builder.finish(report);
}

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
  static constexpr std::string_view kStatements[] = {"v",  "vt", "vn", "vp", "f",      "g",
                                                     "o",  "s",  "l",  "p",  "mtllib", "usemtl"};
  if (!first.empty() && first.front() == '#') return true;
  return std::find(std::begin(kStatements), std::end(kStatements), first) !=
         std::end(kStatements);
}

MeshFormat sniff_format(const char* data, std::size_t size, const std::string& name) {
  if (is_blank(data, size)) fail_blank(name, size);
  if (starts_with_ply_magic(data, size)) return MeshFormat::Ply;
  if (size >= kStlHeaderBytes &&
      kStlHeaderBytes + kStlTriangleBytes * std::uint64_t{load_u32_le(data + 80)} == size)
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

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

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

TriangleMesh read_mesh_from_memory(const char* data, std::size_t size, MeshFormat format,
                                   const std::string& name, ReadReport* report) {
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
      kStlHeaderBytes + kStlTriangleBytes * std::uint64_t{load_u32_le(bytes.data.get() + 80)} ==
          bytes.size;
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
  if (gzipped)
    return read_mesh_from_memory(inflated.data(), inflated.size(), format, path, report);
  return read_mesh_from_memory(bytes.data.get(), bytes.size, format, path, report);
}

void write_stl(const TriangleMesh& mesh, const std::string& path, const std::string& header) {
  // Check everything before a byte is written.
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    fail(path, "too many triangles for STL (" + std::to_string(mesh.triangles.size()) + ")");
  const double float_max = std::numeric_limits<float>::max();
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.triangles[f][static_cast<std::size_t>(k)];
      if (v >= mesh.positions.size())
        fail(path, "cannot write: triangle " + std::to_string(f) + " refers to vertex " +
                       std::to_string(v) + " but there are only " +
                       std::to_string(mesh.positions.size()) + " vertices");
      const Vec3& p = mesh.positions[v];
      if (!p.allFinite() || p.cwiseAbs().maxCoeff() > float_max)
        fail(path, "cannot write: vertex " + std::to_string(v) + " (triangle " +
                       std::to_string(f) + ") has a non-finite or beyond-float32 coordinate " +
                       triple(p.x(), p.y(), p.z()));
    }

  const std::string tmp = path + ".tmp";
  struct TmpGuard {
    const std::string& tmp;
    FilePtr file;
    bool done = false;
    ~TmpGuard() {
      file.reset();
      if (!done) std::remove(tmp.c_str());
    }
  } guard{tmp, nullptr};

  errno = 0;
  guard.file.reset(std::fopen(tmp.c_str(), "wb"));
  if (!guard.file) fail(path, "cannot write '" + tmp + "': " + system_reason(errno));
  auto write = [&](const char* bytes, std::size_t n) {
    if (std::fwrite(bytes, 1, n, guard.file.get()) != n)
      fail(path, "cannot write '" + tmp + "': " + system_reason(errno));
  };

  char head[kStlHeaderBytes] = {};
  std::memcpy(head, header.data(), std::min<std::size_t>(header.size(), 80));
  store_u32_le(head + 80, static_cast<std::uint32_t>(mesh.triangles.size()));
  write(head, sizeof head);

  constexpr std::size_t kChunk = 8192;  // triangles per write
  std::vector<char> buffer(kChunk * kStlTriangleBytes);
  std::size_t used = 0;
  for (const Triangle& t : mesh.triangles) {
    Eigen::Vector3f c[3];
    for (int k = 0; k < 3; ++k) c[k] = mesh.positions[t[static_cast<std::size_t>(k)]].cast<float>();
    // The normal of the triangle as stored (float32 corners).
    const Eigen::Vector3d a = c[0].cast<double>();
    Eigen::Vector3d n = (c[1].cast<double>() - a).cross(c[2].cast<double>() - a);
    const double len = n.norm();
    n = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    float values[12] = {static_cast<float>(n.x()), static_cast<float>(n.y()),
                        static_cast<float>(n.z())};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) values[3 + 3 * k + d] = c[k][d];
    char* record = buffer.data() + used;
    for (int i = 0; i < 12; ++i)
      store_u32_le(record + 4 * i, std::bit_cast<std::uint32_t>(values[i]));
    record[48] = record[49] = 0;  // attribute byte count
    used += kStlTriangleBytes;
    if (used == buffer.size()) {
      write(buffer.data(), used);
      used = 0;
    }
  }
  write(buffer.data(), used);
  if (std::fflush(guard.file.get()) != 0)
    fail(path, "cannot write '" + tmp + "': " + system_reason(errno));
  const int close_result = std::fclose(guard.file.release());
  if (close_result != 0) fail(path, "cannot write '" + tmp + "': " + system_reason(errno));

  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fail(path, "cannot replace it with '" + tmp + "': " + ec.message());
  guard.done = true;
}

} // namespace st
