#include "guide/label_guide.h"

#include "detail/format.h"
#include "guide/seat.h"
#include "st/core/aabb_tree.h"
#include "st/core/errors.h"
#include "st/core/predicates.h"
#include "st/boolean/triangle_intersection.h"
#include "st/guide/inspect.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <unordered_map>

namespace st::guide_detail {

namespace {

/// A planned point may lie this far from the template, mm.
constexpr double kMaxLabelDistance_mm = 5.0;
/// An engraving starts this far above the surface (so that it cuts the surface cleanly), mm.
constexpr double kEngraveLift_mm = 0.5;
/// An embossing stands on a foot this far into the wall (at most half the wall), mm.
constexpr double kEmbossSink_mm = 0.3;
/// Added to a label's depth (beyond what the surface's shape between the text's vertices needs), mm:
/// the Boolean operation and the output's float coordinates move surfaces by up to about 1e-3 mm.
constexpr double kLabelDepthMargin_mm = 0.005;
/// Over a label's top, this far along its normal, nothing of the template may lie, mm.
constexpr double kLabelSky_mm = 2.0;
/// An engraving's floor stays at least this far over the template's inner surface, whatever the
/// thickness asked for (the wall check, options.thickness, asks more when it is given), mm.
constexpr double kMinFloorWall_mm = 0.2;
/// The outer surface under a label may turn this far from the label's normal (cos 60 degrees).
constexpr double kMinSurfaceCosine = 0.5;
/// The wall left under an engraving may fall this fraction of the thickness short of
/// thickness - depth: the outer surface is a distance-field offset, not exact.
constexpr double kWallTolerance = 0.05;

GeometryError label_error(const LabelSpec& label, const std::string& what, const Vec3& where, const std::string& fix) {
  return GeometryError("label '" + label.name + "': " + what + " near " + detail::where(where) + "; " + fix);
}

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

double length2(const Point2& a, const Point2& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1];
  return dx * dx + dy * dy;
}

/// Splits every edge longer than `spacing` at its middle, in both triangles beside it (red-green
/// refinement: one, two or three split edges of a triangle give two, three or four triangles), until
/// none is longer. The boundary's edges are split with them.
void refine(TextCap& cap, double spacing) {
  const double limit2 = spacing * spacing;
  for (int round = 0;; ++round) {
    if (round > 60) throw GeometryError("label: its text could not be refined (degenerate outline)");
    std::unordered_map<std::uint64_t, Index> middle;
    auto split = [&](Index a, Index b) {
      const auto [it, fresh] = middle.try_emplace(edge_key(a, b), static_cast<Index>(cap.points.size()));
      if (fresh) {
        const Point2 pa = cap.points[a], pb = cap.points[b];
        cap.points.push_back({0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])});
      }
      return it->second;
    };
    auto too_long = [&](Index a, Index b) { return length2(cap.points[a], cap.points[b]) > limit2; };
    std::vector<std::array<Index, 3>> next;
    next.reserve(cap.triangles.size() * 2);
    bool changed = false;
    for (const auto& t : cap.triangles) {
      const std::array<bool, 3> mark{too_long(t[0], t[1]), too_long(t[1], t[2]), too_long(t[2], t[0])};
      const int count = mark[0] + mark[1] + mark[2];
      if (count == 0) {
        next.push_back(t);
        continue;
      }
      changed = true;
      if (count == 3) {
        const Index m0 = split(t[0], t[1]), m1 = split(t[1], t[2]), m2 = split(t[2], t[0]);
        next.insert(next.end(), {{t[0], m0, m2}, {m0, t[1], m1}, {m2, m1, t[2]}, {m0, m1, m2}});
        continue;
      }
      // Rotate so that the split edges are (v0, v1) (and (v1, v2) when two are).
      int r = 0;
      if (count == 1) r = mark[0] ? 0 : mark[1] ? 1 : 2;
      else r = !mark[2] ? 0 : !mark[0] ? 1 : 2; // the unsplit edge becomes (v2, v0)
      const Index v0 = t[r], v1 = t[(r + 1) % 3], v2 = t[(r + 2) % 3];
      const Index m0 = split(v0, v1);
      if (count == 1) {
        next.insert(next.end(), {{v0, m0, v2}, {m0, v1, v2}});
        continue;
      }
      const Index m1 = split(v1, v2);
      next.push_back({m0, v1, m1});
      if (length2(cap.points[v0], cap.points[m1]) <= length2(cap.points[m0], cap.points[v2]))
        next.insert(next.end(), {{v0, m0, m1}, {v0, m1, v2}});
      else next.insert(next.end(), {{v0, m0, v2}, {m0, m1, v2}});
    }
    if (!changed) return;
    cap.triangles = std::move(next);
    std::vector<std::array<Index, 2>> boundary;
    for (const auto& [a, b] : cap.boundary) {
      const auto it = middle.find(edge_key(a, b));
      if (it == middle.end()) {
        boundary.push_back({a, b});
      } else {
        boundary.push_back({a, it->second});
        boundary.push_back({it->second, b});
      }
    }
    cap.boundary = std::move(boundary);
  }
}

