#pragma once
// Reading triangle meshes from STL (binary and ASCII), PLY (ascii, binary little and big
// endian) and OBJ files, and writing binary STL.
//
// Every reader returns a TriangleMesh (positions #V by 3 in the file's units, which the project
// takes as mm; triangles #F by 3). Polygons are fan-triangulated (v0, vi, vi+1). A triangle with a
// repeated vertex index is dropped and counted in ReadReport::degenerate_dropped; vertices that no
// triangle uses stay in the mesh.
//
// STL stores every triangle with its own three corners; the reader welds corners whose float32
// coordinates are bit-for-bit equal (with -0.0 taken as 0.0) into one vertex, numbered in order of
// first appearance. ASCII STL values are rounded to float32 first, as the format specifies. PLY
// and OBJ vertices are taken as they are (no welding).
//
// A binary STL is recognised by its size alone (exactly 84 + 50 * n bytes, n from the header),
// never by the word "solid", which many binary files start with. A file that starts with "solid"
// and does not have that size is read as ASCII STL, unless it holds binary bytes, in which case it
// is reported as a truncated or corrupt binary STL. Text files may start with a UTF-8 byte order
// mark; an ASCII STL may be padded with NUL bytes at the end.
//
// Errors: every reader throws InvalidInput (see errors.h) for a missing or unreadable file (the
// path and the system's reason), an empty file or one with no triangles ("contains no
// triangles"), a non-finite coordinate (naming the vertex, and for STL the triangle and corner), a
// face index out of range (naming the face or line), a file whose triangles are all degenerate,
// more than 2^32 - 2 vertices or triangles, and any syntax error. Messages start with the file's
// name and say where: a line number (from 1) for text formats, a byte offset for binary ones, and
// the number of the vertex, face or triangle (from 0, in file order; OBJ vertices from 1, as OBJ
// counts them). The readers never trust a count in a header: each is checked against the bytes
// left before anything is reserved.

#include "st/core/mesh.h"

#include <cstddef>
#include <string>

namespace st {

enum class MeshFormat { Auto, Stl, Ply, Obj };

/// What the reader found in the file, beyond the mesh itself.
struct ReadReport {
  /// Triangles in the file (after fan triangulation of polygons), degenerate ones included.
  std::size_t input_triangles = 0;
  /// STL only: corners merged into an existing vertex because their float32 coordinates are equal
  /// (3 * input_triangles minus the number of vertices).
  std::size_t merged_vertices = 0;
  /// Triangles dropped because two of their corners are the same vertex (after welding).
  std::size_t degenerate_dropped = 0;
  /// Binary STL: the 80-byte header up to its first NUL, trailing blanks removed (raw bytes, not
  /// necessarily UTF-8). ASCII STL: the "solid <name>" line of each solid. PLY: the text of its
  /// "comment" lines; OBJ: the text of its "#" comment lines. Several lines are joined with '\n'.
  /// Kept so callers can look for tags such as "SPACE=RAS".
  std::string header;
  /// The format actually read (never Auto).
  MeshFormat format = MeshFormat::Auto;
};

/// Reads the mesh in the file at `path`. A gzip-compressed file (e.g. "bone.stl.gz") is inflated
/// first, and then read as the file it holds. With MeshFormat::Auto the format comes from the
/// extension (.stl, .ply, .obj, any case, after removing a ".gz"); for any other extension it is
/// recognised from the content ("ply" magic, binary STL size, "solid", OBJ statements). `report`,
/// when given, is filled in. Throws InvalidInput as described at the top of this header, and for
/// corrupt or truncated gzip data.
TriangleMesh read_mesh(const std::string& path, ReadReport* report = nullptr, MeshFormat format = MeshFormat::Auto);

/// Reads a mesh from `size` bytes at `data` (which need not be NUL-terminated), in `format`
/// (MeshFormat::Auto recognises it from the content). `name` stands for the source in messages.
/// Throws InvalidInput as described at the top of this header.
TriangleMesh read_mesh_from_memory(const char* data, std::size_t size, MeshFormat format, const std::string& name,
                                   ReadReport* report = nullptr);

/// Writes `mesh` as binary STL: `header` (cut to 80 bytes, padded with NULs), the triangle count,
/// and per triangle its unit normal computed from the corners (zero for a degenerate triangle) and
/// its corners, all float32 little-endian. The file is written to `path + ".tmp"` and then renamed
/// over `path`, so `path` is either left as it was or holds the complete new file.
/// Preconditions: indices in range, all coordinates finite and within float32 range. Throws
/// InvalidInput if they are not (before anything is written), or on any I/O error (with the path
/// and the system's reason; the temporary file is removed).
void write_stl(const TriangleMesh& mesh, const std::string& path, const std::string& header = "surgical-template");

} // namespace st
