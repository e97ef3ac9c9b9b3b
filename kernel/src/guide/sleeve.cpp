#include "st/guide/sleeve.h"

#include "detail/format.h"
#include "st/core/closest_point.h"
#include "st/core/errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace st {

Vec3 tube_axis(const TubeSpec& tube) { return -tube.direction.normalized(); }

Vec3 tube_point(const TubeSpec& tube, double z) { return tube.entry + z * tube_axis(tube); }

Cylinder tube_cylinder(const TubeSpec& tube, double radius, double z0, double z1) {
  return {tube_point(tube, z0), tube_axis(tube), radius, z1 - z0};
}

void orthonormal_frame(const Vec3& axis, Vec3& u, Vec3& v) {
  // The coordinate axis least aligned with `axis` seeds the frame.
  Vec3 seed = Vec3::UnitX();
  if (std::abs(axis.y()) < std::abs(axis[0]) && std::abs(axis.y()) <= std::abs(axis.z())) seed = Vec3::UnitY();
  else if (std::abs(axis.z()) < std::abs(axis[0]) && std::abs(axis.z()) < std::abs(axis.y())) seed = Vec3::UnitZ();
  u = (seed - seed.dot(axis) * axis).normalized();
  v = axis.cross(u);
}

int circle_segments(double radius, double chordal_tolerance) {
  if (!(radius > 0.0) || !(chordal_tolerance > 0.0)) return 8;
  // A chord of angle a deviates radius * (1 - cos(a / 2)) from the circle.
  const double ratio = std::clamp(1.0 - chordal_tolerance / radius, -1.0, 1.0);
  const double angle = 2.0 * std::acos(ratio);
  if (!(angle > 0.0)) return 1024;
  return std::clamp(static_cast<int>(std::ceil(2.0 * std::numbers::pi / angle)), 8, 1024);
}

namespace {

void check_cylinder(const Cylinder& c, double chordal_tolerance) {
  if (!c.base.allFinite() || !c.axis.allFinite() || c.axis.norm() < 1e-12)
    throw InvalidInput("cylinder: base and axis must be finite, the axis non-zero");
  if (!(c.radius > 0.0) || !(c.height > 0.0) || !std::isfinite(c.radius) || !std::isfinite(c.height))
    throw InvalidInput("cylinder: radius and height must be finite and > 0");
  if (!(chordal_tolerance > 0.0)) throw InvalidInput("cylinder: the chordal tolerance must be > 0");
}

} // namespace

TriangleMesh cylinder_mesh(const Cylinder& c, double chordal_tolerance, bool circumscribed) {
  check_cylinder(c, chordal_tolerance);
  const Vec3 axis = c.axis.normalized();
  Vec3 u, v;
  orthonormal_frame(axis, u, v);
  const int n = circle_segments(c.radius, chordal_tolerance);
  const Vec3 top = c.base + c.height * axis;
  const double corner_radius = circumscribed ? c.radius / std::cos(std::numbers::pi / n) : c.radius;

  TriangleMesh mesh;
  mesh.positions.reserve(2 * n + 2);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    const Vec3 r = corner_radius * (std::cos(a) * u + std::sin(a) * v);
    mesh.positions.push_back(c.base + r);
    mesh.positions.push_back(top + r);
  }
  const Index bottom_centre = static_cast<Index>(mesh.positions.size());
  mesh.positions.push_back(c.base);
  mesh.positions.push_back(top);
  const Index top_centre = bottom_centre + 1;
  for (int i = 0; i < n; ++i) {
    const Index b0 = 2 * i, t0 = 2 * i + 1;
    const Index b1 = 2 * ((i + 1) % n), t1 = b1 + 1;
    // Counter-clockwise around the axis seen from the top; sides face outward.
    mesh.triangles.push_back({b0, b1, t1});
    mesh.triangles.push_back({b0, t1, t0});
    mesh.triangles.push_back({top_centre, t0, t1});
    mesh.triangles.push_back({bottom_centre, b1, b0});
  }
  return mesh;
}

TriangleMesh footed_cylinder_mesh(const Cylinder& c, double chordal_tolerance,
                                  const std::function<double(const Vec3&)>& foot) {
  check_cylinder(c, chordal_tolerance);
  const Vec3 axis = c.axis.normalized();
  Vec3 u, v;
  orthonormal_frame(axis, u, v);
  const int n = circle_segments(c.radius, chordal_tolerance);
  // Rings about as far apart as the points around the rim.
  const double spacing = 2.0 * std::numbers::pi * c.radius / n;
  const int rings = std::clamp(static_cast<int>(std::ceil(c.radius / spacing)), 1, 64);
  auto lift = [&](const Vec3& p) { return std::clamp(foot(p), 0.0, 0.99 * c.height); };

  TriangleMesh mesh;
  const Index centre = 0;
  mesh.positions.push_back(c.base + lift(c.base) * axis);
  auto ring_vertex = [&](int j, int i) { return static_cast<Index>(1 + (j - 1) * n + (i % n)); };
  for (int j = 1; j <= rings; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * std::numbers::pi * i / n;
      const Vec3 p = c.base + (c.radius * j / rings) * (std::cos(a) * u + std::sin(a) * v);
      mesh.positions.push_back(p + lift(p) * axis);
    }
  const Index top0 = mesh.vertex_count();
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    mesh.positions.push_back(c.base + c.height * axis + c.radius * (std::cos(a) * u + std::sin(a) * v));
  }
  const Index top_centre = mesh.vertex_count();
  mesh.positions.push_back(c.base + c.height * axis);
  for (int i = 0; i < n; ++i) {
    // Bottom, facing down: clockwise seen from the top.
    mesh.triangles.push_back({centre, ring_vertex(1, i + 1), ring_vertex(1, i)});
    for (int j = 1; j < rings; ++j) {
      const Index a = ring_vertex(j, i), b = ring_vertex(j + 1, i), cc = ring_vertex(j + 1, i + 1),
                  d = ring_vertex(j, i + 1);
      mesh.triangles.push_back({a, d, cc});
      mesh.triangles.push_back({a, cc, b});
    }
    // Side and top.
    const Index b0 = ring_vertex(rings, i), b1 = ring_vertex(rings, i + 1);
    const Index t0 = top0 + i, t1 = top0 + (i + 1) % n;
    mesh.triangles.push_back({b0, b1, t1});
    mesh.triangles.push_back({b0, t1, t0});
    mesh.triangles.push_back({top_centre, t0, t1});
  }
  return mesh;
}

Vec3 pin_direction(const TubeSpec& tube, const AabbTree& bone, double radius) {
  const auto [sum, area] = bone.area_normal_near(tube.entry, radius);
  const std::string name = "tube '" + tube.name + "'";
  if (!(area > 0.0))
    throw GeometryError(name + ": no direction is planned and no bone lies within " + detail::mm(radius) +
                        " of its entry " + detail::where(tube.entry) + "; give its direction");
  if (sum.norm() < 0.2 * area)
    throw GeometryError(name + ": no direction is planned and the bone within " + detail::mm(radius) +
                        " of its entry " + detail::where(tube.entry) +
                        " faces every way (an edge or a crest); give its direction");
  return -sum.normalized();
}

void direct_pins(std::vector<TubeSpec>& tubes, const std::function<const AabbTree&()>& bone_tree) {
  for (TubeSpec& t : tubes) {
    if (!t.auto_direction) continue;
    t.direction = pin_direction(t, bone_tree(), std::max(3.0, 2.0 * t.outer_radius));
    t.auto_direction = false;
  }
}

} // namespace st