/// Flips the edges (never the outline's) across which two triangles make a convex quad and face angles
/// summing over 180 degrees, until none is left (Lawson's flips to a constrained Delaunay
/// triangulation): ear clipping leaves slivers that float rounding could fold over.
void delaunay_flips(TextCap& cap) {
  std::unordered_map<std::uint64_t, int> outline;
  for (const auto& [a, b] : cap.boundary) outline[edge_key(a, b)] = 1;
  auto angle = [&](Index at, Index p, Index q) {
    const Point2 &o = cap.points[at], &u = cap.points[p], &v = cap.points[q];
    return std::atan2(std::abs((u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0])),
                      (u[0] - o[0]) * (v[0] - o[0]) + (u[1] - o[1]) * (v[1] - o[1]));
  };
  auto ccw = [&](Index a, Index b, Index c) {
    return orient2d(cap.points[a].data(), cap.points[b].data(), cap.points[c].data()) > 0;
  };
  for (int pass = 0; pass < 100; ++pass) {
    std::unordered_map<std::uint64_t, std::pair<std::size_t, int>> seen; // edge -> (triangle, corner)
    std::vector<std::uint8_t> touched(cap.triangles.size(), 0);
    bool flipped = false;
    for (std::size_t t = 0; t < cap.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Index a = cap.triangles[t][k], b = cap.triangles[t][(k + 1) % 3];
        const std::uint64_t key = edge_key(a, b);
        if (outline.count(key)) continue;
        const auto [it, fresh] = seen.try_emplace(key, t, k);
        if (fresh) continue;
        const std::size_t u = it->second.first;
        if (touched[t] || touched[u]) continue;
        const Index c = cap.triangles[t][(k + 2) % 3];
        const auto& tu = cap.triangles[u];
        const Index d = tu[(it->second.second + 2) % 3];
        if (c == d || angle(c, a, b) + angle(d, a, b) <= std::numbers::pi + 1e-9) continue;
        if (!ccw(a, d, c) || !ccw(d, b, c)) continue; // not a convex quad
        cap.triangles[t] = {a, d, c};
        cap.triangles[u] = {d, b, c};
        touched[t] = touched[u] = 1;
        flipped = true;
      }
    if (!flipped) return;
  }
}

/// Groups of polygons whose boxes do not overlap (their solids can share one mesh).
std::vector<std::vector<LabelPolygon>> disjoint_groups(const std::vector<LabelPolygon>& polygons) {
  struct Box {
    double x0, y0, x1, y1;
  };
  auto box_of = [](const LabelPolygon& p) {
    Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const auto& loop : p.loops)
      for (const Point2& q : loop) {
        b.x0 = std::min(b.x0, q[0]), b.y0 = std::min(b.y0, q[1]);
        b.x1 = std::max(b.x1, q[0]), b.y1 = std::max(b.y1, q[1]);
      }
    return b;
  };
  std::vector<std::vector<LabelPolygon>> groups;
  std::vector<std::vector<Box>> boxes;
  for (const LabelPolygon& p : polygons) {
    const Box b = box_of(p);
    std::size_t g = 0;
    for (; g < groups.size(); ++g)
      if (std::none_of(boxes[g].begin(), boxes[g].end(),
                       [&](const Box& o) { return b.x0 <= o.x1 && o.x0 <= b.x1 && b.y0 <= o.y1 && o.y0 <= b.y1; }))
        break;
    if (g == groups.size()) groups.emplace_back(), boxes.emplace_back();
    groups[g].push_back(p);
    boxes[g].push_back(b);
  }
  return groups;
}

} // namespace

