// The removal check's columns along its way off (validate/sweep_columns.h) pass on every face whose
// box, grown by the pad, holds a path or meets a box: a brute force over every face, on a sphere
// (near the origin and 100 km from it, where a float's step is 8 mm), a wavy grid and a flat regular
// one, along an axis (edges parallel to the way, faces seen edge-on), a tilted way, from random
// points, vertices and edge midpoints.

#include "helpers.h"

#include "validate/sweep_columns.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace st {
namespace {

using test::make_grid_patch;
using test::make_icosphere;
using validate_detail::FrameBox;
using validate_detail::SweepColumns;

std::vector<TriangleMesh> meshes() {
  const TriangleMesh wavy = make_grid_patch(20, -3.0, 3.0, -3.0, 3.0, [](double u, double v) {
    return Vec3(u, v, 0.4 * std::sin(2.0 * u) * std::cos(1.5 * v));
  });
  const TriangleMesh flat = make_grid_patch(12, 0.0, 6.0, 0.0, 6.0, [](double u, double v) { return Vec3(u, v, 1.0); });
  return {make_icosphere(2.0, 3), make_icosphere(2.0, 2, Vec3(1.0e5, -2.5e5 + 0.3, 7.0e4 + 0.7)), wavy, flat};
}

/// Random points about the mesh, its vertices and its edges' midpoints.
std::vector<Vec3> probes(const TriangleMesh& mesh, std::mt19937& rng) {
  const BoundingBox box = bounding_box(mesh).inflated(0.5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> out;
  for (int i = 0; i < 150; ++i) out.push_back(box.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(box.size()));
  for (Index f = 0; f < mesh.face_count(); f += 7) {
    const Triangle& t = mesh.triangles[f];
    out.push_back(mesh.positions[t[0]]);
    out.push_back(0.5 * (mesh.positions[t[1]] + mesh.positions[t[2]]));
  }
  return out;
}

/// Whether face f's box in the frame, grown by `grow`, meets `box`.
bool meets(const SweepColumns& columns, const TriangleMesh& mesh, Index f, const FrameBox& box, double grow) {
  const FrameBox b = columns.box_of(mesh, f);
  return ((b.lo.array() - grow) <= box.hi.array()).all() && (box.lo.array() <= (b.hi.array() + grow)).all();
}

TEST(SweepColumns, PassOnEveryFaceWhoseGrownBoxHoldsThePathOrMeetsTheBox) {
  std::mt19937 rng(11);
  const std::vector<Vec3> ways = {Vec3::UnitZ(), -Vec3::UnitX(), Vec3(0.3, -0.2, 0.9).normalized()};
  for (const TriangleMesh& mesh : meshes()) {
    const BoundingBox all = bounding_box(mesh);
    const double magnitude = std::max(all.min.cwiseAbs().maxCoeff(), all.max.cwiseAbs().maxCoeff());
    const double pad = 4.0 * std::max(1e-3, std::ldexp(magnitude, -20));
    const double slack = pad + std::ldexp(magnitude, -20); // the float rounding outwards may add
    std::vector<Index> half; // a subset of the faces, as the removal check lists the bone's
    for (Index f = 0; f < mesh.face_count(); f += 2) half.push_back(f);
    const std::vector<Vec3> points = probes(mesh, rng);
    std::uniform_real_distribution<double> reach(0.0, 1.0);
    for (const Vec3& w : ways)
      for (const std::vector<Index>* faces : {static_cast<const std::vector<Index>*>(nullptr), &std::as_const(half)}) {
        SweepColumns columns(w);
        columns.build(mesh, faces, pad);
        std::vector<Index> listed;
        if (faces) listed = *faces;
        else
          for (Index f = 0; f < mesh.face_count(); ++f) listed.push_back(f);
        for (const Vec3& p : points) {
          const Vec3 at = columns.frame(p);
          const double length = reach(rng) < 0.2 ? 0.0 : 20.0 * reach(rng);
          FrameBox path;
          path.lo = at;
          path.hi = Vec3(at[0], at[1], at[2] + length);
          std::set<Index> visited;
          EXPECT_FALSE(columns.any_along(at[0], at[1], at[2], at[2] + length, [&](Index f) {
            visited.insert(f);
            return false;
          }));
          for (Index f : listed)
            if (meets(columns, mesh, f, path, pad)) EXPECT_TRUE(visited.count(f)) << "face " << f << " missed";
          for (Index f : visited) EXPECT_TRUE(meets(columns, mesh, f, path, slack)) << "face " << f << " far off";
          // A box about the point: some face meets it grown by the pad, exactly when any_in says so
          // (up to the rounding outwards).
          FrameBox box;
          const double r = reach(rng) < 0.2 ? 0.0 : reach(rng);
          box.lo = at.array() - r;
          box.hi = at.array() + r;
          bool near = false, near_slack = false;
          for (Index f : listed) {
            near = near || meets(columns, mesh, f, box, pad);
            near_slack = near_slack || meets(columns, mesh, f, box, slack);
          }
          const bool found = columns.any_in(box);
          if (near) EXPECT_TRUE(found);
          if (found) EXPECT_TRUE(near_slack);
        }
      }
  }
}

TEST(SweepColumns, FacesWithCornersBeyondFloatOrNotFiniteArePassedOnWhereverTheyMayReach) {
  // A corner that is not a number (its faces reach everywhere), one at infinity and one beyond
  // float's range (their boxes reach that far): every face whose box, grown, holds a path is passed
  // on, and nothing fails.
  for (const double odd : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), 1e300}) {
    TriangleMesh mesh = make_grid_patch(8, 0.0, 4.0, 0.0, 4.0, [](double u, double v) { return Vec3(u, v, 0.0); });
    mesh.positions[10].x() = odd;
    const double pad = 1e-3;
    SweepColumns columns(Vec3(0.1, 0.2, 0.9).normalized());
    columns.build(mesh, nullptr, pad);
    for (const Vec3& p : {Vec3(1.0, 1.0, 0.0), Vec3(3.3, 0.2, 0.0), Vec3(-50.0, 7.0, 1.0), Vec3(60.0, 1.0, 0.0)}) {
      const Vec3 at = columns.frame(p);
      FrameBox path;
      path.lo = Vec3(at[0], at[1], at[2] - 1.0);
      path.hi = Vec3(at[0], at[1], at[2] + 1.0);
      std::set<Index> visited;
      columns.any_along(at[0], at[1], path.lo[2], path.hi[2], [&](Index f) {
        visited.insert(f);
        return false;
      });
      bool reached = false;
      for (Index f = 0; f < mesh.face_count(); ++f) {
        const FrameBox b = columns.box_of(mesh, f);
        const bool nan = !(b.lo.array() == b.lo.array()).all() || !(b.hi.array() == b.hi.array()).all();
        if (nan || meets(columns, mesh, f, path, pad)) {
          reached = true;
          EXPECT_TRUE(visited.count(f)) << "face " << f << " with a corner at " << odd;
        }
      }
      if (reached) EXPECT_TRUE(columns.any_in(path));
    }
    FrameBox not_a_box;
    not_a_box.lo = not_a_box.hi = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    EXPECT_FALSE(columns.any_in(not_a_box));
  }
}

TEST(SweepColumns, NoFacesPassOnNothing) {
  const TriangleMesh mesh = make_icosphere(1.0, 1);
  SweepColumns columns(Vec3::UnitZ());
  const std::vector<Index> none;
  columns.build(mesh, &none, 1e-3);
  FrameBox box;
  box.lo = Vec3::Constant(-10.0);
  box.hi = Vec3::Constant(10.0);
  EXPECT_FALSE(columns.any_in(box));
  EXPECT_FALSE(columns.any_along(0.0, 0.0, -10.0, 10.0, [](Index) { return true; }));
}

} // namespace
} // namespace st
