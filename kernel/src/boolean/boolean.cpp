#include "st/boolean/boolean.h"

#include "boolean/corefinement.h"
#include "detail/format.h"
#include "st/core/errors.h"
#include "st/core/float32.h"
#include "st/core/topology.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace st {

namespace {

void check_operand(const TriangleMesh& mesh, const std::string& what) {
  if (mesh.empty()) throw InvalidInput(what + " is empty");
  check_mesh(mesh, what);
  check_closed_manifold(mesh, what);
}

} // namespace

void check_closed_manifold(const TriangleMesh& mesh, const std::string& what) {
  const MeshTopology topology(mesh);
  std::size_t open = 0;
  Vec3 where = Vec3::Zero();
  for (Index h = 0; h < 3 * mesh.face_count(); ++h)
    if (topology.opposite(h) == kInvalidIndex) {
      if (open++ == 0) where = mesh.positions[topology.from_vertex(h)];
    }
  if (open > 0)
    throw InvalidInput(what + " is not a closed, 2-manifold, consistently oriented surface: " + std::to_string(open) +
                       " edge(s) without a proper partner face, the first near " + detail::where(where));
}

BooleanResult mesh_boolean(const TriangleMesh& a, const TriangleMesh& b, BooleanOp op, const BooleanOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.check_operands) {
    check_operand(a, "the first operand");
    check_operand(b, "the second operand");
  } else {
    if (a.empty() || b.empty()) throw InvalidInput("a Boolean operand is empty");
  }
  if (!options.seat.empty() && options.seat.size() != a.face_count())
    throw InvalidInput("the seat flags must have one entry per face of the first operand");
  const BoundingBox a_box = bounding_box(a);
  BoundingBox box = a_box;
  box.extend(bounding_box(b));
  const double magnitude = std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  // 10 float32 ulp of the largest coordinate: large enough to survive rounding to float, far below
  // any printing or tessellation tolerance.
  const double step = std::max(10.0 * magnitude * std::ldexp(1.0, -23), 1e-9);
  // Operands are rounded to float32 first (what an STL holds), so that only the new points move.
  auto rounded = [&](const TriangleMesh& m) {
    std::optional<TriangleMesh> copy;
    if (!options.round_to_float) return copy;
    for (const Vec3& p : m.positions)
      if (!is_float32(p)) {
        copy = m;
        round_to_float32(*copy);
        break;
      }
    return copy;
  };
  const std::optional<TriangleMesh> a_float = rounded(a), b_float = rounded(b);
  const TriangleMesh& first = a_float ? *a_float : a;
  const BoundingBox first_box = a_float ? bounding_box(first) : a_box;
  const TriangleMesh& second_input = b_float ? *b_float : b;
  static const Vec3 kicks[] = {Vec3(0.5377, -0.6131, 0.5787), Vec3(-0.4431, 0.3318, 0.8328),
                               Vec3(0.7202, 0.6113, -0.3281), Vec3(-0.2217, -0.8874, -0.4041),
                               Vec3(0.3010, 0.1417, -0.9430)};
  std::string last_reason;
  for (int attempt = 0; attempt < std::max(1, options.max_attempts); ++attempt) {
    TriangleMesh moved;
    const TriangleMesh* second = &second_input;
    double offset = 0.0;
    if (attempt > 0) {
      // Growing kicks: 10, 30, 90, ... ulp, for near-coincidences a small one does not separate.
      offset = step * std::pow(3.0, attempt - 1);
      const Vec3 kick = offset * kicks[(attempt - 1) % 5].normalized();
      moved = second_input;
      for (Vec3& p : moved.positions) {
        p += kick;
        if (options.round_to_float) p = to_float32(p);
      }
      second = &moved;
    }
    try {
      // 256 float ulp of the coordinates (2 um at 100 mm): see collapse_short_edges.
      BooleanResult result = boolean_detail::corefine(first, first_box, *second, op, options, 25.6 * step);
      result.attempts = attempt + 1;
      result.curve_tolerance = options.round_to_float ? 25.6 * step : 0.0;
      result.perturbation = offset;
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return result;
    } catch (const boolean_detail::Degenerate& d) {
      last_reason = d.why;
      if (std::getenv("ST_DEBUG_BOOLEAN")) std::fprintf(stderr, "boolean attempt %d: %s\n", attempt + 1, d.why.c_str());
    }
  }
  throw GeometryError("Boolean operation: the operands touch in a way that stays degenerate after " +
                      std::to_string(options.max_attempts) + " small displacements (" + last_reason + ")");
}

} // namespace st