TextCap text_cap(const LabelSpec& label, const std::vector<LabelPolygon>& polygons, double spacing) {
  TextCap cap;
  for (std::size_t g = 0; g < polygons.size(); ++g) {
    std::vector<Point2> points;
    std::vector<std::vector<Index>> loops;
    for (std::size_t k = 0; k < polygons[g].loops.size(); ++k) {
      std::vector<Index> loop;
      const auto& given = polygons[g].loops[k];
      for (std::size_t i = 0; i < given.size(); ++i) {
        if (!std::isfinite(given[i][0]) || !std::isfinite(given[i][1]))
          throw InvalidInput("label '" + label.name + "': its outline has a point that is not finite");
        if (!loop.empty() && points.back() == given[i]) continue;
        loop.push_back(static_cast<Index>(points.size()));
        points.push_back(given[i]);
      }
      while (loop.size() > 1 && points[loop.back()] == points[loop.front()]) loop.pop_back();
      if (loop.size() < 3)
        throw GeometryError("label '" + label.name + "': loop " + std::to_string(k) + " of its outline's region " +
                            std::to_string(g) + " has fewer than 3 points");
      const double area = loop_area2(points, loop);
      if ((k == 0) != (area > 0.0)) std::reverse(loop.begin(), loop.end());
      loops.push_back(std::move(loop));
    }
    if (loops.empty()) continue;
    const auto base = static_cast<Index>(cap.points.size());
    for (const auto& loop : loops)
      for (std::size_t i = 0; i < loop.size(); ++i)
        cap.boundary.push_back({base + loop[i], base + loop[(i + 1) % loop.size()]});
    auto filled = fill_polygon(points, loops);
    if (!filled)
      throw GeometryError("label '" + label.name + "': region " + std::to_string(g) +
                          " of its text's outline is not a polygon with holes (loops cross or touch)");
    for (auto& t : *filled) cap.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    cap.points.insert(cap.points.end(), points.begin(), points.end());
  }
  delaunay_flips(cap);
  refine(cap, spacing);
  delaunay_flips(cap);
  return cap;
}

