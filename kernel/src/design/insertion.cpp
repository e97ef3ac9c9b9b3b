#include "st/design/insertion.h"

#include "design/insertion_samples.h"
#include "detail/cell_set.h"
#include "detail/parallel.h"
#include "st/boolean/triangle_intersection.h"
#include "st/core/errors.h"
#include "st/core/predicates.h"
#include "st/core/ray_triangle.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace st::insertion_detail {

namespace {

/// Columns along -d over the bone's faces the region's segments can meet: those in the prism they sweep,
/// in the columns' frame (u, v across the way, w along it) the region's extent across it and from its
/// nearest point to its farthest plus the reach along it, grown by four lifts (a segment starts a lift or
/// two off its sample, and the frame's dot products round far below that). An oblique way's prism is a
/// small part of its axis-aligned box. None when there are more than `most` of them (the region's own faces
/// among them), the faces a segment reads in the tree costing less than listing them all.
std::optional<validate_detail::SweepColumns> columns_along(const Sight& sight, const TriangleMesh& region,
                                                           const Vec3& d, std::size_t most) {
  if (region.face_count() > most) return std::nullopt;
  std::optional<validate_detail::SweepColumns> columns(std::in_place, -d);
  validate_detail::FrameBox prism;
  for (const Vec3& p : region.positions) {
    const Vec3 x = columns->frame(p);
    prism.lo = prism.lo.cwiseMin(x);
    prism.hi = prism.hi.cwiseMax(x);
  }
  prism.hi[2] += sight.reach;
  prism.lo -= Vec3::Constant(4.0 * sight.lift);
  prism.hi += Vec3::Constant(4.0 * sight.lift);
  const BoundingBox box = bounding_box(region);
  BoundingBox swept = box;
  swept.extend(box.min - sight.reach * d);
  swept.extend(box.max - sight.reach * d);
  const TriangleMesh& bone = sight.bone.mesh();
  std::vector<Index> faces;
  sight.bone.for_each_in_box(swept.inflated(4.0 * sight.lift), [&](Index f) {
    const validate_detail::FrameBox b = columns->box_of(bone, f);
    if ((b.lo.array() <= prism.hi.array()).all() && (b.hi.array() >= prism.lo.array()).all()) faces.push_back(f);
  });
  if (faces.size() > most) return std::nullopt;
  columns->build(bone, &faces, sight.lift);
  return columns;
}

/// Hidden area of the samples along d, and per sample whether it is hidden. Given a bound (and no
/// flags), infinity as soon as the area hidden so far is over it: a direction that cannot be better
/// is left at that. (Over by more than the sums' rounding, 1e-9 of it: the whole sum is then over the
/// bound too, so a caller comparing the area with the bound decides as it would on the whole sum.) The
/// chunks on all threads, or in order on the caller's.
double hidden_area(const Sight& sight, const TriangleMesh& region, const std::vector<Sample>& samples, const Vec3& d,
                   std::vector<std::uint8_t>* flags, double bound = std::numeric_limits<double>::infinity(),
                   bool on_threads = true) {
  constexpr std::size_t kGrain = 256;
  std::vector<double> chunk_area((samples.size() + kGrain - 1) / kGrain, 0.0);
  if (flags) flags->assign(samples.size(), 0);
  const bool bounded = !flags && bound < std::numeric_limits<double>::infinity();
  const double stop = bound * (1.0 + 1e-9);
  std::atomic<double> done{0.0}; // the area hidden in the chunks finished, in any order
  std::atomic<bool> over{false};
  auto chunk = [&](std::size_t, std::size_t begin, std::size_t end) {
    if (over.load(std::memory_order_relaxed)) return;
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      const Sample& s = samples[i];
      const Triangle& t = region.triangles[s.face];
      if (!is_hidden(sight, s.point, region.positions[t[0]], region.positions[t[1]], region.positions[t[2]], d))
        continue;
      sum += s.area;
      if (flags) (*flags)[i] = 1;
      if (bounded && done.load(std::memory_order_relaxed) + sum > stop) {
        over.store(true, std::memory_order_relaxed);
        return;
      }
    }
    chunk_area[begin / kGrain] = sum;
    if (bounded) done.fetch_add(sum, std::memory_order_relaxed);
  };
  if (on_threads) detail::parallel_for(samples.size(), kGrain, chunk);
  else
    for (std::size_t begin = 0; begin < samples.size(); begin += kGrain)
      chunk(0, begin, std::min(samples.size(), begin + kGrain));
  if (over.load()) return std::numeric_limits<double>::infinity();
  double total = 0.0;
  for (double a : chunk_area) total += a; // in chunk order: the same for any thread count
  return total;
}

} // namespace

