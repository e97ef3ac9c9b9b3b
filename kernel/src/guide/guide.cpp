#include "st/guide/guide.h"
#include "detail/timing.h"

#include "st/core/aabb_tree.h"
#include "st/boolean/boolean.h"
#include "st/core/errors.h"
#include "st/core/ray_triangle.h"
#include "st/core/union_find.h"
#include "st/guide/sleeve.h"
#include "st/boolean/triangle_intersection.h"

#include "detail/format.h"
#include "guide/guide_pieces.h"
#include "guide/label_guide.h"
#include "guide/seat.h"
#include "guide/slot_guide.h"
#include "st/guide/blade_path.h"
#include "st/guide/inspect.h"

#include <algorithm>
#include <cstdlib>
#include <array>
#include <limits>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

namespace st {

namespace {

using namespace guide_detail;
using detail::Clock;
using detail::seconds_since;

struct Sample {
  double radius = 0.0;
  double angle = 0.0;
  std::optional<double> enter, exit; // heights where the ray enters and leaves the template
};

// `near`: the faces of `shell` around the tube's axis stretch (faces_around).
TubePlacement place(const TubeSpec& tube, const TriangleMesh& shell, std::vector<Index> near,
                    const GuideOptions& options) {
  TubePlacement p;
  p.name = tube.name;
  p.kind = tube.kind;
  p.direction = tube.direction.normalized();
  p.sleeve_bottom = tube.offset;
  p.sleeve_top = tube.offset + tube.length;
  const Vec3 axis = tube_axis(tube);
  Vec3 u, v;
  orthonormal_frame(axis, u, v);
  const AxisStretch stretch = axis_stretch(tube, options);
  const double start = stretch.start, reach = stretch.reach, above = stretch.above;
  auto origin_of = [&](const Sample& s) -> Vec3 { // a Vec3, not an Eigen expression of temporaries
    return tube_point(tube, start) + s.radius * (std::cos(s.angle) * u + std::sin(s.angle) * v);
  };
  const AabbTree tree(shell, std::move(near));
  std::vector<Sample> samples;
  double roof = -std::numeric_limits<double>::infinity(); // the template's top over the bore, when above `start`
  constexpr int kAround = 16;
  for (double radius : {0.0, tube.inner_radius, tube.outer_radius})
    for (int k = 0; k < (radius == 0.0 ? 1 : kAround); ++k) {
      Sample s{radius, 2.0 * std::numbers::pi * k / kAround, {}, {}};
      if (!tree.empty())
        if (const auto first = tree.first_hit(origin_of(s), -axis, 0.0, reach)) {
          if (triangle_normal(shell, first->face).dot(-axis) < 0.0) { // entering the template
            s.enter = start - first->t;
            if (const auto second = tree.first_hit(origin_of(s), -axis, first->t + 1e-9, reach))
              s.exit = start - second->t;
          } else { // the ray starts inside the template's wall (the bore goes up to where it leaves it)
            s.enter = start;
            s.exit = start - first->t;
            if (s.radius <= tube.inner_radius) {
              const auto up = tree.first_hit(origin_of(s), axis, 0.0, above);
              roof = std::max(roof, start + (up ? up->t : 0.0));
            }
          }
        }
      samples.push_back(s);
    }
  std::optional<double> top, bottom, middle, bore, lowest_top, highest_bottom;
  bool all_hit = true;
  for (const Sample& s : samples) {
    if (!s.enter || !s.exit) {
      all_hit = false;
      continue;
    }
    top = std::max(top.value_or(-1e300), *s.enter);
    lowest_top = std::min(lowest_top.value_or(1e300), *s.enter);
    bottom = std::min(bottom.value_or(1e300), *s.exit);
    highest_bottom = std::max(highest_bottom.value_or(-1e300), *s.exit);
    middle = std::min(middle.value_or(1e300), 0.5 * (*s.enter + *s.exit));
    if (s.radius <= tube.inner_radius) bore = std::min(bore.value_or(1e300), *s.exit);
  }
  // The drill's way: every layer of template the bore's rays meet down to an outer radius (and a bore
  // radius and margin) below the entry is bored: a template wrapped around thin bone lies in the
  // drill's path on the far side.
  for (const Sample& s : samples) {
    if (s.radius > tube.inner_radius || !s.exit || tree.empty()) continue;
    double t = start - *s.exit;
    while (const auto hit = tree.first_hit(origin_of(s), -axis, t + 1e-9, reach)) {
      t = hit->t;
      const double z = start - t;
      if (z < -(tube.outer_radius + tube.inner_radius + options.bore_margin)) break;
      bore = std::min(bore.value_or(1e300), z);
    }
  }
  if (!top) {
    const AabbTree all(shell);
    const auto closest = all.closest_point(tube.entry);
    throw GeometryError("tube '" + tube.name + "' misses the template: no part of the sleeve (outer radius " +
                        detail::mm(tube.outer_radius) + ") lies over it; the template passes " +
                        (closest ? detail::mm(closest->distance) : std::string("far")) + " from the entry " +
                        detail::where(tube.entry));
  }
  // The column reaches down into the middle of the template wall (at the lowest sample, so it stands
  // in the template all around); its foot then rises over the bone under it (seat_foot). Not lower,
  // even where the sleeve is planned lower: below that the template body is the material, and
  // beyond the inner surface lie clearance and bone.
  const double column = *middle;
  std::vector<double> walls;
  for (const Sample& s : samples)
    if (s.enter && s.exit) walls.push_back(*s.enter - *s.exit);
  std::nth_element(walls.begin(), walls.begin() + walls.size() / 2, walls.end());
  p.foot_lift = std::min(0.1, 0.25 * walls[walls.size() / 2]);
  p.template_top = *top;
  p.template_bottom = *bottom;
  p.column_bottom = column;
  // No column when the sleeve's top is below the template's middle all around (or the sleeve lies
  // wholly between the template's surfaces): the template body is the sleeve's material there.
  p.sleeve_inside_template =
      column >= p.sleeve_top - 1e-6 || (all_hit && p.sleeve_top < *lowest_top && p.sleeve_bottom > *highest_bottom);
  p.bore_top = std::max({p.sleeve_top, p.template_top, roof}) + options.bore_margin;
  p.bore_bottom = bore.value_or(p.template_bottom) - options.bore_margin;
  return p;
}

// Seats a column whose foot (its first `foot_vertices` vertices) lies flat at height `floor`: every
// foot vertex rises to `above` over the highest bone over the foot triangles around it (so each foot
// triangle, whose corners all stand that high over the bone under it, stays clear of it), never by
// steps. False (the column left as it was) where bone reaches the sleeve's top under it: the column
// is then trimmed by the bone instead (trimmed()).
bool seat_foot(TriangleMesh& column, Index foot_vertices, const TubeSpec& tube, double floor, double ceiling,
               double above, const AabbTree& bone) {
  if (bone.empty()) return true;
  const Vec3 axis = tube_axis(tube);
  const std::vector<double> need = foot_needs(column, foot_vertices, tube.entry, axis, floor, ceiling, above, bone);
  for (Index v = 0; v < foot_vertices; ++v)
    if (need[v] > ceiling - 0.01 * tube.length) return false;
  for (Index v = 0; v < foot_vertices; ++v)
    if (need[v] > floor) column.positions[v] += (need[v] - floor) * axis;
  return true;
}

// A column under which the bone rises to the sleeve's top, trimmed by the bone: minus a block over a
// disk a little wider than the sleeve, from below the column up to a height field that stands
// `above` over the highest bone over each of its triangles (the same exact clipping as the foot),
// cut off above the sleeve's top. The sleeve keeps its axis; where the bone stands, it is notched.
TriangleMesh trimmed(const TriangleMesh& column, const TubeSpec& tube, double floor, double ceiling, double above,
                     double tolerance, const AabbTree& bone, int& perturbed) {
  const double radius = tube.outer_radius + std::max(0.5, 0.2 * tube.outer_radius);
  const double top = ceiling + 1.0, bottom = floor - 2.0;
  // A cylinder upside down: its foot grid is the block's top, at `top` until lowered onto the bone.
  Cylinder c;
  c.base = tube_point(tube, top);
  c.axis = -tube_axis(tube);
  c.radius = radius;
  c.height = top - bottom;
  TriangleMesh block = footed_cylinder_mesh(c, tolerance, [](const Vec3&) { return 0.0; });
  const Index ring = static_cast<Index>(circle_segments(radius, tolerance));
  const Index foot = block.vertex_count() - ring - 1;
  const std::vector<double> need =
      foot_needs(block, foot, tube.entry, tube_axis(tube), bottom, top, above, bone, -(top - bottom));
  for (Index v = 0; v < foot; ++v)
    block.positions[v] += (std::clamp(need[v], bottom + 1.0, top) - top) * tube_axis(tube);
  BooleanOptions o;
  o.check_operands = false;
  const BooleanResult r = mesh_boolean(column, rounded(std::move(block)), BooleanOp::Difference, o);
  perturbed += r.attempts > 1;
  if (r.mesh.empty()) throw conflict(tube, tube_point(tube, ceiling), "sleeve stands wholly in the bone");
  return r.mesh;
}

// What seat_foot makes sure of, checked exactly on the column as it will be written (float): no
// face of it meets the bone. One that does (rounding, or bone through the sleeve's side) is a
// conflict named by the tube and the place.
void check_clear_of_bone(const TriangleMesh& column, const TubeSpec& tube, const AabbTree& bone) {
  if (const auto meets = meets_bone(column, bone)) throw conflict(tube, *meets, "sleeve runs into the bone");
}

// The drill's way down the axis, from the sleeve's top to just past the entry, meets the bone's
// surface once: where it enters the bone (at the entry, or a little above an entry planned inside the
// bone). Two crossings or more (exact tests; crossings closer than 0.05 mm along the axis count as
// one, for duplicated sheets of a dirty mesh) mean bone in the bore above the template, a cusp or a
// lamina beside the entry: a conflict. The way runs 0.05 mm past the entry, so that an entry on the
// bone's surface (where the segment would only touch it) is one crossing for certain.
void check_bore_line(const TubeSpec& tube, double top, const AabbTree& bone) {
  if (!(top > 0.0)) return;
  constexpr double kPast = 0.05;
  const Vec3 axis = tube_axis(tube);
  const Vec3 from = tube_point(tube, top), to = tube_point(tube, -kPast);
  const TriangleMesh& mesh = bone.mesh();
  std::vector<std::pair<double, Vec3>> crossings; // distance from the top, where
  bone.any_along(from, -axis, top + kPast, 1e-6, [&](Index g) {
    const Triangle& t = mesh.triangles[g];
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    if (!segment_intersects_triangle(from, to, a, b, c)) return false;
    const auto hit = ray_triangle(from, -axis, a, b, c, 1e-6);
    crossings.emplace_back(hit ? hit->t : axis.dot(from - (a + b + c) / 3.0), a);
    return false;
  });
  std::sort(crossings.begin(), crossings.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  int distinct = 0;
  for (std::size_t i = 0; i < crossings.size(); ++i)
    if (i == 0 || crossings[i].first > crossings[i - 1].first + 0.05) ++distinct;
  if (distinct >= 2)
    throw conflict(tube, crossings.front().second,
                   "bore runs into the bone above the entry (between the sleeve's top and the entry)");
}

// Tubes whose paths (bore radius about the axis, from above the sleeve to the planned depth, 20 mm
// into the bone when none is planned) come within 1 mm of each other: a pin or drill would meet or
// weaken the other's hole.
void note_near_paths(const std::vector<TubeSpec>& tubes, std::vector<TubePlacement>& placements) {
  auto path_end = [&](std::size_t i) { return tube_point(tubes[i], -(tubes[i].depth > 0.0 ? tubes[i].depth : 20.0)); };
  for (std::size_t i = 0; i < tubes.size(); ++i)
    for (std::size_t j = i + 1; j < tubes.size(); ++j) {
      const double gap = segment_segment_distance(tube_point(tubes[i], placements[i].bore_top), path_end(i),
                                                  tube_point(tubes[j], placements[j].bore_top), path_end(j)) -
                         tubes[i].inner_radius - tubes[j].inner_radius;
      if (gap >= 1.0) continue;
      placements[i].near.push_back("tube '" + tubes[j].name + "' (" + detail::mm(std::max(gap, 0.0)) + ")");
      placements[j].near.push_back("tube '" + tubes[i].name + "' (" + detail::mm(std::max(gap, 0.0)) + ")");
    }
}

// Each slot's cut against the other slots' housings and cuts and the tubes' sleeves and bores: what
// it meets is reported (a slot through a sleeve weakens it; two slots crossing cut off a piece).
void note_slot_meetings(const std::vector<TubeSpec>& tubes, const std::vector<SlotSpec>& slots,
                        const std::vector<TriangleMesh>& housings, const GuideOptions& options, GuideResult& result) {
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const TriangleMesh cut = slot_cut(slots[i], result.slots[i]);
    for (std::size_t j = 0; j < tubes.size(); ++j) {
      const TubePlacement& t = result.tubes[j];
      const Cylinder c = tube_cylinder(tubes[j], tubes[j].outer_radius, std::min(t.bore_bottom, t.column_bottom),
                                       std::max(t.bore_top, t.sleeve_top));
      if (convex_solids_meet(cut, cylinder_mesh(c, options.chordal_tolerance, true)))
        result.slots[i].meets.push_back("tube '" + tubes[j].name + "'");
    }
    for (std::size_t j = 0; j < slots.size(); ++j)
      if (j != i && solids_cross(cut, housings[j])) result.slots[i].meets.push_back("slot '" + slots[j].name + "'");
  }
}

} // namespace

GuideResult add_tubes(const TriangleMesh& shell, std::size_t inner_faces, const TriangleMesh& bone,
                      const std::vector<TubeSpec>& tubes, const GuideOptions& options) {
  return build_guide(shell, inner_faces, bone, GuideParts{tubes, {}, {}}, options);
}

GuideResult build_guide(const TriangleMesh& shell, std::size_t inner_faces, const TriangleMesh& bone,
                        const GuideParts& parts, const GuideOptions& options) {
  std::vector<TubeSpec> tubes = parts.tubes;
  std::vector<SlotSpec> slots = parts.slots;
  // Pins planned by their entry only go into the bone there; so do slots planned by their plane only.
  if (options.bone_tree && !options.bone_tree->holds_all_of(bone))
    throw InvalidInput("guide: the bone tree given is not over all of the bone's faces");
  std::optional<AabbTree> all_bone;
  const auto whole_bone = [&]() -> const AabbTree& {
    if (options.bone_tree) return *options.bone_tree;
    if (!all_bone) all_bone.emplace(bone);
    return *all_bone;
  };
  direct_pins(tubes, whole_bone);
  for (const SlotSpec& s : slots) check_slot(s); // before the bone is asked about its plane
  direct_slots(slots, whole_bone);
  const auto t0 = Clock::now();
  if (!(options.chordal_tolerance > 0.0) || !(options.chordal_tolerance < 1.0))
    throw InvalidInput("chordal tolerance: must be in (0, 1) mm, got " + detail::number(options.chordal_tolerance));
  if (inner_faces > shell.face_count()) throw InvalidInput("inner faces: more than the shell has");
  GuideResult result;
  result.from_tube.assign(shell.face_count(), 0);
  if (tubes.empty() && slots.empty() && parts.labels.empty()) {
    result.mesh = shell;
    return result;
  }
  for (const TubeSpec& t : tubes) check_tube(t);
  for (const LabelSpec& l : parts.labels) check_label(l);

  auto note = [&](const BooleanResult& r) {
    result.perturbed_operations += r.attempts > 1;
    result.max_perturbation = std::max(result.max_perturbation, r.perturbation);
    result.curve_tolerance = std::max(result.curve_tolerance, r.curve_tolerance);
  };
  BooleanOptions quick; // the operands are made here, closed by construction
  quick.check_operands = false;
  auto unite = [&](TriangleMesh& all, const TriangleMesh& one) {
    if (all.empty()) {
      all = one;
      return;
    }
    const BooleanResult r = mesh_boolean(all, one, BooleanOp::Union, quick);
    note(r);
    all = r.mesh;
  };
  std::vector<std::vector<Index>> around = faces_around(shell, tubes, options);
  for (std::size_t i = 0; i < tubes.size(); ++i)
    result.tubes.push_back(place(tubes[i], shell, std::move(around[i]), options));
  for (const SlotSpec& slot : slots) result.slots.push_back(place_slot(slot, shell, options));
  std::vector<LaidLabel> labels;
  const LabelObstacles obstacles{tubes, result.tubes, slots, result.slots};
  for (const LabelSpec& label : parts.labels) {
    labels.push_back(lay_label(label, shell, inner_faces, obstacles, options));
    result.labels.push_back(labels.back().placement);
  }
  // The bone under all sleeves, for their feet: one pass over it.
  std::vector<Index> bone_near;
  {
    BoundingBox all;
    std::vector<BoundingBox> boxes;
    for (std::size_t i = 0; i < tubes.size(); ++i) {
      BoundingBox b;
      b.extend(tube_point(tubes[i], result.tubes[i].column_bottom - 1.0));
      b.extend(tube_point(tubes[i], result.tubes[i].sleeve_top + options.bore_margin));
      boxes.push_back(b.inflated(tubes[i].outer_radius + std::max(0.5, 0.2 * tubes[i].outer_radius)));
      all.extend(boxes.back());
    }
    for (std::size_t i = 0; i < slots.size(); ++i) {
      const SlotPlacement& p = result.slots[i];
      const SlotFrame f = slot_frame(slots[i]);
      BoundingBox b;
      for (const double a : {-1.0, 1.0})
        for (const double e : {p.housing_start, p.housing_end})
          for (const double z : {p.housing_bottom - 1.0, p.cut_top})
            b.extend(f.at(a * (0.5 * p.width + slots[i].wall), e, z));
      boxes.push_back(b.inflated(0.5));
      all.extend(boxes.back());
    }
    // The bone's faces whose boxes meet a part's, in the order of the bone's faces: from the whole
    // bone's tree when there is one, part by part (its boxes hold the faces' boxes, so it passes all
    // of them, and each is then tested as without it), else in one pass over every face.
    auto near_a_part = [&](Index f) {
      const BoundingBox fb = triangle_box(bone, f);
      return fb.overlaps(all) &&
             std::any_of(boxes.begin(), boxes.end(), [&](const BoundingBox& b) { return fb.overlaps(b); });
    };
    if (options.bone_tree) {
      for (const BoundingBox& b : boxes)
        options.bone_tree->for_each_in_box(b, [&](Index f) {
          if (triangle_box(bone, f).overlaps(b)) bone_near.push_back(f);
        });
      std::sort(bone_near.begin(), bone_near.end());
      bone_near.erase(std::unique(bone_near.begin(), bone_near.end()), bone_near.end());
    } else {
      for (Index f = 0; f < bone.face_count(); ++f)
        if (near_a_part(f)) bone_near.push_back(f);
    }
  }
  const AabbTree bone_tree(bone, std::move(bone_near));
  result.placement_seconds = seconds_since(t0);

  // Columns (each sleeve's outer cylinder from inside the template wall to the sleeve's top), united
  // with each other (neighbouring sleeves may overlap) and then with the shell, on its seat.
  TriangleMesh columns;
  for (std::size_t i = 0; i < tubes.size(); ++i) {
    const TubePlacement& p = result.tubes[i];
    if (p.sleeve_inside_template) continue;
    // The foot: at least foot_lift above the bone (plus clearance) everywhere under the sleeve.
    const Cylinder cylinder = tube_cylinder(tubes[i], tubes[i].outer_radius, p.column_bottom, p.sleeve_top);
    TriangleMesh column = footed_cylinder_mesh(cylinder, options.chordal_tolerance, [](const Vec3&) { return 0.0; });
    const Index ring = static_cast<Index>(circle_segments(tubes[i].outer_radius, options.chordal_tolerance));
    check_bore_line(tubes[i], p.sleeve_top, bone_tree); // first: bone in the bore is the reason to name
    if (seat_foot(column, column.vertex_count() - ring - 1, tubes[i], p.column_bottom, p.sleeve_top,
                  options.clearance + p.foot_lift, bone_tree))
      column = rounded(std::move(column));
    else {
      result.tubes[i].trimmed_by_bone = true;
      column =
          trimmed(rounded(std::move(column)), tubes[i], p.column_bottom, p.sleeve_top, options.clearance + p.foot_lift,
                  options.chordal_tolerance, bone_tree, result.perturbed_operations);
    }
    check_clear_of_bone(column, tubes[i], bone_tree);
    unite(columns, column);
  }
  std::vector<TriangleMesh> housings;
  for (std::size_t i = 0; i < slots.size(); ++i) {
    housings.push_back(slot_housing(slots[i], result.slots[i], bone_tree, options));
    unite(columns, housings.back());
  }
  for (const LaidLabel& label : labels)
    if (label.placement.mode == LabelMode::emboss)
      for (const TriangleMesh& solid : label.solids) unite(columns, solid);
  result.columns_seconds = seconds_since(t0) - result.placement_seconds;
  if (!columns.empty()) {
    BooleanOptions o = quick;
    o.check_result = options.check_booleans;
    o.seat.assign(shell.face_count(), 0);
    std::fill(o.seat.begin(), o.seat.begin() + static_cast<std::ptrdiff_t>(inner_faces), 1);
    BooleanResult merged = mesh_boolean(shell, columns, BooleanOp::Union, o);
    note(merged);
    result.mesh = std::move(merged.mesh);
    result.from_tube = std::move(merged.from_b);
    result.unchecked_part_dropped =
        drop_unjoined(result.mesh, result.from_tube, tubes, result.tubes) && !o.check_result;
  } else {
    result.mesh = shell; // the shell as it is, for the cuts
  }
  result.union_seconds = seconds_since(t0);
  result.columns = std::move(columns);

  // Bores along every whole axis, from above the sleeve to below the inner surface.
  const auto t1 = Clock::now();
  TriangleMesh bores;
  for (std::size_t i = 0; i < tubes.size(); ++i) {
    const TubePlacement& p = result.tubes[i];
    unite(bores, rounded(cylinder_mesh(tube_cylinder(tubes[i], tubes[i].inner_radius, p.bore_bottom, p.bore_top),
                                       options.chordal_tolerance, true)));
  }
  for (std::size_t i = 0; i < tubes.size(); ++i) {
    if (!tubes[i].counterbore) continue;
    TubePlacement& p = result.tubes[i];
    p.counterbore_bottom = p.sleeve_top - tubes[i].counterbore->depth;
    unite(bores, rounded(cylinder_mesh(
                     tube_cylinder(tubes[i], tubes[i].counterbore->radius, *p.counterbore_bottom, p.bore_top),
                     options.chordal_tolerance, true)));
  }
  for (std::size_t i = 0; i < slots.size(); ++i) unite(bores, slot_cut(slots[i], result.slots[i]));
  for (const LaidLabel& label : labels)
    if (label.placement.mode == LabelMode::engrave)
      for (const TriangleMesh& solid : label.solids) unite(bores, solid);
  note_near_paths(tubes, result.tubes);
  note_slot_meetings(tubes, slots, housings, options, result);
  if (!bores.empty()) {
    BooleanOptions o = quick;
    o.check_result = options.check_booleans;
    BooleanResult cut = mesh_boolean(result.mesh, bores, BooleanOp::Difference, o);
    note(cut);
    std::vector<std::uint8_t> from_tube(cut.mesh.face_count());
    for (Index f = 0; f < cut.mesh.face_count(); ++f)
      from_tube[f] = cut.from_b[f] ? 1 : result.from_tube[cut.source_face[f]];
    result.mesh = std::move(cut.mesh);
    result.from_tube = std::move(from_tube);
    result.fragments_dropped = drop_fragments(result.mesh, result.from_tube);
    result.unchecked_part_dropped |= result.fragments_dropped > 0 && !o.check_result;
  }
  result.bores = std::move(bores);
  result.bore_seconds = seconds_since(t1);
  result.seconds = seconds_since(t0);
  if (options.check_blade_paths) {
    const auto t2 = Clock::now();
    for (std::size_t i = 0; i < slots.size(); ++i) {
      result.blade_paths.push_back(check_blade_path(result.mesh, slots[i], result.slots[i]));
      if (const auto& at = result.blade_paths.back().blocked; at && !std::getenv("ST_DEBUG_SLOTS"))
        throw GeometryError("slot '" + slots[i].name + "': guide material is left in the blade's path near " +
                            detail::where(*at));
    }
    result.blade_path_seconds = seconds_since(t2);
  }
  return result;
}

} // namespace st