LaidLabel lay_label(const LabelSpec& label, const TriangleMesh& shell, std::size_t inner_faces,
                    const LabelObstacles& obstacles, const GuideOptions& options) {
  // The label's numbers were checked by build_guide.
  if (label.outlines.empty())
    throw InvalidInput("label '" + label.name +
                       "': its text has no outlines (they are made with OpenCASCADE's fonts, st/occt/occt_text.h)");
  // The shell's faces (all, and the inner ones) whose boxes meet `box`.
  auto faces_in = [&](const BoundingBox& box) {
    std::pair<std::vector<Index>, std::vector<Index>> found;
    for (Index f : faces_meeting_box(shell, box)) (f < inner_faces ? found.second : found.first).push_back(f);
    found.first.insert(found.first.end(), found.second.begin(), found.second.end());
    return found;
  };
  // First the shell around `at`: its nearest point, the outer surface over it, the normal around it.
  const double radius = std::max(1.0, 0.25 * label.height);
  const double outward = kMaxLabelDistance_mm + std::max(options.thickness, 1.0) + 1.0;
  BoundingBox around_at;
  around_at.extend(label.at);
  const AabbTree local(shell, faces_in(around_at.inflated(outward + radius)).first);
  LaidLabel laid;
  LabelPlacement& p = laid.placement;
  p.name = label.name;
  p.text = label.text;
  p.mode = label.mode;

  // The frame: the nearest point of the outer surface, the outward normal averaged around it.
  const auto nearest = local.empty() ? std::nullopt : local.closest_point(label.at, kMaxLabelDistance_mm);
  if (!nearest)
    throw label_error(label, "its point lies more than " + detail::mm(kMaxLabelDistance_mm) + " from the template",
                      label.at, "put it on the template's outer surface");
  p.origin = nearest->point;
  Index face = nearest->face;
  if (face < inner_faces) {
    // A point on the bone side (the bone under the guide, say): the outer surface over it, straight out.
    const Vec3 out = -triangle_normal(shell, face).normalized();
    std::optional<RayHit> over;
    for (double t = 0.0; !over;) {
      const auto hit = local.first_hit(label.at, out, t, outward);
      if (!hit) break;
      if (hit->face >= inner_faces) over = hit;
      t = hit->t + 1e-9;
    }
    if (!over)
      throw label_error(label, "its point is nearest the template's inner surface and no outer surface lies over it",
                        label.at, "put it on the outer surface");
    p.origin = over->point;
    face = over->face;
  }
  const Vec3 n0 = triangle_normal(shell, face).normalized();
  Vec3 sum = Vec3::Zero();
  BoundingBox around;
  around.extend(p.origin);
  local.for_each_in_box(around.inflated(radius), [&](Index f) {
    if (f < inner_faces) return;
    const Triangle& t = shell.triangles[f];
    const Vec3 q =
        closest_point_on_triangle(p.origin, shell.positions[t[0]], shell.positions[t[1]], shell.positions[t[2]]);
    const Vec3 normal = triangle_normal(shell, f);
    if ((q - p.origin).norm() <= radius && normal.dot(n0) > 0.0) sum += normal;
  });
  p.normal = sum.norm() > 0.0 ? sum.normalized() : n0;
  const Vec3 up = label.up.normalized();
  p.up = up - up.dot(p.normal) * p.normal;
  if (p.up.norm() < std::sin(15.0 * std::numbers::pi / 180.0)) // within 15 degrees of the normal
    throw label_error(label, "its up direction runs along the surface's normal", p.origin,
                      "give an up direction along the surface");
  p.up.normalize();
  p.right = p.up.cross(p.normal);

  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& polygon : label.outlines)
    for (const auto& loop : polygon.loops)
      for (const Point2& q : loop)
        x0 = std::min(x0, q[0]), x1 = std::max(x1, q[0]), y0 = std::min(y0, q[1]), y1 = std::max(y1, q[1]);
  p.width = x1 - x0;
  p.text_height = y1 - y0;
  // Then the shell over and under the text's footprint in its frame: its rays run `window` over and
  // under the origin, its sky and its floor's wall check a little further.
  double reach = 0.0;
  for (const double x : {x0, x1})
    for (const double y : {y0, y1}) reach = std::max(reach, std::hypot(x, y));
  const double window = 2.0 + reach;
  BoundingBox footprint;
  for (const double x : {x0 - 1.0, x1 + 1.0})
    for (const double y : {y0 - 1.0, y1 + 1.0})
      for (const double z : {-window - std::max(options.thickness, 1.0) - 1.0, window + kLabelSky_mm + 1.0})
        footprint.extend(p.origin + x * p.right + y * p.up + z * p.normal);
  auto [near, near_inner] = faces_in(footprint);
  const AabbTree shell_tree(shell, std::move(near));
  const std::optional<AabbTree> inner_tree =
      near_inner.empty() ? std::nullopt : std::optional<AabbTree>(std::in_place, shell, std::move(near_inner));
  p.depth = label.depth;
  p.min_wall = std::numeric_limits<double>::infinity();
  p.min_clearance = std::numeric_limits<double>::infinity();
  p.top = -std::numeric_limits<double>::infinity();
  double low = std::numeric_limits<double>::infinity(), high = -low;

  for (const auto& group : disjoint_groups(label.outlines)) {
    const TextCap cap = text_cap(label, group, kLabelSpacing_mm);
    const auto count = static_cast<Index>(cap.points.size());
    std::vector<double> surface(count), below(count);
    auto plane_point = [&](Index i) { return p.origin + cap.points[i][0] * p.right + cap.points[i][1] * p.up; };
    // Each point of the text carried down the normal onto the outer surface.
    for (Index i = 0; i < count; ++i) {
      const Vec3 at = plane_point(i), from = at + window * p.normal;
      const auto first = shell_tree.first_hit(from, -p.normal, 0.0, 2.0 * window);
      if (!first) throw label_error(label, "it runs off the template", at, "move it or make the text smaller");
      const Vec3 normal = triangle_normal(shell, first->face).normalized();
      if (first->face < inner_faces || normal.dot(p.normal) <= 0.0)
        throw label_error(label, "the template's inner surface or another part of it lies over it", at,
                          "move it onto open outer surface");
      if (normal.dot(p.normal) < kMinSurfaceCosine)
        throw label_error(label, "the outer surface under it turns more than 60 degrees from its normal", at,
                          "move it to a flatter place or make the text shorter");
      const auto exit = shell_tree.first_hit(from, -p.normal, first->t + 1e-9);
      surface[i] = window - first->t;
      below[i] = exit ? window - exit->t : -std::numeric_limits<double>::infinity();
      low = std::min(low, surface[i]), high = std::max(high, surface[i]);
    }
    // Neighbours on one surface: no step between them steeper than the surface may turn.
    for (const auto& t : cap.triangles)
      for (int k = 0; k < 3; ++k) {
        const Index a = t[k], b = t[(k + 1) % 3];
        if (std::abs(surface[a] - surface[b]) > 2.0 * std::sqrt(length2(cap.points[a], cap.points[b])) + 0.05)
          throw label_error(label, "the outer surface under it steps (an edge, or another part of the template)",
                            plane_point(a), "move it onto one smooth part of the outer surface");
      }

    // Between its vertices the text's floor (top) is flat, the outer surface is not: how far the surface
    // falls under (rises over) the flat interpolation at the triangles' middles and edges' middles is
    // added to the depth (height), so that it holds everywhere, not only at the vertices.
    double short_by = 0.0;
    for (const auto& t : cap.triangles)
      for (int k = 0; k < 4; ++k) {
        const std::array<double, 3> w =
            k == 3 ? std::array<double, 3>{1.0 / 3, 1.0 / 3, 1.0 / 3}
                   : std::array<double, 3>{k == 0 ? 0.0 : 0.5, k == 1 ? 0.0 : 0.5, k == 2 ? 0.0 : 0.5};
        Point2 q{0.0, 0.0};
        double flat = 0.0;
        for (int c = 0; c < 3; ++c) {
          q[0] += w[c] * cap.points[t[c]][0], q[1] += w[c] * cap.points[t[c]][1];
          flat += w[c] * surface[t[c]];
        }
        const Vec3 from = p.origin + q[0] * p.right + q[1] * p.up + window * p.normal;
        if (const auto hit = shell_tree.first_hit(from, -p.normal, 0.0, 2.0 * window)) {
          const double there = window - hit->t;
          short_by = std::max(short_by, label.mode == LabelMode::engrave ? flat - there : there - flat);
        }
      }
    const double extra = short_by + kLabelDepthMargin_mm;

    TriangleMesh solid;
    solid.positions.resize(2 * static_cast<std::size_t>(count));
    for (Index i = 0; i < count; ++i) {
      double bottom = surface[i] - label.depth - extra, top = surface[i] + kEngraveLift_mm;
      if (label.mode == LabelMode::emboss) {
        top = surface[i] + label.depth + extra;
        bottom = surface[i] - std::min(kEmbossSink_mm, 0.5 * (surface[i] - below[i]));
      }
      if (label.mode == LabelMode::engrave && bottom <= below[i] + kMinFloorWall_mm)
        throw label_error(label, "the engraving would cut through the template's wall",
                          plane_point(i) + surface[i] * p.normal,
                          "move it away from the template's rim or engrave less deep");
      solid.positions[i] = plane_point(i) + bottom * p.normal;
      solid.positions[count + i] = plane_point(i) + top * p.normal;
      if (label.mode == LabelMode::engrave)
        if (const auto wall = inner_tree ? inner_tree->closest_point(solid.positions[i]) : std::nullopt)
          p.min_wall = std::min(p.min_wall, wall->distance);
    }
    auto close_prism = [&](TriangleMesh& prism) {
      for (const auto& t : cap.triangles) {
        prism.triangles.push_back({count + t[0], count + t[1], count + t[2]});
        prism.triangles.push_back({t[0], t[2], t[1]});
      }
      for (const auto& [a, b] : cap.boundary) {
        prism.triangles.push_back({a, b, count + b});
        prism.triangles.push_back({a, count + b, count + a});
      }
    };
    close_prism(solid);
    // Open sky over the text: no part of the template within kLabelSky_mm over the label's top
    // (exact triangle tests against the prism standing there).
    TriangleMesh sky;
    sky.positions.resize(solid.positions.size());
    for (Index i = 0; i < count; ++i) {
      sky.positions[i] = solid.positions[count + i];
      sky.positions[count + i] = solid.positions[count + i] + kLabelSky_mm * p.normal;
      p.top = std::max(p.top, (solid.positions[count + i] - p.origin).dot(p.normal));
    }
    close_prism(sky);
    for (Index f = 0; f < sky.face_count(); ++f) {
      const Triangle& t = sky.triangles[f];
      shell_tree.for_each_in_box(triangle_box(sky, f), [&](Index g) {
        const Triangle& u = shell.triangles[g];
        if (triangles_intersect(sky.positions[t[0]], sky.positions[t[1]], sky.positions[t[2]], shell.positions[u[0]],
                                shell.positions[u[1]], shell.positions[u[2]]))
          throw label_error(label, "another part of the template lies over it", sky.positions[t[0]],
                            "move it onto open outer surface");
      });
    }

    // Clear of the sleeves and bores (their axes, outer radius) and the slots' housings.
    for (const Vec3& v : solid.positions) {
      for (std::size_t k = 0; k < obstacles.tubes.size(); ++k) {
        const TubeSpec& tube = obstacles.tubes[k];
        const TubePlacement& tp = obstacles.tube_places[k];
        const double r = std::max(tube.outer_radius, tube.counterbore ? tube.counterbore->radius : 0.0);
        const double d =
            segment_segment_distance(v, v, tube_point(tube, tp.bore_bottom), tube_point(tube, tp.bore_top)) - r;
        p.min_clearance = std::min(p.min_clearance, d);
        if (d < kLabelClearance_mm)
          throw label_error(label, "it comes within " + detail::mm(kLabelClearance_mm) + " of tube '" + tube.name + "'",
                            v, "move it or make the text smaller");
      }
      for (std::size_t k = 0; k < obstacles.slots.size(); ++k) {
        const SlotPlacement& sp = obstacles.slot_places[k];
        const SlotFrame f = slot_frame(obstacles.slots[k]);
        const Vec3 q = v - f.origin;
        const double half = 0.5 * sp.width + obstacles.slots[k].wall;
        const double e0 = std::min(sp.housing_start, sp.slot_start), e1 = std::max(sp.housing_end, sp.slot_end);
        const double z = q.dot(f.up()), e = q.dot(f.e);
        const double da = std::max(0.0, std::abs(q.dot(f.n)) - half);
        const double de = std::max({0.0, e0 - e, e - e1}), dz = std::max({0.0, sp.cut_bottom - z, z - sp.cut_top});
        const double d = std::sqrt(da * da + de * de + dz * dz);
        p.min_clearance = std::min(p.min_clearance, d);
        if (d < kLabelClearance_mm)
          throw label_error(
              label, "it comes within " + detail::mm(kLabelClearance_mm) + " of slot '" + obstacles.slots[k].name + "'",
              v, "move it or make the text smaller");
      }
    }
    laid.solids.push_back(rounded(std::move(solid)));
  }
  p.surface_rise = high - low;
  if (label.mode == LabelMode::engrave && options.thickness > 0.0) {
    const double need = options.thickness - label.depth;
    if (p.min_wall < need - kWallTolerance * options.thickness)
      throw label_error(label,
                        "the engraving would leave " + detail::mm(p.min_wall) + " of wall under it (at least " +
                            detail::mm(need) + ", thickness - depth, is needed)",
                        p.origin, "move it away from the template's rim or engrave less deep");
  }
  if (label.mode == LabelMode::emboss) p.min_wall = 0.0;
  return laid;
}

} // namespace st::guide_detail