Sight sight_of(const AabbTree& bone, double reach) {
  const double size = bounding_box(bone.mesh()).diagonal() + 1.0;
  return {bone, std::min(reach, 2.0 * size), 1e-9 * size};
}

/// Whether the guide, moving along d, cannot reach `p` on region face f (corners a, b, c), against
/// the bone: f faces away from it (exactly: orient3d of a, b, c and a + d), or a bone face meets the
/// segment from p back along -d (exact test, after a floating filter). The segment starts `lift`
/// (a nanometre-scale length) off p, so that the bone face p lies on, to rounding, does not count.
bool is_hidden(const Sight& sight, const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double reach = sight.reach, lift = sight.lift;
  // orient3d(a, b, c, a + d) < 0 when a + d lies on the side the normal points to, i.e. n . d > 0:
  // the face looks away from the guide coming along d.
  const int side = orient3d(a, b, c, a + d);
  if (side < 0) return true;
  const Vec3 back = -d;
  Vec3 p0 = p + lift * back;
  // A wall parallel to d: the segment runs a lift off it, on its outer side, so that it passes beside
  // the wall's own edges and meets only bone that overhangs the wall (see insertion.h).
  if (side == 0) p0 += lift * (b - a).cross(c - a).normalized();
  const Vec3 q = p0 + reach * back;
  const TriangleMesh& mesh = sight.bone.mesh();
  auto meets = [&](Index g) {
    const Triangle& t = mesh.triangles[g];
    const Vec3 &ga = mesh.positions[t[0]], &gb = mesh.positions[t[1]], &gc = mesh.positions[t[2]];
    const auto hit = ray_triangle(p0, back, ga, gb, gc, 1e-6);
    if (!hit || hit->t < -lift || hit->t > reach + lift) return false;
    return segment_intersects_triangle(p0, q, ga, gb, gc);
  };
  if (sight.columns) {
    const Vec3 at = sight.columns->frame(p0);
    return sight.columns->any_along(at[0], at[1], at[2], at[2] + reach, meets);
  }
  return sight.bone.any_along(p0, back, reach, lift, meets);
}

/// A face is split into k x k with k = ceil(longest edge / (this * spacing)): a face of one sample's
/// share of the area (spacing^2 / 2; equilateral, its edges 1.07 spacings) gets one sample, one of four
/// shares four.
constexpr double kEdgesPerSpacing = 1.5;

std::vector<Sample> samples_of(const TriangleMesh& region, double spacing, std::size_t stride) {
  std::vector<Sample> out;
  for (Index f = 0; f < region.face_count(); f += static_cast<Index>(stride)) {
    const Triangle& t = region.triangles[f];
    const Vec3 &a = region.positions[t[0]], &b = region.positions[t[1]], &c = region.positions[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm() * static_cast<double>(stride);
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int k =
        spacing > 0.0 ? std::clamp(static_cast<int>(std::ceil(longest / (kEdgesPerSpacing * spacing))), 1, 64) : 1;
    const double w = area / (k * k);
    const Vec3 u = (b - a) / k, v = (c - a) / k;
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j) {
        out.push_back({a + (i + 1.0 / 3.0) * u + (j + 1.0 / 3.0) * v, f, w});
        if (i + j + 2 <= k) out.push_back({a + (i + 2.0 / 3.0) * u + (j + 2.0 / 3.0) * v, f, w});
      }
  }
  return out;
}

