#include "st/design/blockout.h"

#include "st/core/polygon_fill.h"
#include "st/core/errors.h"
#include "st/core/predicates.h"
#include "st/core/topology.h"
#include "st/design/ruled_surface.h"
#include "st/validate/removal.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

namespace st {

namespace {

/// How many rings of faces a zone whose fill is blocked may grow by.
constexpr int kGrowthRings = 6;

/// The border loops of a zone (faces with zone[f] == id): its half-edges whose opposite is not in the
/// zone, chained head to tail, the zone on their left. Nothing when a vertex starts two of them.
std::optional<std::vector<std::vector<Index>>> zone_loops(const TriangleMesh& region,
                                                          const std::vector<Index>& opposite,
                                                          const std::vector<Index>& faces,
                                                          const std::vector<std::int32_t>& zone, std::int32_t id) {
  std::unordered_map<Index, Index> next; // from vertex -> to vertex
  for (Index f : faces)
    for (int k = 0; k < 3; ++k) {
      const Index h = 3 * f + static_cast<Index>(k);
      const Index o = opposite[h];
      if (o != kInvalidIndex && zone[face_of(o)] == id) continue;
      const Index from = region.triangles[f][k], to = region.triangles[f][(k + 1) % 3];
      if (!next.emplace(from, to).second) return std::nullopt; // the zone pinches at `from`
    }
  std::vector<std::vector<Index>> loops;
  std::unordered_set<Index> used;
  for (const auto& [start, ignored] : next) {
    if (used.count(start)) continue;
    std::vector<Index> loop;
    for (Index v = start; !used.count(v);) {
      used.insert(v);
      loop.push_back(v);
      const auto it = next.find(v);
      if (it == next.end()) return std::nullopt;
      v = it->second;
    }
    if (loop.size() < 3) return std::nullopt;
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// The ruled strip between a zone's outer border and its one hole (ruled_surface.h), in vertex indices.
std::optional<std::vector<Triangle>> ruled_fill(const TriangleMesh& region, const std::vector<Index>& outer,
                                                std::vector<Index> hole) {
  std::reverse(hole.begin(), hole.end());
  std::vector<Vec3> p, q;
  for (Index v : outer) p.push_back(region.positions[v]);
  for (Index v : hole) q.push_back(region.positions[v]);
  const auto m = static_cast<Index>(outer.size());
  const RuledResult strip = ruled_surface(p, q, 0, m);
  std::vector<Triangle> out;
  for (const Triangle& t : strip.triangles) {
    Triangle u{};
    for (int k = 0; k < 3; ++k) u[k] = t[k] < m ? outer[t[k]] : hole[t[k] - m];
    out.push_back(u);
  }
  return out;
}

double signed_volume(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (a - o).dot((b - o).cross(c - o)) / 6.0;
}

} // namespace

BlockOutResult block_out(const SweepTest& sweep, const TriangleMesh& region, const std::vector<float>& sampled,
                         const Vec3& direction, double reach) {
  BlockOutResult out;
  const Index nf = region.face_count();
  // Hidden faces: those the sampling saw hidden, and every face whose raised prism along -d meets the
  // bone (exact: a face partly in the shadow of a bulge, its samples all in the light, is found).
  const RemovalReport swept = sweep(region, direction, reach, SweepStart::raised);
  std::vector<float> hidden(nf, 0.0f);
  for (Index f = 0; f < nf; ++f)
    hidden[f] = (f < sampled.size() && sampled[f] > 0.0f) || swept.blocked_faces[f] ? 1.0f : 0.0f;
  // The plane across d, oriented so that faces turned towards the guide (n . d < 0) run
  // counter-clockwise in it: u x v = -d.
  const Vec3 d = direction.normalized();
  const Vec3 u = d.cross(std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
  const Vec3 v = (-d).cross(u);
  std::vector<Point2> plane(region.vertex_count());
  for (Index i = 0; i < region.vertex_count(); ++i) plane[i] = {region.positions[i].dot(u), region.positions[i].dot(v)};

  const MeshTopology topology(region);
  const std::vector<Index> opposite = topology.all_opposites();
  // Zones: hidden faces joined across manifold edges.
  std::vector<std::int32_t> zone(nf, -1);
  std::vector<std::vector<Index>> zone_faces;
  for (Index f = 0; f < nf; ++f) {
    if (!(hidden[f] > 0.0f) || zone[f] >= 0) continue;
    const auto id = static_cast<std::int32_t>(zone_faces.size());
    std::vector<Index> faces{f};
    zone[f] = id;
    for (std::size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const Index o = opposite[3 * faces[i] + static_cast<Index>(k)];
        if (o == kInvalidIndex) continue;
        const Index g = face_of(o);
        if (zone[g] < 0 && hidden[g] > 0.0f) {
          zone[g] = id;
          faces.push_back(g);
        }
      }
    zone_faces.push_back(std::move(faces));
  }
  out.zones = zone_faces.size();

  std::vector<std::uint8_t> replaced(nf, 0);
  std::vector<Triangle> fills;
  std::vector<std::size_t> trimmed_zones;
  auto at_rim = [&](const std::vector<Index>& faces) {
    return std::any_of(faces.begin(), faces.end(), [&](Index f) {
      for (int k = 0; k < 3; ++k)
        if (opposite[3 * f + static_cast<Index>(k)] == kInvalidIndex) return true;
      return false;
    });
  };
  // Grows zone z by the faces around its vertices; a zone not yet handled that it meets joins it.
  auto grow = [&](std::size_t z) {
    const auto id = static_cast<std::int32_t>(z);
    std::vector<Index> added;
    for (Index f : zone_faces[z])
      for (Index vtx : region.triangles[f])
        for (Index g : topology.faces_of(vtx)) {
          if (zone[g] == id || replaced[g]) continue;
          if (zone[g] >= 0 && zone[g] < id) return false; // a zone already filled or trimmed
          if (zone[g] > id) {
            std::vector<Index>& other = zone_faces[static_cast<std::size_t>(zone[g])];
            for (Index h : other) {
              zone[h] = id;
              added.push_back(h);
            }
            other.clear();
            continue;
          }
          zone[g] = id;
          added.push_back(g);
        }
    zone_faces[z].insert(zone_faces[z].end(), added.begin(), added.end());
    return !added.empty();
  };
  // The zone's fill, or nothing (see blockout.h).
  auto fill = [&](std::size_t z) -> std::optional<std::vector<Triangle>> {
    const std::vector<Index>& faces = zone_faces[z];
    auto loops = zone_loops(region, opposite, faces, zone, static_cast<std::int32_t>(z));
    if (!loops) return std::nullopt;
    // One loop turning counter-clockwise across d (the outer border), the others clockwise (holes).
    std::size_t outer = loops->size();
    for (std::size_t k = 0; k < loops->size(); ++k)
      if (loop_area2(plane, (*loops)[k]) > 0.0) {
        if (outer != loops->size()) return std::nullopt;
        outer = k;
      }
    if (outer == loops->size()) return std::nullopt;
    std::swap((*loops)[0], (*loops)[outer]);
    auto triangles = fill_polygon(plane, *loops);
    // A ring whose two borders lie over each other seen along d (a silhouette exactly above the
    // first visible ring beyond it) has no area to clip: the fill is the ruled wall between them,
    // the outer border forwards and the inner one reversed, so both run as the zone ran.
    if (!triangles && loops->size() == 2) triangles = ruled_fill(region, (*loops)[0], (*loops)[1]);
    if (!triangles) return std::nullopt;
    // No fill face may turn away from the guide (the guide behind it could not come off): each runs
    // counter-clockwise seen along d, or is a wall along d (exact orient2d).
    for (const auto& t : *triangles)
      if (orient2d(plane[t[0]].data(), plane[t[1]].data(), plane[t[2]].data()) < 0) return std::nullopt;
    // A fill edge inside the hole that a face outside the zone already uses would be used four times.
    for (const auto& t : *triangles)
      for (int k = 0; k < 3; ++k) {
        const Index a = t[k], b = t[(k + 1) % 3];
        bool in_zone = false, outside = false;
        for (Index g : topology.faces_of(a)) {
          const Triangle& tg = region.triangles[g];
          if (tg[0] != b && tg[1] != b && tg[2] != b) continue;
          if (zone[g] == static_cast<std::int32_t>(z)) in_zone = true;
          else if (!replaced[g]) outside = true;
        }
        if (outside && !in_zone) return std::nullopt;
      }
    // The fill itself must be free to come off: no bone above it within the reach.
    std::vector<Index> all(triangles->size());
    std::iota(all.begin(), all.end(), Index{0});
    const TriangleMesh piece = submesh(TriangleMesh{region.positions, *triangles}, all);
    if (!sweep(piece, d, reach, SweepStart::raised).removable) return std::nullopt;
    return triangles;
  };

  for (std::size_t z = 0; z < zone_faces.size(); ++z) {
    if (zone_faces[z].empty()) continue; // joined another zone
    const Vec3 somewhere = region.positions[region.triangles[zone_faces[z].front()][0]];
    std::optional<std::vector<Triangle>> triangles;
    bool trimmed = false;
    // A fill that is blocked (bone rises above the straight fill between the zone's borders) is
    // tried again over a zone grown by a ring of faces, up to kGrowthRings times.
    for (int ring = 0; ring <= kGrowthRings; ++ring) {
      if (ring > 0 && !grow(z)) break;
      // A zone that reaches the rim: the rim cannot stay under the overhang; the zone is cut off
      // and the rim follows its edge on the visible side (checked below to leave one border loop).
      if (at_rim(zone_faces[z])) {
        trimmed = true;
        break;
      }
      if ((triangles = fill(z))) break;
    }
    const std::vector<Index>& faces = zone_faces[z];
    if (trimmed) {
      trimmed_zones.push_back(z);
      for (Index f : faces) replaced[f] = 1;
      continue;
    }
    if (!triangles) {
      out.unfilled.push_back(somewhere);
      continue;
    }
    ++out.filled_zones;
    out.removed_faces += faces.size();
    double volume = 0.0;
    for (const Triangle& t : *triangles) {
      fills.push_back(t);
      volume += signed_volume(somewhere, region.positions[t[0]], region.positions[t[1]], region.positions[t[2]]);
    }
    for (Index f : faces) {
      replaced[f] = 1;
      const Triangle& t = region.triangles[f];
      volume -= signed_volume(somewhere, region.positions[t[0]], region.positions[t[1]], region.positions[t[2]]);
    }
    out.volume_mm3 += volume;
  }
  auto assemble = [&] {
    out.triangles.clear();
    for (Index f = 0; f < nf; ++f)
      if (!replaced[f]) out.triangles.push_back(region.triangles[f]);
    out.filled.assign(out.triangles.size(), 0);
    out.triangles.insert(out.triangles.end(), fills.begin(), fills.end());
    out.filled.resize(out.triangles.size(), 1);
  };
  assemble();
  // Each zone cut off must leave the region one simple border loop; one that would not (it splits
  // off a piece, or pinches the border) stays as it was. Largest zones first.
  std::sort(trimmed_zones.begin(), trimmed_zones.end(),
            [&](std::size_t a, std::size_t b) { return zone_faces[a].size() > zone_faces[b].size(); });
  for (std::size_t z : trimmed_zones)
    for (Index f : zone_faces[z]) replaced[f] = 0;
  for (std::size_t z : trimmed_zones) {
    for (Index f : zone_faces[z]) replaced[f] = 1;
    assemble();
    TriangleMesh trimmed{region.positions, out.triangles};
    bool one_loop = false;
    try {
      one_loop = border_loops(trimmed, MeshTopology(trimmed).all_opposites()).size() == 1;
    } catch (const GeometryError&) {
    }
    if (!one_loop) {
      for (Index f : zone_faces[z]) replaced[f] = 0;
      out.unfilled.push_back(region.positions[region.triangles[zone_faces[z].front()][0]]);
      continue;
    }
    ++out.trimmed_zones;
    out.rim_changed = true;
    for (Index f : zone_faces[z]) out.trimmed_area_mm2 += 0.5 * triangle_normal(region, f).norm();
  }
  assemble();
  return out;
}

} // namespace st
