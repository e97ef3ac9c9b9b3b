// STL, binary and ASCII: the reader (corners welded) and the binary writer.

#include "mesh_reader.h"
#include "detail/parallel.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

namespace st::mesh_reader {
namespace {

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
    std::uint64_t h = (static_cast<std::uint64_t>(x) | static_cast<std::uint64_t>(y) << 32) * 0x9E3779B97F4A7C15ull;
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
  Index find_or_insert(std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint64_t h, Index next) {
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
Index add_stl_corner(MeshBuilder& builder, CornerWelder& welder, const std::uint32_t bits[3], std::uint64_t hash) {
  const Index next = static_cast<Index>(builder.mesh().positions.size());
  const Index v = welder.find_or_insert(bits[0], bits[1], bits[2], hash, next);
  if (v == next) builder.add_vertex(Vec3(float_from_bits(bits[0]), float_from_bits(bits[1]), float_from_bits(bits[2])));
  return v;
}

std::string stl_header_text(const char* data) {
  std::string_view h(data, 80);
  const std::size_t nul = h.find('\0');
  if (nul != std::string_view::npos) h = h.substr(0, nul);
  while (!h.empty() && is_space(h.back())) h.remove_suffix(1);
  return std::string(h);
}

using CornerBits = std::array<std::uint32_t, 3>;

/// The corners of triangles [first, end) of a binary STL in order, in batches: each corner's float32
/// coordinate bits (-0.0 made 0.0) and hash, the welder's slots for a batch prefetched so that their
/// cache misses overlap, then corner(bits, hash) for each, and triangle() after a triangle's three.
/// Stops at a corner that is not finite and returns what to say about it (nothing when all are).
template <class Corner, class TriangleDone>
std::optional<std::string> for_each_stl_corner(const char* data, std::size_t first, std::size_t end,
                                               const CornerWelder& welder, Corner&& corner, TriangleDone&& triangle) {
  constexpr std::size_t kBatch = 32; // triangles
  CornerBits bits[kBatch * 3];
  std::uint64_t hashes[kBatch * 3];
  for (std::size_t begin = first; begin < end; begin += kBatch) {
    const std::size_t count = std::min(kBatch, end - begin);
    for (std::size_t b = 0; b < count; ++b) {
      const std::size_t t = begin + b;
      const char* record = data + kStlHeaderBytes + kStlTriangleBytes * t;
      for (std::size_t k = 0; k < 3; ++k) {
        const char* at = record + 12 + 12 * k;
        CornerBits& c = bits[3 * b + k];
        c = {load_u32_le(at), load_u32_le(at + 4), load_u32_le(at + 8)};
        if (!is_finite_bits(c[0]) || !is_finite_bits(c[1]) || !is_finite_bits(c[2]))
          return "triangle " + std::to_string(t) + " corner " + std::to_string(k) + " (byte offset " +
                 std::to_string(at - data) + ") has a non-finite coordinate " +
                 triple(float_from_bits(c[0]), float_from_bits(c[1]), float_from_bits(c[2]));
        for (int d = 0; d < 3; ++d)
          if (c[d] == 0x80000000u) c[d] = 0; // -0.0 welds with 0.0
        hashes[3 * b + k] = CornerWelder::hash(c[0], c[1], c[2]);
        welder.prefetch(hashes[3 * b + k]);
      }
    }
    for (std::size_t b = 0; b < count; ++b) {
      for (std::size_t k = 0; k < 3; ++k) corner(bits[3 * b + k], hashes[3 * b + k]);
      triangle();
    }
  }
  return std::nullopt;
}

/// A range of a binary STL's triangles welded on its own: its vertices numbered in order of first
/// appearance in the range, its triangles in those numbers (degenerate ones too).
struct WeldedRange {
  std::vector<CornerBits> vertices;
  std::vector<std::uint64_t> hashes; // of each vertex
  std::vector<Triangle> triangles;
  std::optional<std::string> failure; // the range's first corner that is not finite
};

WeldedRange weld_range(const char* data, std::size_t first, std::size_t end) {
  WeldedRange r;
  const std::size_t n = end - first;
  CornerWelder welder(n / 2 + n / 16 + 4);
  r.vertices.reserve(n / 2 + n / 16 + 4);
  r.hashes.reserve(n / 2 + n / 16 + 4);
  r.triangles.reserve(n);
  Triangle tri{};
  std::size_t k = 0;
  r.failure = for_each_stl_corner(
      data, first, end, welder,
      [&](const CornerBits& c, std::uint64_t h) {
        const auto next = static_cast<Index>(r.vertices.size());
        tri[k++] = welder.find_or_insert(c[0], c[1], c[2], h, next);
        if (tri[k - 1] == next) {
          r.vertices.push_back(c);
          r.hashes.push_back(h);
        }
      },
      [&] {
        r.triangles.push_back(tri);
        k = 0;
      });
  return r;
}

/// Precondition: the size is exactly 84 + 50 * n.
TriangleMesh read_stl_binary(const char* data, const std::string& name, ReadReport* report) {
  const std::size_t n = load_u32_le(data + 80);
  MeshBuilder builder(name, MeshFormat::Stl);
  builder.header() = stl_header_text(data);
  builder.mesh().triangles.reserve(n);
  builder.mesh().positions.reserve(n / 2 + n / 16 + 4); // a closed mesh has about n / 2
  CornerWelder welder(n / 2 + n / 16 + 4);
  // Vertices are numbered in order of first appearance in the file. A large file is read in a few
  // consecutive ranges on threads of their own, each welded on its own; then the ranges' vertices,
  // in order, go through the first range's welder (a vertex that first appears in a later range
  // takes the next number there) and their triangles are renumbered: the same mesh as one pass.
  constexpr std::size_t kMinRange = std::size_t{1} << 17; // triangles
  const std::size_t ranges = std::clamp<std::size_t>(n / kMinRange, 1, detail::thread_count());
  auto range_begin = [&](std::size_t r) { return n * r / ranges; };
  std::vector<WeldedRange> later(ranges - 1);
  std::optional<std::string> failure;
  auto read_first_range = [&] {
    Index v[3];
    int k = 0;
    failure = for_each_stl_corner(
        data, 0, range_begin(1), welder,
        [&](const CornerBits& c, std::uint64_t h) { v[k++] = add_stl_corner(builder, welder, c.data(), h); },
        [&] {
          builder.add_triangle(v[0], v[1], v[2]);
          k = 0;
        });
  };
  std::vector<std::exception_ptr> thrown(ranges); // what a range threw (out of memory): not out of its thread
  detail::parallel_for(ranges, 1, [&](std::size_t, std::size_t r, std::size_t) {
    try {
      if (r > 0) later[r - 1] = weld_range(data, range_begin(r), range_begin(r + 1));
      else read_first_range();
    } catch (...) {
      thrown[r] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : thrown)
    if (e) std::rethrow_exception(e);
  for (std::size_t r = 1; r < ranges && !failure; ++r) { // in file order
    const WeldedRange& range = later[r - 1];
    if (range.failure) { // the first in the file: the ranges before it have none
      failure = range.failure;
      break;
    }
    std::vector<Index> number(range.vertices.size());
    constexpr std::size_t kBatch = 64;
    for (std::size_t begin = 0; begin < range.vertices.size(); begin += kBatch) {
      const std::size_t end = std::min(range.vertices.size(), begin + kBatch);
      for (std::size_t i = begin; i < end; ++i) welder.prefetch(range.hashes[i]);
      for (std::size_t i = begin; i < end; ++i)
        number[i] = add_stl_corner(builder, welder, range.vertices[i].data(), range.hashes[i]);
    }
    for (const Triangle& t : range.triangles) builder.add_triangle(number[t[0]], number[t[1]], number[t[2]]);
  }
  if (failure) fail(name, *failure);
  const std::size_t merged = 3 * n - builder.mesh().positions.size();
  return builder.finish(report, merged);
}

TriangleMesh read_stl_ascii(const char* data, std::size_t size, const std::string& name, ReadReport* report) {
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
    if (!iequals(tok, "solid")) fail(name, at(in.token_line()) + "expected 'solid', found " + quoted(tok));
    const std::string_view solid_name = in.rest_of_line();
    builder.add_header_line(solid_name.empty() ? std::string(tok) : std::string(tok) + " " + std::string(solid_name));
    bool end_of_file = false;
    for (;;) {
      tok = in.token();
      if (tok.empty()) { // a missing "endsolid" at the very end is tolerated
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
          fail(name, at(line) + "facet " + std::to_string(facet) + " corner " + std::to_string(corners.size()) +
                         " has a non-finite or out-of-range coordinate " + triple(xyz[0], xyz[1], xyz[2]));
        std::uint32_t bits[3];
        for (int d = 0; d < 3; ++d) {
          bits[d] = std::bit_cast<std::uint32_t>(xyz[d]);
          if (bits[d] == 0x80000000u) bits[d] = 0; // -0.0 welds with 0.0
        }
        corners.push_back(add_stl_corner(builder, welder, bits, CornerWelder::hash(bits[0], bits[1], bits[2])));
      }
      if (corners.size() < 3)
        fail(name, at(in.token_line()) + "facet " + std::to_string(facet) + " has " + std::to_string(corners.size()) +
                       " vertices, needs at least 3");
      expect("endfacet");
      builder.add_polygon(corners);
      corner_total += corners.size();
      ++facet;
    }
    if (end_of_file) break;
  }
  return builder.finish(report, corner_total - builder.mesh().positions.size());
}

} // namespace

TriangleMesh read_stl(const char* data, std::size_t size, const std::string& name, ReadReport* report) {
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
  fail(name, "truncated or corrupt binary STL: header says " + std::to_string(count) + " triangles (needs " +
                 std::to_string(needed) + " bytes), file has " + std::to_string(size) + " bytes");
}

} // namespace st::mesh_reader

namespace st {

using namespace mesh_reader;

void write_stl(const TriangleMesh& mesh, const std::string& path, const std::string& header) {
  // Check everything before a byte is written.
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    fail(path, "too many triangles for STL (" + std::to_string(mesh.triangles.size()) + ")");
  const double float_max = std::numeric_limits<float>::max();
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.triangles[f][static_cast<std::size_t>(k)];
      if (v >= mesh.positions.size())
        fail(path, "cannot write: triangle " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                       " but there are only " + std::to_string(mesh.positions.size()) + " vertices");
      const Vec3& p = mesh.positions[v];
      if (!p.allFinite() || p.cwiseAbs().maxCoeff() > float_max)
        fail(path, "cannot write: vertex " + std::to_string(v) + " (triangle " + std::to_string(f) +
                       ") has a non-finite or beyond-float32 coordinate " + triple(p.x(), p.y(), p.z()));
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

  constexpr std::size_t kChunk = 8192; // triangles per write
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
    float values[12] = {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) values[3 + 3 * k + d] = c[k][d];
    char* record = buffer.data() + used;
    for (int i = 0; i < 12; ++i) store_u32_le(record + 4 * i, std::bit_cast<std::uint32_t>(values[i]));
    record[48] = record[49] = 0; // attribute byte count
    used += kStlTriangleBytes;
    if (used == buffer.size()) {
      write(buffer.data(), used);
      used = 0;
    }
  }
  write(buffer.data(), used);
  if (std::fflush(guard.file.get()) != 0) fail(path, "cannot write '" + tmp + "': " + system_reason(errno));
  const int close_result = std::fclose(guard.file.release());
  if (close_result != 0) fail(path, "cannot write '" + tmp + "': " + system_reason(errno));

  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fail(path, "cannot replace it with '" + tmp + "': " + ec.message());
  guard.done = true;
}

} // namespace st