std::vector<double> hidden_areas(const Sight& sight, const TriangleMesh& region, const std::vector<Sample>& samples,
                                 const std::vector<Vec3>& ds, double bound) {
  const std::size_t most = 4 * samples.size();
  auto one = [&](const Vec3& d, bool on_threads) {
    const std::optional<validate_detail::SweepColumns> columns = columns_along(sight, region, d, most);
    Sight along = sight;
    if (columns) along.columns = &*columns;
    return hidden_area(along, region, samples, d, nullptr, bound, on_threads);
  };
  std::vector<double> areas(ds.size());
  if (ds.size() == 1) areas[0] = one(ds[0], true);
  else
    detail::parallel_for(ds.size(), 1, [&](std::size_t, std::size_t i, std::size_t) { areas[i] = one(ds[i], false); });
  return areas;
}

} // namespace st::insertion_detail

namespace st {

using namespace insertion_detail;

namespace {

Vec3 checked_direction(const Vec3& d) {
  const double n = d.norm();
  if (!std::isfinite(n) || !(n > 0.0)) throw InvalidInput("insertion direction: must be a non-zero vector");
  return d / n;
}

/// A unit vector perpendicular to the unit vector d.
Vec3 perpendicular(const Vec3& d) {
  const Vec3 other = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return d.cross(other).normalized();
}

/// d turned by `angle` (radians) towards the unit vector `towards` perpendicular to it.
Vec3 tilted(const Vec3& d, const Vec3& towards, double angle) {
  return (std::cos(angle) * d + std::sin(angle) * towards).normalized();
}

} // namespace

Undercut undercut(const AabbTree& bone, const TriangleMesh& region, const Vec3& direction, double spacing,
                  double reach) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) throw InvalidInput("undercut: the sample spacing must be > 0 mm");
  if (!(reach > 0.0)) throw InvalidInput("undercut: the reach must be > 0 mm");
  Undercut u;
  u.direction = checked_direction(direction);
  u.area_mm2 = surface_area(region);
  const Index nf = region.face_count();
  Sight sight = sight_of(bone, reach);
  // Faces much smaller than a sample's share of the area: every stride-th face is sampled.
  const double per_sample = 0.5 * spacing * spacing;
  const auto stride = nf > 0 ? std::max<std::size_t>(1, static_cast<std::size_t>(per_sample * nf / u.area_mm2)) : 1;
  const std::vector<Sample> samples = samples_of(region, spacing, stride);
  // The same hidden samples whichever filter reads the bone (the exact test decides): columns when
  // the bone the segments can meet is not much larger than the samples.
  const std::size_t most = 2 * samples.size();
  const std::optional<validate_detail::SweepColumns> columns = columns_along(sight, region, u.direction, most);
  if (columns) sight.columns = &*columns;
  std::vector<std::uint8_t> flags;
  hidden_area(sight, region, samples, u.direction, &flags);
  std::vector<double> hidden(nf, 0.0), total(nf, 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    total[samples[i].face] += samples[i].area;
    if (flags[i]) hidden[samples[i].face] += samples[i].area;
  }
  std::vector<double> fraction(nf, 0.0); // of each face's area hidden
  for (Index f = 0; f < nf; ++f)
    if (total[f] > 0.0) fraction[f] = hidden[f] / total[f];
  if (stride > 1) {
    // The faces between samples: one turned away from the guide is hidden; one within two spacings of
    // a hidden sample is tested at its centre (so a hidden zone's border is found face by face); the
    // others lie among visible samples and count as seen.
    detail::CellSet near_hidden(2.0 * spacing);
    for (std::size_t i = 0; i < samples.size(); ++i)
      if (flags[i]) near_hidden.mark_around(samples[i].point);
    detail::parallel_for(nf, 1024, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f) {
        if (total[f] > 0.0) continue;
        const Triangle& t = region.triangles[f];
        const Vec3 &a = region.positions[t[0]], &b = region.positions[t[1]], &c = region.positions[t[2]];
        const Vec3 centre = (a + b + c) / 3.0;
        if (orient3d(a, b, c, a + u.direction) < 0 ||
            (near_hidden.contains(centre) && is_hidden(sight, centre, a, b, c, u.direction)))
          fraction[f] = 1.0;
      }
    });
  }
  u.hidden.resize(nf);
  for (Index f = 0; f < nf; ++f) {
    u.hidden[f] = static_cast<float>(fraction[f]);
    if (fraction[f] > 0.0) u.hidden_mm2 += 0.5 * triangle_normal(region, f).norm() * fraction[f];
  }
  return u;
}

