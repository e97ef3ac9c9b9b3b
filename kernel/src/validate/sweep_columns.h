#pragma once
// Faces seen along a direction w (the removal check's way off): a uniform grid over the plane across
// w. Each cell lists the faces whose projected boxes cover it, with their boxes in the frame (u, v
// across w, w along it), and keeps the stretch along w they span. A path along w is a
// point of that plane: the faces it can meet are those of one cell whose boxes hold the point and
// reach its stretch along w. An axis-aligned tree's boxes instead hold whole pieces of a surface that
// rises across the path, and a path from a guide resting on the bone walks through them all.
//
// Conservative throughout: the frame's coordinates are dot products, rounded by a few units of 2^-53
// of a coordinate's magnitude, and a face's box is grown by the caller's pad (the removal check's
// four lifts, at least 2^-18 of the largest coordinate: far more than that rounding), then rounded
// outwards to float (moved out by 2^-22 of itself first). A face whose grown box misses what is asked is left out; one
// that meets it may be passed on.

#include "st/core/mesh.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace st::validate_detail {

/// An axis-aligned box in the frame (u, v, w).
struct FrameBox {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

class SweepColumns {
public:
  /// The frame of unit direction `w` (u and v across it).
  explicit SweepColumns(const Vec3& w);
  /// Lists `faces` of `mesh` (every face when null), their boxes grown by `pad` on every side.
  void build(const TriangleMesh& mesh, const std::vector<Index>* faces, double pad);

  /// The frame's coordinates of p.
  [[nodiscard]] Vec3 frame(const Vec3& p) const { return {u_.dot(p), v_.dot(p), w_.dot(p)}; }
  /// The box in the frame of face f of `mesh` (not grown).
  [[nodiscard]] FrameBox box_of(const TriangleMesh& mesh, Index f) const;

  /// Whether a listed face's grown box meets `box`.
  [[nodiscard]] bool any_in(const FrameBox& box) const;
  /// Calls visit(face) for the listed faces whose grown boxes hold (u, v) with some w in [w0, w1],
  /// until one returns true; returns whether one did.
  template <class Visit> bool any_along(double u, double v, double w0, double w1, Visit&& visit) const {
    if (!(u >= origin_[0] && u <= end_[0] && v >= origin_[1] && v <= end_[1])) return false; // no box holds it
    const std::size_t c = cell(column(u, 0), column(v, 1));
    if (!(stretch_[c].lo <= w1 && stretch_[c].hi >= w0)) return false;
    for (std::uint32_t e = start_[c]; e < start_[c + 1]; ++e) {
      const Entry& r = listed_[e];
      if (u >= r.lo[0] && u <= r.hi[0] && v >= r.lo[1] && v <= r.hi[1] && r.lo[2] <= w1 && r.hi[2] >= w0 &&
          visit(r.face))
        return true;
    }
    return false;
  }

private:
  struct Entry {
    float lo[3], hi[3]; // the grown box, rounded outwards
    Index face;
  };
  struct Stretch {
    float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
  };
  [[nodiscard]] std::int64_t column(double x, int axis) const; // clamped to the grid; monotone in x
  [[nodiscard]] std::size_t cell(std::int64_t i, std::int64_t j) const {
    return static_cast<std::size_t>(i * cells_[1] + j);
  }

  Vec3 u_, v_, w_;
  double origin_[2] = {0.0, 0.0}, end_[2] = {-1.0, -1.0}, per_cell_ = 1.0; // 1 / a cell's side
  std::int64_t cells_[2] = {0, 0};
  std::vector<Stretch> stretch_;     // per cell
  std::vector<std::uint32_t> start_; // per cell, its first entry in listed_ (and one past the last)
  std::vector<Entry> listed_;        // cell by cell
};

} // namespace st::validate_detail
