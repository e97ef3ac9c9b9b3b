#include "sweep_columns.h"

#include <algorithm>
#include <cmath>

namespace st::validate_detail {

namespace {

// A float at most x (at least x): float keeps 24 bits, so x moved by 2^-22 of itself outwards first
// rounds to one beyond x; beyond float's range (or not a number) the infinity or the largest float
// on the safe side.
float below(double x) {
  const double y = x - (std::abs(x) * 0x1p-22 + 0x1p-126);
  if (!(y > -std::numeric_limits<float>::max())) return -std::numeric_limits<float>::infinity();
  return y >= std::numeric_limits<float>::max() ? std::numeric_limits<float>::max() : static_cast<float>(y);
}
float above(double x) {
  const double y = x + (std::abs(x) * 0x1p-22 + 0x1p-126);
  if (!(y < std::numeric_limits<float>::max())) return std::numeric_limits<float>::infinity();
  return y <= -std::numeric_limits<float>::max() ? -std::numeric_limits<float>::max() : static_cast<float>(y);
}

} // namespace

SweepColumns::SweepColumns(const Vec3& w) : w_(w) {
  int k = 0; // the axis most across w
  for (int j = 1; j < 3; ++j)
    if (std::abs(w[j]) < std::abs(w[k])) k = j;
  const Vec3 e = Vec3::Unit(k);
  u_ = (e - e.dot(w) * w).normalized();
  v_ = w.cross(u_);
}

FrameBox SweepColumns::box_of(const TriangleMesh& mesh, Index f) const {
  FrameBox b;
  for (Index c : mesh.triangles[f]) {
    const Vec3 x = frame(mesh.positions[c]);
    b.lo = b.lo.cwiseMin(x);
    b.hi = b.hi.cwiseMax(x);
  }
  return b;
}

std::int64_t SweepColumns::column(double x, int axis) const {
  // Truncation is the floor where it is not clamped to 0 (as is a place that is not a number).
  double c = (x - origin_[axis]) * per_cell_;
  if (!(c > 0.0)) return 0;
  c = std::min(c, static_cast<double>(cells_[axis] - 1));
  return static_cast<std::int64_t>(c);
}

void SweepColumns::build(const TriangleMesh& mesh, const std::vector<Index>* faces, double pad) {
  const std::size_t n = faces ? faces->size() : mesh.face_count();
  auto face = [&](std::size_t i) { return faces ? (*faces)[i] : static_cast<Index>(i); };
  std::vector<Entry> entries(n);
  double mean = 0.0;
  for (int a = 0; a < 2; ++a) {
    origin_[a] = std::numeric_limits<double>::infinity();
    end_[a] = -origin_[a];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const FrameBox b = box_of(mesh, face(i));
    Entry& e = entries[i];
    for (int a = 0; a < 3; ++a) {
      e.lo[a] = below(b.lo[a] - pad);
      e.hi[a] = above(b.hi[a] + pad);
    }
    e.face = face(i);
    for (int a = 0; a < 2; ++a) {
      origin_[a] = std::min(origin_[a], static_cast<double>(e.lo[a]));
      end_[a] = std::max(end_[a], static_cast<double>(e.hi[a]));
    }
    mean += std::max(e.hi[0] - e.lo[0], e.hi[1] - e.lo[1]);
  }
  cells_[0] = cells_[1] = 0;
  stretch_.clear();
  start_.assign(1, 0);
  listed_.clear();
  if (n == 0) return;
  mean /= static_cast<double>(n);
  // Cells about a face's size (or finer faces spread over a larger plane): a few faces each, a face
  // in a few cells; at most 4n + 16 cells, and fewer while the faces would be listed more than 16n
  // times over (large faces among small ones). A plane without a finite extent is one cell.
  const double extent[2] = {end_[0] - origin_[0], end_[1] - origin_[1]};
  double side = std::max(mean, std::sqrt(extent[0] * extent[1] / static_cast<double>(n)));
  const bool finite = std::isfinite(extent[0]) && std::isfinite(extent[1]) && std::isfinite(side);
  if (!finite || !(side > 0.0)) side = finite ? std::max({extent[0], extent[1], 1.0}) : 1.0;
  const double most = 4.0 * static_cast<double>(n) + 16.0;
  for (;;) {
    for (int a = 0; a < 2; ++a)
      cells_[a] = finite ? std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(extent[a] / side))) : 1;
    per_cell_ = 1.0 / side;
    if (static_cast<double>(cells_[0]) * static_cast<double>(cells_[1]) > most) {
      side *= 2.0;
      continue;
    }
    double listed = 0.0;
    for (const Entry& e : entries)
      listed += static_cast<double>(column(e.hi[0], 0) - column(e.lo[0], 0) + 1) *
                static_cast<double>(column(e.hi[1], 1) - column(e.lo[1], 1) + 1);
    if (listed <= 16.0 * static_cast<double>(n) + 16.0 || (cells_[0] == 1 && cells_[1] == 1)) break;
    side *= 2.0;
  }
  const std::size_t cells = cell(cells_[0] - 1, cells_[1] - 1) + 1;
  stretch_.assign(cells, Stretch{});
  auto each_cell = [&](const Entry& e, auto&& visit) {
    const std::int64_t u0 = column(e.lo[0], 0), u1 = column(e.hi[0], 0);
    const std::int64_t v0 = column(e.lo[1], 1), v1 = column(e.hi[1], 1);
    for (std::int64_t i = u0; i <= u1; ++i)
      for (std::int64_t j = v0; j <= v1; ++j) visit(cell(i, j));
  };
  std::vector<std::uint32_t> count(cells + 1, 0);
  for (const Entry& e : entries)
    each_cell(e, [&](std::size_t c) {
      stretch_[c].lo = std::min(stretch_[c].lo, e.lo[2]);
      stretch_[c].hi = std::max(stretch_[c].hi, e.hi[2]);
      ++count[c + 1];
    });
  for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
  start_ = count;
  listed_.resize(count[cells]);
  for (const Entry& e : entries) each_cell(e, [&](std::size_t c) { listed_[count[c]++] = e; });
}

bool SweepColumns::any_in(const FrameBox& box) const {
  if (cells_[0] == 0 || box.hi[0] < origin_[0] || box.lo[0] > end_[0] || box.hi[1] < origin_[1] || box.lo[1] > end_[1])
    return false;
  const std::int64_t u0 = column(box.lo[0], 0), u1 = column(box.hi[0], 0);
  const std::int64_t v0 = column(box.lo[1], 1), v1 = column(box.hi[1], 1);
  for (std::int64_t i = u0; i <= u1; ++i)
    for (std::int64_t j = v0; j <= v1; ++j) {
      const std::size_t c = cell(i, j);
      if (!(stretch_[c].lo <= box.hi[2] && stretch_[c].hi >= box.lo[2])) continue;
      for (std::uint32_t e = start_[c]; e < start_[c + 1]; ++e) {
        const Entry& r = listed_[e];
        if (r.lo[0] <= box.hi[0] && r.hi[0] >= box.lo[0] && r.lo[1] <= box.hi[1] && r.hi[1] >= box.lo[1] &&
            r.lo[2] <= box.hi[2] && r.hi[2] >= box.lo[2])
          return true;
      }
    }
  return false;
}

} // namespace st::validate_detail