Vec3 least_undercut_direction(const AabbTree& bone, const TriangleMesh& region, const std::optional<Vec3>& start,
                              double reach) {
  Vec3 m;
  if (start) {
    m = checked_direction(*start);
  } else {
    Vec3 mean = Vec3::Zero();
    for (Index f = 0; f < region.face_count(); ++f) mean += triangle_normal(region, f);
    if (!(mean.norm() > 0.0)) throw GeometryError("insertion direction: the region has no mean normal");
    m = -mean.normalized(); // the guide moves against the bone's outward normal
  }
  // Samples: face centres of about 4000 faces.
  const std::size_t stride = std::max<std::size_t>(1, region.face_count() / 4000);
  const std::vector<Sample> samples = samples_of(region, 0.0, stride);
  const Sight sight = sight_of(bone, reach);
  struct Best {
    Vec3 d;
    double hidden;
    double angle; // from m
  } best{m, hidden_areas(sight, region, samples, {m}, std::numeric_limits<double>::infinity())[0], 0.0};
  // Directions in turn, each taking the best place when its hidden area is smaller, or as small and
  // nearer the start; each group's areas found at once, beside each other, with the best area before
  // the group as their bound: one over it is over the best met in turn too, and left as before.
  auto consider = [&](const std::vector<Vec3>& group) {
    std::vector<Vec3> ds;
    std::vector<double> angles;
    for (const Vec3& d : group) {
      const double angle = std::acos(std::clamp(d.dot(m), -1.0, 1.0));
      if (angle > std::numbers::pi / 3.0 + 1e-12) continue;
      ds.push_back(d);
      angles.push_back(angle);
    }
    const std::vector<double> hidden = hidden_areas(sight, region, samples, ds, best.hidden);
    bool moved = false;
    for (std::size_t i = 0; i < ds.size(); ++i)
      if (hidden[i] < best.hidden || (hidden[i] == best.hidden && angles[i] < best.angle)) {
        best = {ds[i], hidden[i], angles[i]};
        moved = true;
      }
    return moved;
  };
  // Nothing hidden: no direction does better, and none is nearer the start.
  if (best.hidden == 0.0) return m;
  const Vec3 u = perpendicular(m), v = m.cross(u);
  constexpr double kDegree = std::numbers::pi / 180.0;
  for (int ring = 1; ring <= 8 && best.hidden > 0.0; ++ring) { // a ring farther out cannot beat a zero
    std::vector<Vec3> group;
    for (int k = 0; k < 12; ++k) {
      const double around = k * 30.0 * kDegree;
      group.push_back(tilted(m, std::cos(around) * u + std::sin(around) * v, ring * 7.5 * kDegree));
    }
    consider(group);
  }
  for (double step = 3.75 * kDegree; step > 0.1 * kDegree; step *= 0.5)
    for (int round = 0; round < 8; ++round) {
      const Vec3 centre = best.d, a = perpendicular(centre), b = centre.cross(a);
      std::vector<Vec3> group;
      for (int k = 0; k < 8; ++k) {
        const double around = k * 45.0 * kDegree;
        group.push_back(tilted(centre, std::cos(around) * a + std::sin(around) * b, step));
      }
      if (!consider(group)) break;
    }
  return best.d;
}

} // namespace st
